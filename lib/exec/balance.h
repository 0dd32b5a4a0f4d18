#pragma once

namespace cdb {

// How much work per index varies: traversals are uneven, so the host executor hands out
// small chunks for them; the CUDA executor ignores the hint.
enum class Balance { even, uneven };

// Whether a functor that asks for resident blocks (F::kMinBlocksPerSm, exec/tuning.h) is
// launched under that bound (bounded) or not (plain); the host executor ignores it.
enum class Occupancy { plain, bounded };

}  // namespace cdb
