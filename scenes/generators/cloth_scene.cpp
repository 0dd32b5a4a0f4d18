#include "scenes/generators/cloth_scene.h"

#include "scenes/generators/rng.h"

namespace cdb::scene {

ClothSceneSource::ClothSceneSource(ClothSceneSpec spec) : spec_(std::move(spec)) {
  topology_.faces = spec_.cloth_faces;
  topology_.objects.push_back({"cloth", 0, uint32_t(spec_.cloth_faces.size()), false});
  uint32_t base = uint32_t(spec_.cloth.size());
  for (const auto& b : spec_.bodies) {
    const uint32_t first = uint32_t(topology_.faces.size());
    append_faces(b.mesh, base, topology_.faces);
    topology_.objects.push_back({b.name, first, uint32_t(topology_.faces.size()) - first, true});
    base += uint32_t(b.mesh.vertices.size());
  }
  for (const auto& d : spec_.deforming) {
    const uint32_t first = uint32_t(topology_.faces.size());
    for (const Tri& t : d.faces) topology_.faces.push_back({base + t.v0, base + t.v1, base + t.v2});
    topology_.objects.push_back({d.name, first, uint32_t(d.faces.size()), false});
    base += d.vertices;
  }
  topology_.num_vertices = base;
}

void ClothSceneSource::positions(uint32_t k, std::vector<vec3d>& out) const {
  if (k >= spec_.frames) fail("frame " + std::to_string(k) + " out of range (" + std::to_string(spec_.frames) + " frames)");
  std::lock_guard<std::mutex> lock(mutex_);
  const double dt = spec_.frame_time;
  if (!start_) {
    PbdCloth cloth(spec_.cloth, spec_.cloth_faces, spec_.settings);
    for (uint32_t v : spec_.pins) cloth.pin(v);
    for (const auto& [v, at] : spec_.moved_pins) cloth.pin(v, at);
    if (spec_.driven_at) cloth.drive(spec_.driven, spec_.driven_at);
    for (uint32_t f = 0; f < spec_.warmup; ++f) cloth.step(f * dt, dt, spec_.colliders, spec_.wind);
    start_.emplace(std::move(cloth));
  }
  if (!current_ || current_frame_ > k) {
    current_ = *start_;
    current_frame_ = 0;
  }
  for (; current_frame_ < k; ++current_frame_)
    current_->step((spec_.warmup + current_frame_) * dt, dt, spec_.colliders, spec_.wind);

  out.clear();
  out.reserve(topology_.num_vertices);
  for (const dvec3& p : current_->positions()) out.push_back({p.x, p.y, p.z});
  const double t = (spec_.warmup + k) * dt;
  for (const auto& b : spec_.bodies) {
    const Pose pose = b.pose(t);
    for (const dvec3& v : b.mesh.vertices) {
      const dvec3 p = pose.apply(v);
      out.push_back({p.x, p.y, p.z});
    }
  }
  std::vector<dvec3> body;
  for (const auto& d : spec_.deforming) {
    d.at_frame(k, body);
    if (body.size() != d.vertices) fail(d.name + ": frame " + std::to_string(k) + " has another vertex count");
    for (const dvec3& p : body) out.push_back({p.x, p.y, p.z});
  }
}

void cloth_grid(uint32_t nu, uint32_t nv, dvec3 origin, dvec3 du, dvec3 dv, std::vector<dvec3>& vertices,
                std::vector<Tri>& faces) {
  const uint32_t base = uint32_t(vertices.size());
  for (uint32_t j = 0; j < nv; ++j)
    for (uint32_t i = 0; i < nu; ++i) vertices.push_back(origin + double(i) * du + double(j) * dv);
  for (uint32_t j = 0; j + 1 < nv; ++j)
    for (uint32_t i = 0; i + 1 < nu; ++i) {
      const uint32_t a = base + j * nu + i;
      grid_cell_faces(i, j, a, a + 1, a + nu, a + nu + 1, faces);
    }
}

void grid_cell_faces(uint32_t i, uint32_t j, uint32_t a, uint32_t b, uint32_t c, uint32_t d, std::vector<Tri>& faces) {
  if ((i + j) % 2 == 0) {
    faces.push_back({a, b, d});
    faces.push_back({a, d, c});
  } else {
    faces.push_back({a, b, c});
    faces.push_back({b, d, c});
  }
}

ClothCommon read_cloth_common(Params& p, uint32_t res, uint32_t frames, uint32_t warmup, uint32_t substeps) {
  ClothCommon c;
  c.res = p.count32("res", res, 2, 20000);
  c.frames = p.count32("frames", frames, 1, 100000);
  c.warmup = p.count32("warmup", warmup, 0, 100000);
  c.substeps = p.count32("substeps", substeps, 1, 1000);
  c.seed = p.count_in("seed", 1, 0, scene::kLargestExactCount);
  return c;
}

void perturb(std::vector<dvec3>& vertices, dvec3 normal, double amount, uint64_t seed) {
  Rng rng{seed};
  for (dvec3& v : vertices) v += (amount * rng.symmetric()) * normal;
}

}  // namespace cdb::scene
