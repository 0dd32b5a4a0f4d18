#pragma once

namespace cdb {

// How much work per index varies: traversals are uneven, so the host executor hands out
// small chunks for them; the CUDA executor ignores the hint.
enum class Balance { even, uneven };

}  // namespace cdb
