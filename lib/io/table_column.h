#pragma once
// A column of a results file's tables (/frames, /plans): one extendible dataset per
// column, a row appended at a time, each value read from the row by `value`.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <variant>

namespace cdb {

enum class ColumnType { u32, u64, f64, text };

// Text columns are fixed-width (so they compress like the others); a longer value is an
// error, never cut short.
inline constexpr size_t kTextColumnBytes = 64;

using ColumnValue = std::variant<uint64_t, double, std::string>;

template <class Row>
struct TableColumn {
  std::string name;
  ColumnType type;
  std::string description;  // stored with the dataset
  std::function<ColumnValue(const Row&)> value;
};

}  // namespace cdb
