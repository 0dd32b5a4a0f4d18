#pragma once
#include <array>
#include <cstddef>

namespace cdb {

// The timed phases of a frame. Each pipeline times the ones it runs; the rest read 0.
enum class Phase : int {
  upload, boxes, build, order, refit, query, generate, preserve, update, balance, front_order,
  restructure, inspect, count
};

inline constexpr size_t kPhaseCount = static_cast<size_t>(Phase::count);

inline constexpr std::array<const char*, kPhaseCount> kPhaseNames = {
    "upload", "boxes", "build", "order", "refit", "query",
    "generate", "preserve", "update", "balance", "front_order",
    "restructure", "inspect"};

}  // namespace cdb
