// Paper's Dragon (Wang et al. 2018, §5.2: 252K triangles): a dragon shattered by a
// projectile, its pieces scattering. The hierarchy built on the intact dragon of frame 0
// becomes poor as the pieces fly apart: the case for the paper's restructuring, where
// refitting alone degrades.
//
// Here the scan is CGAL's ChineseDragon-10kv (libcgal-demo's data.tar.gz), refined by
// longest-edge bisection to `triangles`, cut into `pieces` Voronoi cells (every triangle in
// the cell of its centroid; the triangle count stays fixed), and hit by a ball. Each piece
// is a rigid body: still until the impact, then moving with the velocity the impact gives
// it (stronger near the impact point), spinning, falling under gravity and bouncing on the
// ground. Pieces pass through each other: their contacts are what the broad phase reports.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <queue>
#include <set>
#include <unordered_map>

#include "cdbench/core/error.h"
#include "scenes/generators/dvec.h"
#include "scenes/generators/paper_scenes.h"
#include "scenes/generators/rigid_shapes.h"
#include "scenes/generators/rng.h"

namespace cdb::scene {
namespace {

uint64_t edge_key(uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a; }

// Splits the longest edge, in every triangle that has it, at its midpoint until there are
// at least `target` triangles: the mesh stays conforming (no T-junctions) and its
// triangles even in size. Edges of more than two triangles are never split. Ties go to
// the smaller key, so the result is the same on every run.
void refine(std::vector<dvec3>& x, std::vector<Tri>& faces, uint64_t target) {
  struct Edge {
    uint32_t face[2];
    uint32_t count;
  };
  std::unordered_map<uint64_t, Edge> edges;
  std::priority_queue<std::pair<double, uint64_t>, std::vector<std::pair<double, uint64_t>>,
                      bool (*)(const std::pair<double, uint64_t>&, const std::pair<double, uint64_t>&)>
      longest([](const std::pair<double, uint64_t>& a, const std::pair<double, uint64_t>& b) {
        return a.first < b.first || (a.first == b.first && a.second > b.second);
      });
  auto add = [&](uint32_t a, uint32_t b, uint32_t f) {
    const uint64_t k = edge_key(a, b);
    auto [it, fresh] = edges.try_emplace(k, Edge{{f, f}, 0});
    if (it->second.count < 2) it->second.face[it->second.count] = f;
    ++it->second.count;
    if (fresh) {
      const dvec3 d = x[a] - x[b];
      longest.push({dot(d, d), k});
    }
  };
  auto replace = [&](uint32_t a, uint32_t b, uint32_t from, uint32_t to) {
    Edge& e = edges.at(edge_key(a, b));
    for (uint32_t i = 0; i < std::min(e.count, 2u); ++i)
      if (e.face[i] == from) e.face[i] = to;
  };
  for (uint32_t f = 0; f < faces.size(); ++f) {
    add(faces[f].v0, faces[f].v1, f);
    add(faces[f].v1, faces[f].v2, f);
    add(faces[f].v2, faces[f].v0, f);
  }
  while (faces.size() < target && !longest.empty()) {
    const uint64_t k = longest.top().second;
    longest.pop();
    const auto it = edges.find(k);
    if (it == edges.end() || it->second.count > 2) continue;
    const Edge e = it->second;
    edges.erase(it);
    const uint32_t a = uint32_t(k >> 32), b = uint32_t(k);
    const uint32_t m = uint32_t(x.size());
    x.push_back(0.5 * (x[a] + x[b]));
    for (uint32_t i = 0; i < e.count; ++i) {
      const uint32_t f = e.face[i];
      // Rotate the corners so the split edge is (u, v) in the triangle's own order.
      Tri t = faces[f];
      while (!((t.v0 == a || t.v0 == b) && (t.v1 == a || t.v1 == b))) t = {t.v1, t.v2, t.v0};
      const uint32_t u = t.v0, v = t.v1, w = t.v2;
      const uint32_t g = uint32_t(faces.size());
      faces[f] = {u, m, w};
      faces.push_back({m, v, w});
      replace(v, w, f, g);
      add(u, m, f);
      add(m, v, g);
      add(m, w, f);
      add(m, w, g);
    }
  }
}

// Orientation as a unit quaternion (w, x, y, z).
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

Pose pose_of(const Quat& q, dvec3 t) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  Pose p;
  p.r[0][0] = 1 - 2 * (y * y + z * z), p.r[0][1] = 2 * (x * y - w * z), p.r[0][2] = 2 * (x * z + w * y);
  p.r[1][0] = 2 * (x * y + w * z), p.r[1][1] = 1 - 2 * (x * x + z * z), p.r[1][2] = 2 * (y * z - w * x);
  p.r[2][0] = 2 * (x * z - w * y), p.r[2][1] = 2 * (y * z + w * x), p.r[2][2] = 1 - 2 * (x * x + y * y);
  p.t = t;
  return p;
}

// q += h/2 (0, spin) q, renormalised.
void turn(Quat& q, dvec3 spin, double h) {
  const Quat d{-spin.x * q.x - spin.y * q.y - spin.z * q.z, spin.x * q.w + spin.y * q.z - spin.z * q.y,
               -spin.x * q.z + spin.y * q.w + spin.z * q.x, spin.x * q.y - spin.y * q.x + spin.z * q.w};
  q = {q.w + 0.5 * h * d.w, q.x + 0.5 * h * d.x, q.y + 0.5 * h * d.y, q.z + 0.5 * h * d.z};
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  q = {q.w / n, q.x / n, q.y / n, q.z / n};
}

struct Piece {
  uint32_t first_vertex, vertices;  // its own vertices (body coordinates, about its centre)
  dvec3 x, v, spin;
  Quat q;
  double radius;  // of the bounding sphere about x
};

class DragonSource final : public FrameSource {
 public:
  DragonSource(Topology topology, std::vector<dvec3> local, std::vector<std::vector<Pose>> poses,
               std::vector<Piece> pieces, std::string description)
      : topology_(std::move(topology)),
        local_(std::move(local)),
        poses_(std::move(poses)),
        pieces_(std::move(pieces)),
        description_(std::move(description)) {}
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return uint32_t(poses_.size()); }
  std::string describe() const override { return description_; }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    if (k >= poses_.size()) fail("frame " + std::to_string(k) + " out of range (" + std::to_string(poses_.size()) + " frames)");
    out.resize(local_.size());
    for (size_t i = 0; i < pieces_.size(); ++i) {
      const Pose& pose = poses_[k][i];
      for (uint32_t v = pieces_[i].first_vertex; v < pieces_[i].first_vertex + pieces_[i].vertices; ++v) {
        const dvec3 p = pose.apply(local_[v]);
        out[v] = {p.x, p.y, p.z};
      }
    }
  }

 private:
  Topology topology_;
  std::vector<dvec3> local_;
  std::vector<std::vector<Pose>> poses_;  // per frame, per piece (the ball last)
  std::vector<Piece> pieces_;
  std::string description_;
};

}  // namespace

std::unique_ptr<FrameSource> make_dragon(Params& p, const SceneInputs& inputs) {
  // 250,720 + the ball's 1,280 = 252,000, the paper's count.
  const uint64_t target = p.count_in("triangles", 250720, 1, uint64_t(1) << 28);
  const uint32_t pieces = p.count32("pieces", 256, 1, 4096);
  const uint32_t frames = p.count32("frames", 60, 1, 100000);
  const uint32_t impact = p.count32("impact_frame", 8, 0, 100000);
  const uint32_t level = p.count32("ball_level", 3, 0, 8);
  const double speed = p.number("speed", 8.0);
  const uint32_t ground = p.count32("ground", 1, 0, 1);
  // Frames per second of simulated time: the pieces fall from the statue's 1.2 m in about
  // half a second, so 75 fps keeps most of the 60 frames in flight.
  const double fps = p.number("fps", 75.0);
  const uint32_t substeps = p.count32("substeps", 4, 1, 1000);
  const uint64_t seed = p.count_in("seed", 1, 0, kLargestExactCount);
  const std::string scan = p.text("scan", "/usr/share/doc/libcgal-dev/data.tar.gz");
  const std::string member = p.text("member", "data/meshes/ChineseDragon-10kv.off");
  p.finish();
  if (!(speed >= 0)) fail("generator 'dragon', parameter 'speed': must be >= 0");
  if (!(fps > 0)) fail("generator 'dragon', parameter 'fps': must be positive");

  InputMesh mesh = inputs.mesh(scan, member);
  const std::string origin = member.empty() ? scan : scan + ":" + member;
  if (mesh.faces.empty()) fail("dragon: " + origin + ": no triangles");
  const size_t scanned = mesh.faces.size();
  // Placed standing on the ground (y = 0, y up), centred over the origin, 2 long.
  dvec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const dvec3& q : mesh.positions) {
    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
  }
  const double scale = 2.0 / std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-300});
  for (dvec3& q : mesh.positions)
    q = scale * dvec3{q.x - 0.5 * (lo.x + hi.x), q.y - lo.y, q.z - 0.5 * (lo.z + hi.z)};
  const double height = scale * (hi.y - lo.y);

  // The ball comes in level, along +x and a little across, aimed at the middle of the dragon;
  // it strikes where that line first meets the scan.
  const dvec3 dir = normalized(dvec3{1, 0, 0.3}), aim{0, 0.5 * height, 0};
  dvec3 hit = aim;
  double first = 1e300;
  for (const Tri& t : mesh.faces) {
    const dvec3 a = mesh.positions[t.v0], e1 = mesh.positions[t.v1] - a, e2 = mesh.positions[t.v2] - a;
    const dvec3 o = aim - 4.0 * dir;
    const dvec3 pv = cross(dir, e2);
    const double det = dot(e1, pv);
    if (std::abs(det) < 1e-14) continue;
    const double u = dot(o - a, pv) / det;
    const dvec3 qv = cross(o - a, e1);
    const double v = dot(dir, qv) / det, s = dot(e2, qv) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && s > 0 && s < first) first = s, hit = o + s * dir;
  }

  refine(mesh.positions, mesh.faces, target);

  // Voronoi seeds: scan vertices drawn at random, kept with a probability that falls with
  // the distance from the impact, so the pieces are small where the ball strikes.
  Rng rng{seed};
  const size_t nv = mesh.positions.size();
  std::vector<uint32_t> seeds;
  std::set<uint32_t> taken;
  const double near = 0.3 * height;
  for (uint64_t tries = 0; seeds.size() < std::min<size_t>(pieces, nv) && tries < 1000ull * pieces; ++tries) {
    const uint32_t v = uint32_t(rng.next() % nv);
    const double d = length(mesh.positions[v] - hit) / near;
    if (rng.uniform() < 0.15 + 0.85 * std::exp(-d * d) && taken.insert(v).second) seeds.push_back(v);
  }
  std::vector<uint32_t> cell(mesh.faces.size());
  const int64_t nf = int64_t(mesh.faces.size());
#pragma omp parallel for schedule(static)
  for (int64_t f = 0; f < nf; ++f) {
    const Tri& t = mesh.faces[f];
    const dvec3 centroid = (1.0 / 3.0) * (mesh.positions[t.v0] + mesh.positions[t.v1] + mesh.positions[t.v2]);
    double best = 1e300;
    for (uint32_t s = 0; s < seeds.size(); ++s) {
      const dvec3 d = centroid - mesh.positions[seeds[s]];
      if (dot(d, d) < best) best = dot(d, d), cell[f] = s;
    }
  }

  // Faces grouped by piece (in scan order within one); each piece its own vertices.
  Topology topo;
  std::vector<dvec3> local;
  std::vector<Piece> bodies;
  std::vector<std::vector<uint32_t>> members(seeds.size());
  for (uint32_t f = 0; f < mesh.faces.size(); ++f) members[cell[f]].push_back(f);
  std::vector<uint32_t> index(nv, UINT32_MAX);
  for (const auto& list : members) {
    if (list.empty()) continue;
    Piece piece{uint32_t(local.size()), 0, {}, {}, {}, {}, 0};
    std::vector<uint32_t> used;
    for (uint32_t f : list) {
      uint32_t c[3] = {mesh.faces[f].v0, mesh.faces[f].v1, mesh.faces[f].v2};
      for (uint32_t& v : c) {
        if (index[v] == UINT32_MAX) index[v] = uint32_t(local.size()), local.push_back(mesh.positions[v]), used.push_back(v);
        v = index[v];
      }
      topo.faces.push_back({c[0], c[1], c[2]});
    }
    // A vertex on a cut belongs to each piece that has it: copies, free to part.
    for (uint32_t v : used) index[v] = UINT32_MAX;
    piece.vertices = uint32_t(local.size()) - piece.first_vertex;
    for (uint32_t v = piece.first_vertex; v < local.size(); ++v) piece.x += local[v];
    piece.x = (1.0 / piece.vertices) * piece.x;
    for (uint32_t v = piece.first_vertex; v < local.size(); ++v) {
      local[v] -= piece.x;
      piece.radius = std::max(piece.radius, length(local[v]));
    }
    bodies.push_back(piece);
  }
  const uint32_t dragon_faces = uint32_t(topo.faces.size());
  topo.objects.push_back({"dragon", 0, dragon_faces, false});

  const RigidMesh ball = icosphere(level, 0.08 * height);
  Piece b{uint32_t(local.size()), uint32_t(ball.vertices.size()), {}, speed * dir, {}, {}, 0.08 * height};
  for (const dvec3& v : ball.vertices) local.push_back(v);
  append_faces(ball, b.first_vertex, topo.faces);
  topo.objects.push_back({"ball", dragon_faces, uint32_t(topo.faces.size()) - dragon_faces, true});
  topo.num_vertices = uint32_t(local.size());
  const double dt = 1.0 / fps, hit_time = impact * dt;
  b.x = hit - b.radius * dir - (speed * hit_time) * dir;
  bodies.push_back(b);

  // The impact gives each piece a push along the ball's path and away from the impact
  // point, falling off with distance, a spin and a seeded scatter; the ball keeps a third of
  // its speed.
  const double gravity = 9.81, restitution = 0.3, grip = 0.85;
  std::vector<std::vector<Pose>> poses(frames);
  bool struck = false;
  auto strike = [&] {
    for (size_t i = 0; i + 1 < bodies.size(); ++i) {
      Piece& q = bodies[i];
      const dvec3 away = q.x - hit;
      const double falloff = std::exp(-length(away) / (0.35 * height));
      const dvec3 jitter{rng.symmetric(), rng.symmetric(), rng.symmetric()};
      q.v = speed * falloff * (0.6 * dir + 0.5 * normalized(away) + 0.15 * jitter);
      const dvec3 axis = normalized(dvec3{rng.symmetric(), rng.symmetric(), rng.symmetric()});
      q.spin = (0.5 * length(q.v) / std::max(q.radius, 0.02 * height)) * axis;
    }
    bodies.back().v = (1.0 / 3.0) * bodies.back().v;
    struck = true;
  };
  // Lowest point of a body as turned now (the ball's is its centre less its radius).
  auto lowest = [&](size_t i, const Pose& pose) {
    const Piece& q = bodies[i];
    if (i + 1 == bodies.size()) return q.x.y - q.radius;
    double y = 1e300;
    for (uint32_t v = q.first_vertex; v < q.first_vertex + q.vertices; ++v) y = std::min(y, pose.apply(local[v]).y);
    return y;
  };
  const double h = dt / substeps;
  for (uint32_t k = 0; k < frames; ++k) {
    for (size_t i = 0; i < bodies.size(); ++i) poses[k].push_back(pose_of(bodies[i].q, bodies[i].x));
    for (uint32_t s = 0; s < substeps; ++s) {
      const double t = k * dt + (s + 1) * h;
      if (!struck && t > hit_time) strike();
      for (size_t i = 0; i < bodies.size(); ++i) {
        Piece& q = bodies[i];
        const bool ball_flying = i + 1 == bodies.size() && !struck;
        if (!struck && !ball_flying) continue;  // the dragon stands until it is struck
        if (struck) q.v.y -= gravity * h;
        q.x += h * q.v;
        turn(q.q, q.spin, h);
        if (!ground || q.x.y - q.radius > 0) continue;
        const double y = lowest(i, pose_of(q.q, q.x));
        if (y >= 0) continue;
        // On the ground: lifted out, the fall reversed and damped, sliding and spin slowed.
        q.x.y -= y;
        if (q.v.y < 0) q.v.y = -restitution * q.v.y;
        q.v.x *= grip, q.v.z *= grip;
        q.spin = grip * q.spin;
      }
    }
  }
  const size_t total = topo.faces.size();
  char fps_text[32];
  std::snprintf(fps_text, sizeof fps_text, "%g", fps);
  const std::string description =
      "dragon: " + origin + " (" + std::to_string(scanned) + " triangles) refined to " + std::to_string(dragon_faces) +
      " and cut into " + std::to_string(bodies.size() - 1) + " pieces, struck by a ball (" +
      std::to_string(ball.faces.size()) + ") at frame " + std::to_string(impact) + " and scattering" +
      (ground ? " onto the ground" : "") + " (" + std::to_string(total) + " triangles, " + std::to_string(frames) +
      " frames at " + fps_text + " fps)";
  return std::make_unique<DragonSource>(std::move(topo), std::move(local), std::move(poses), std::move(bodies),
                                        description);
}

}  // namespace cdb::scene
