#pragma once
// Pairs files: one frame's pairs of triangles as any program can write them, so `cdbench
// verify --pairs DIR` can check an outside method against the oracle and `verify
// --write-pairs DIR` can show what a correct file holds (docs/extending.md "Checking an
// outside method").
//
// Text (any name not ending in .bin): one pair a line, two 0-based triangle indices (the
// order of the scene's faces) separated by spaces, tabs or a comma; blank lines and lines
// starting with # are skipped. Binary (.bin): the pairs back to back, each two
// little-endian uint32, no header. Either way a pair's two indices may come in either
// order, the pairs in any order; a pair listed twice (in either order) is a duplicate.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/pair.h"

namespace cdb {

enum class PairsFormat { text, binary };

// By the file's extension: .bin is binary, anything else text.
PairsFormat pairs_format_of(const std::filesystem::path& file);

// frame_0007.txt or frame_0007.bin: the name verify --write-pairs gives frame 7.
std::string pairs_file_name(uint32_t frame, PairsFormat format);

struct PairsRead {
  std::vector<PrimPair> pairs;  // a < b, sorted by pair_key, each once
  uint64_t listed = 0;          // pairs the file lists, duplicates included
  uint64_t duplicates = 0;      // listings past a pair's first
  std::vector<PrimPair> first_duplicates;  // the first few, a < b
};

// Throws cdb::Error naming the file and its line (text) or pair and byte (binary) for an
// entry that is not two indices, an index not below num_faces, or a triangle paired with
// itself; and for a file that cannot be read.
PairsRead read_pairs_file(const std::filesystem::path& file, uint32_t num_faces, size_t keep = 8);

// Writes `pairs` in the file's format (pairs_format_of); a text file starts with the
// `comment` lines, each behind "# ". Throws cdb::Error naming the file when it cannot.
void write_pairs_file(const std::filesystem::path& file, const std::vector<PrimPair>& pairs,
                      const std::vector<std::string>& comment = {});

// The file of each frame of [first, last) in `dir`. Files named frame_N.EXT (N decimal,
// any zero padding) are matched by N, and those of frames outside the range are left
// alone; otherwise every file of the directory (hidden ones aside) is taken in natural
// order (io/natural_order.h), the k-th for frame first + k, and there must be exactly one
// a frame. Throws cdb::Error naming the directory and the frame when they do not match.
std::vector<std::filesystem::path> pairs_files_for_frames(const std::filesystem::path& dir, uint32_t first,
                                                          uint32_t last);

}  // namespace cdb
