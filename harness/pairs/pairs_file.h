#pragma once
// Pairs files: one frame's pairs of triangles as any program can write them, text or
// binary (.bin; docs/extending.md "The pairs file format"), so `cdbench verify --pairs DIR`
// can check an outside method against the oracle and `verify --write-pairs DIR` can show
// what a correct file holds. A pair listed twice, in either order, is a duplicate.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "cdbench/core/pair.h"

namespace cdb {

enum class PairsFormat { text, binary };

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

// Writes `pairs` in the format its name gives; a text file starts with the `comment`
// lines, each behind "# ". Throws cdb::Error naming the file when it cannot.
void write_pairs_file(const std::filesystem::path& file, const std::vector<PrimPair>& pairs,
                      const std::vector<std::string>& comment = {});

// The file of each frame of [first, last) in `dir`: frame_N.EXT is frame N (files of other
// frames left alone), else the directory's files in natural order are the frames in order,
// one each. Throws cdb::Error naming the directory and the frame when they do not match.
std::vector<std::filesystem::path> pairs_files_for_frames(const std::filesystem::path& dir, uint32_t first,
                                                          uint32_t last);

}  // namespace cdb
