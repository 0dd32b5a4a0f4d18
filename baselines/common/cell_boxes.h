#pragma once
// What the cell baselines (grid and hash) keep per box, and the steps they share on it:
// the face boxes (face_boxes.h), the scene statistics (scene_stats.h) and, per box, the
// count of its cell entries and the offset of its first one. Each baseline's workspace
// derives from this and adds its cells, entries and sort.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "baselines/common/face_boxes.h"
#include "baselines/common/scene_stats.h"
#include "cdbench/exec/memory.h"

namespace cdb {

template <class Exec>
struct CellBoxes : FaceBoxes {
  // Buffers are named "<prefix>.<array>" in the growth log.
  CellBoxes(Exec& exec, const std::string& prefix) : FaceBoxes(exec.memory(), prefix) {
    bind_arrays(exec.memory(), prefix + ".",
                {{&counts, "counts"}, {&offsets, "offsets"}, {&scene, "scene"}, {&temp, "temp"}});
  }

  void reserve_boxes(uint32_t n) {
    reserve_faces(n);
    for (auto* a : {&counts, &offsets}) a->reserve(n);
    scene.reserve(1);
  }

  // Temporary storage of the scene reduction and the scan of the counts over n boxes.
  size_t box_temp_bytes(Exec& exec, uint32_t n) const {
    return std::max(exec.scan_temp_bytes(n), exec.template reduce_temp_bytes_of<SceneStats>(n));
  }

  Array<uint32_t> counts, offsets;
  Array<SceneStats> scene;
  Array<std::byte> temp;
};

template <class Exec>
void reduce_scene_stats(Exec& exec, CellBoxes<Exec>& b, uint32_t n) {
  exec.reduce(n, SceneStatsFn{b.lo.data(), b.hi.data()}, SceneStatsOp{}, SceneStatsOp::identity(),
              b.scene.data(), b.temp.data(), b.temp.size());
}

}  // namespace cdb
