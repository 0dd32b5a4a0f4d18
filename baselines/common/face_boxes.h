#pragma once
// The triangles' boxes, by face, that every baseline workspace starts from, and the step
// that fills them: geometry/mesh.h FaceBoxFn, so every box option (--box-margin, --boxes
// swept, --box-precision) applies and the boxes are the oracle's.
#include <cstdint>
#include <string>

#include "cdbench/exec/memory.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

struct FaceBoxes {
  // Buffers are named "<prefix>.lo" and "<prefix>.hi" in the growth log.
  FaceBoxes(MemoryResource& mr, const std::string& prefix) {
    bind_arrays(mr, prefix + ".", {{&lo, "lo"}, {&hi, "hi"}});
  }

  void reserve_faces(uint32_t n) {
    for (auto* a : {&lo, &hi}) a->reserve(n);
  }

  Array<vec4f> lo, hi;
};

template <class Exec>
void face_boxes(Exec& exec, FaceBoxes& b, const MeshView& mesh) {
  exec.for_each_n(mesh.num_faces, FaceBoxFn{mesh, b.lo.data(), b.hi.data()});
}

}  // namespace cdb
