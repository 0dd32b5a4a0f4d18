#include "scenes/generators/pbd_cloth.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <utility>

#include "cdbench/core/error.h"

namespace cdb::scene {
namespace {

// Below this many items a loop runs on one thread: the fork costs more than it saves.
constexpr int64_t kParallelMin = 2048;

}  // namespace

PbdCloth::PbdCloth(std::vector<dvec3> positions, const std::vector<Tri>& faces, const ClothSettings& settings)
    : s_(settings), faces_(faces), x_(std::move(positions)) {
  const size_t n = x_.size();
  prev_ = x_;
  v_.assign(n, {});
  accel_.assign(n, {});
  inv_mass_.assign(n, 1.0);

  // Edges and, for interior edges, the two opposite vertices: stretch and bending pairs.
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> opposite;
  for (const Tri& t : faces_) {
    const uint32_t v[3] = {t.v0, t.v1, t.v2};
    for (int e = 0; e < 3; ++e) opposite[std::minmax(v[e], v[(e + 1) % 3])].push_back(v[(e + 2) % 3]);
  }
  auto add = [&](uint32_t a, uint32_t b, double compliance) {
    if (a != b) constraints_.push_back({a, b, length(x_[a] - x_[b]), compliance});
  };
  for (const auto& [edge, opp] : opposite) add(edge.first, edge.second, s_.stretch_compliance);
  for (const auto& [edge, opp] : opposite)
    if (opp.size() == 2) add(opp[0], opp[1], s_.bend_compliance);
  colour_constraints();
  lambda_.assign(constraints_.size(), 0.0);

  // Faces around each vertex, in face order, for the per-vertex wind sums.
  vertex_face_start_.assign(n + 1, 0);
  for (const Tri& t : faces_) {
    ++vertex_face_start_[t.v0 + 1];
    ++vertex_face_start_[t.v1 + 1];
    ++vertex_face_start_[t.v2 + 1];
  }
  for (size_t v = 0; v < n; ++v) vertex_face_start_[v + 1] += vertex_face_start_[v];
  vertex_faces_.resize(vertex_face_start_[n]);
  std::vector<uint32_t> fill(vertex_face_start_.begin(), vertex_face_start_.end() - 1);
  for (uint32_t f = 0; f < faces_.size(); ++f)
    for (uint32_t v : {faces_[f].v0, faces_[f].v1, faces_[f].v2}) vertex_faces_[fill[v]++] = f;
  face_force_.assign(faces_.size(), {});
  double area = 0;
  for (const Tri& t : faces_) area += 0.5 * length(cross(x_[t.v1] - x_[t.v0], x_[t.v2] - x_[t.v0]));
  mean_vertex_area_ = n > 0 && area > 0 ? area / double(n) : 1.0;
}

void PbdCloth::pin(uint32_t vertex) { inv_mass_.at(vertex) = 0.0; }

void PbdCloth::pin(uint32_t vertex, dvec3 position) {
  pin(vertex);
  x_[vertex] = prev_[vertex] = position;
}

void PbdCloth::drive(std::vector<uint32_t> vertices, DrivenAt at) {
  for (uint32_t v : vertices) pin(v);
  driven_ = std::move(vertices);
  driven_at_ = std::move(at);
}

// Greedy colouring in constraint order: each constraint takes the lowest colour that
// neither of its vertices has yet. Fixed order, so the batches are the same every run.
void PbdCloth::colour_constraints() {
  std::vector<uint64_t> used(x_.size(), 0);
  std::vector<uint32_t> colour(constraints_.size());
  uint32_t colours = 0;
  for (size_t i = 0; i < constraints_.size(); ++i) {
    const uint64_t taken = used[constraints_[i].a] | used[constraints_[i].b];
    if (~taken == 0) fail("cloth solver: a vertex has too many constraints to colour (more than 64)");
    const uint32_t c = uint32_t(std::countr_one(taken));
    colour[i] = c;
    used[constraints_[i].a] |= 1ull << c;
    used[constraints_[i].b] |= 1ull << c;
    colours = std::max(colours, c + 1);
  }
  colour_start_.assign(colours + 1, 0);
  for (uint32_t c : colour) ++colour_start_[c + 1];
  for (uint32_t c = 0; c < colours; ++c) colour_start_[c + 1] += colour_start_[c];
  std::vector<Constraint> sorted(constraints_.size());
  std::vector<uint32_t> fill(colour_start_.begin(), colour_start_.end() - 1);
  for (size_t i = 0; i < constraints_.size(); ++i) sorted[fill[colour[i]]++] = constraints_[i];
  constraints_ = std::move(sorted);
}

void PbdCloth::wind_accelerations(double t, const WindAt& wind) {
  const int64_t nf = int64_t(faces_.size()), nv = int64_t(x_.size());
  if (s_.drag > 0 && wind) {
#pragma omp parallel for schedule(static) if (nf > kParallelMin)
    for (int64_t f = 0; f < nf; ++f) {
      const Tri tri = faces_[f];
      const dvec3 a = x_[tri.v0], b = x_[tri.v1], c = x_[tri.v2];
      const dvec3 area_normal = 0.5 * cross(b - a, c - a);
      const double area = length(area_normal);
      if (area <= 0) {
        face_force_[f] = {};
        continue;
      }
      const dvec3 n = (1.0 / area) * area_normal;
      const dvec3 velocity = (1.0 / 3.0) * (v_[tri.v0] + v_[tri.v1] + v_[tri.v2]);
      const dvec3 relative = wind(t, (1.0 / 3.0) * (a + b + c)) - velocity;
      // Pressure of the wind's normal component: a sheet edge-on to the wind feels none.
      face_force_[f] = (s_.drag * area * dot(relative, n)) * n;
    }
  }
#pragma omp parallel for schedule(static) if (nv > kParallelMin)
  for (int64_t v = 0; v < nv; ++v) {
    dvec3 a = s_.gravity;
    if (s_.drag > 0 && wind) {
      dvec3 f{};
      for (uint32_t k = vertex_face_start_[v]; k < vertex_face_start_[v + 1]; ++k) f += face_force_[vertex_faces_[k]];
      a += (1.0 / (3.0 * mean_vertex_area_)) * f;
    }
    accel_[v] = a;
  }
}

void PbdCloth::project_constraints(double h) {
  const double inv_h2 = 1.0 / (h * h);
  for (size_t c = 0; c + 1 < colour_start_.size(); ++c) {
    const int64_t begin = colour_start_[c], end = colour_start_[c + 1];
#pragma omp parallel for schedule(static) if (end - begin > kParallelMin)
    for (int64_t i = begin; i < end; ++i) {
      const Constraint k = constraints_[i];
      const double wa = inv_mass_[k.a], wb = inv_mass_[k.b];
      const double alpha = k.compliance * inv_h2;
      if (wa + wb == 0) continue;
      const dvec3 d = x_[k.a] - x_[k.b];
      const double len = length(d);
      if (len < 1e-12) continue;
      const double dl = (-(len - k.rest) - alpha * lambda_[i]) / (wa + wb + alpha);
      lambda_[i] += dl;
      const dvec3 g = (dl / len) * d;
      x_[k.a] += wa * g;
      x_[k.b] -= wb * g;
    }
  }
}

void PbdCloth::collide(const Colliders& col, double h) {
  const int64_t n = int64_t(x_.size());
  const size_t shells = col.revolved.size();
  if (!sides_ready_) {
    shell_side_.assign(shells * x_.size(), 1);
    for (size_t s = 0; s < shells; ++s)
      if (!col.revolved[s].solid)
        for (int64_t v = 0; v < n; ++v) shell_side_[s * x_.size() + v] = shell_side(col.revolved[s], prev_[v]);
    sides_ready_ = true;
  }
  if (shell_side_.size() != shells * x_.size()) fail("cloth solver: the obstacles changed between steps");
#pragma omp parallel for schedule(static) if (n > kParallelMin)
  for (int64_t v = 0; v < n; ++v) {
    if (inv_mass_[v] == 0) continue;
    dvec3 p = x_[v];
    Contact c;
    // Friction: remove part of the slip against the surface during this substep.
    auto rub = [&] {
      const dvec3 slip = (p - prev_[v]) - h * c.surface_velocity;
      const dvec3 tangential = slip - dot(slip, c.normal) * c.normal;
      p -= s_.friction * tangential;
    };
    for (const auto& s : col.spheres)
      if (resolve(s, s_.thickness, p, c)) rub();
    for (const auto& s : col.capsules)
      if (resolve(s, s_.thickness, p, c)) rub();
    for (size_t s = 0; s < shells; ++s)
      if (resolve(col.revolved[s], s_.thickness, p, shell_side_[s * x_.size() + v], c)) rub();
    for (const auto& m : col.meshes)
      if (resolve(m, s_.thickness, p, c)) rub();
    x_[v] = p;
  }
}

void PbdCloth::step(double t, double dt, const CollidersAt& colliders, const WindAt& wind) {
  const uint32_t substeps = std::max(s_.substeps, 1u);
  const double h = dt / substeps, decay = std::exp(-s_.damping * h);
  const int64_t n = int64_t(x_.size());
  for (uint32_t sub = 0; sub < substeps; ++sub) {
    const double ts = t + (sub + 1) * h;
    colliders_ = {};
    if (colliders) colliders(ts, colliders_);
    wind_accelerations(ts, wind);
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (int64_t v = 0; v < n; ++v) {
      prev_[v] = x_[v];
      if (inv_mass_[v] == 0) continue;
      v_[v] = decay * v_[v] + h * accel_[v];
      x_[v] += h * v_[v];
    }
    if (driven_at_) {
      driven_at_(ts, driven_to_);
      if (driven_to_.size() != driven_.size()) fail("cloth solver: driven vertices and their positions differ in number");
      for (size_t i = 0; i < driven_.size(); ++i) x_[driven_[i]] = driven_to_[i];
    }
    std::fill(lambda_.begin(), lambda_.end(), 0.0);
    for (uint32_t it = 0; it < std::max(s_.iterations, 1u); ++it) project_constraints(h);
    collide(colliders_, h);
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (int64_t v = 0; v < n; ++v) v_[v] = (1.0 / h) * (x_[v] - prev_[v]);
  }
}

}  // namespace cdb::scene
