#pragma once
// The header of a NumPy .npy file (format versions 1.0, 2.0 and 3.0): magic, version, header
// length, and the Python-literal dict {'descr': ..., 'fortran_order': ..., 'shape': (...)}.
// Parsed here rather than through a library: the format is small and fixed, and a reader of
// per-frame boxes (io/box_stream.h) needs only the dtype, order, shape and where data starts.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace cdb {

struct NpyHeader {
  std::string descr;             // the dtype as written, e.g. "<f4"
  bool fortran_order = false;
  std::vector<uint64_t> shape;   // () for a scalar
  size_t data_offset = 0;        // bytes before the array's data
};

// `bytes` is the file's start (at least the whole header). Throws cdb::Error prefixed by
// `where` on a bad magic, an unknown version, a truncated header or a malformed dict.
NpyHeader parse_npy_header(std::string_view bytes, const std::string& where);

// "(3, 2, 3)", "(4,)", "()": the shape as NumPy prints it, for messages.
std::string shape_text(const std::vector<uint64_t>& shape);

}  // namespace cdb
