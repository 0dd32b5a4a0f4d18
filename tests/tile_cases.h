#pragma once
// Exec::for_each_tile over an explicit tiling (exec/tiles.h), on host and CUDA: tiles of one
// index up to F::kTile, fewer blocks than tiles (a block takes several in turn), and no
// tiles. Every index runs once, with its own tile's bounds and a shared state that f.init
// prepared for that tile.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "cdbench/core/hd.h"
#include "cdbench/exec/memory.h"
#include "cdbench/exec/tiles.h"

struct RecordTileFn {
  static constexpr uint32_t kTile = 512;
  struct Shared {
    uint32_t mark[kTile];
  };
  uint32_t* first_of;
  uint32_t* last_of;
  uint32_t* runs;  // per index: runs so far, each adding the lane's init mark
  CDB_HD void init(Shared& s, uint32_t lane) const { s.mark[lane] = lane + 1; }
  CDB_HD void operator()(uint32_t i, uint32_t first, uint32_t last, Shared& s) const {
    first_of[i] = first;
    last_of[i] = last;
    runs[i] += s.mark[i - first];
    s.mark[i - first] = 0;  // a tile that reused the state without init would see 0
  }
};

template <class Exec>
void check_for_each_tile() {
  const std::vector<uint32_t> sizes = {1, 512, 7, 300, 1, 1, 511, 2, 64, 512, 5};
  std::vector<uint32_t> first = {0};
  for (int round = 0; round < 4; ++round)
    for (uint32_t s : sizes) first.push_back(first.back() + s);
  const uint32_t n = first.back(), tiles = uint32_t(first.size() - 1);
  for (uint32_t count : {0u, tiles})
    for (uint32_t blocks : {1u, 3u, tiles, 4 * tiles}) {
      Exec exec;
      cdb::Array<uint32_t> d_first, d_count, first_of, last_of, runs;
      for (auto* a : {&d_first, &d_count, &first_of, &last_of, &runs}) a->bind(exec.memory(), "tiles");
      d_first.reserve(first.size());
      d_count.reserve(1);
      for (auto* a : {&first_of, &last_of, &runs}) a->reserve(n);
      exec.copy_from_host(d_first.data(), first.data(), first.size());
      exec.copy_from_host(d_count.data(), &count, 1);
      exec.fill(runs.data(), n, 0u);
      exec.for_each_tile(cdb::Tiles{d_first.data(), d_count.data(), blocks},
                         RecordTileFn{first_of.data(), last_of.data(), runs.data()});
      std::vector<uint32_t> got_first(n), got_last(n), got_runs(n);
      exec.copy_to_host(got_first.data(), first_of.data(), n);
      exec.copy_to_host(got_last.data(), last_of.data(), n);
      exec.copy_to_host(got_runs.data(), runs.data(), n);
      for (uint32_t t = 0; t < tiles; ++t)
        for (uint32_t i = first[t]; i < first[t + 1]; ++i) {
          const std::string where = "blocks " + std::to_string(blocks) + ", tiles " + std::to_string(count) +
                                    ", tile " + std::to_string(t) + ", index " + std::to_string(i);
          if (count == 0) {
            ASSERT_EQ(got_runs[i], 0u) << where;
            continue;
          }
          ASSERT_EQ(got_runs[i], i - first[t] + 1) << where;
          ASSERT_EQ(got_first[i], first[t]) << where;
          ASSERT_EQ(got_last[i], first[t + 1] - 1) << where;
        }
    }
}
