#pragma once
// A simulated scene: one PBD cloth and kinematic rigid or deforming bodies. Every frame's
// mesh holds the cloth's triangles first, then each body's, so the broad phase sees cloth
// self-contact and cloth-body contact in one triangle set (as the paper's benchmarks do).
//
// Frames are simulated on demand and in order. The state after the warm-up steps is kept,
// so asking for an earlier frame restarts from there; memory stays at a few copies of the
// cloth, however many frames the scene has.
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cdbench/geometry/frame_source.h"
#include "scenes/generators/params.h"
#include "scenes/generators/pbd_cloth.h"
#include "scenes/generators/rigid_shapes.h"

namespace cdb::scene {

struct ClothSceneSpec {
  std::string description;
  std::vector<dvec3> cloth;  // initial positions
  std::vector<Tri> cloth_faces;
  std::vector<uint32_t> pins;      // held at their initial positions
  std::vector<std::pair<uint32_t, dvec3>> moved_pins;  // held elsewhere (rest shape unchanged)
  ClothSettings settings;
  struct Body {
    std::string name;  // the scene object's name, for declared queries
    RigidMesh mesh;
    std::function<Pose(double t)> pose;
  };
  std::vector<Body> bodies;
  // Deforming bodies (a skinned character), after the rigid ones, each one deformable
  // object: its faces and its positions at output frame k.
  struct Deforming {
    std::string name;
    std::vector<Tri> faces;
    uint32_t vertices = 0;
    std::function<void(uint32_t frame, std::vector<dvec3>& out)> at_frame;
  };
  std::vector<Deforming> deforming;
  std::vector<uint32_t> driven;  // cloth vertices moved by `driven_at` (PbdCloth::drive)
  DrivenAt driven_at;
  CollidersAt colliders;
  WindAt wind;
  double frame_time = 1.0 / 30.0;
  uint32_t warmup = 0;  // frames simulated before frame 0, not output
  uint32_t frames = 1;
};

class ClothSceneSource final : public FrameSource {
 public:
  explicit ClothSceneSource(ClothSceneSpec spec);
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return spec_.frames; }
  void positions(uint32_t k, std::vector<vec3d>& out) const override;
  std::string describe() const override { return spec_.description; }

 private:
  ClothSceneSpec spec_;
  Topology topology_;
  mutable std::mutex mutex_;
  mutable std::optional<PbdCloth> start_;  // state at frame 0
  mutable std::optional<PbdCloth> current_;
  mutable uint32_t current_frame_ = 0;
};

// A flat rectangular grid of nu x nv vertices at origin + i*du + j*dv, two triangles per
// cell with the diagonal alternating cell by cell (no preferred fold direction).
void cloth_grid(uint32_t nu, uint32_t nv, dvec3 origin, dvec3 du, dvec3 dv, std::vector<dvec3>& vertices,
                std::vector<Tri>& faces);

// Cell (i, j) of a cloth grid, corners a, b along the row and c, d above them, as two
// triangles whose diagonal alternates with (i + j), as cloth_grid's cells do.
void grid_cell_faces(uint32_t i, uint32_t j, uint32_t a, uint32_t b, uint32_t c, uint32_t d, std::vector<Tri>& faces);

// Parameters every cloth scene takes.
struct ClothCommon {
  uint32_t res, frames, warmup, substeps;
  uint64_t seed;
};
ClothCommon read_cloth_common(Params& p, uint32_t res, uint32_t frames, uint32_t warmup, uint32_t substeps);

// Tiny seeded displacement of each vertex (along `normal`, a thousandth of the grid spacing)
// so that symmetric set-ups do not fold symmetrically and each seed folds differently.
void perturb(std::vector<dvec3>& vertices, dvec3 normal, double amount, uint64_t seed);

}  // namespace cdb::scene
