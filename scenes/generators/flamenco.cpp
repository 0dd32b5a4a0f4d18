// Paper's Flamenco (Wang et al. 2018, §5.2: 49K triangles): a dancer in a multi-layer
// skirt. The layers slide over each other and over the legs, so self-contact between the
// layers and contact with the body are dense and change every frame.
//
// Here the dancer is assimp's BCN_Epileptic.X (a skinned body, its 3.3 s jump clip looping)
// and the skirt is `layers` cones of the PBD cloth (pbd_cloth.h) whose waistbands are driven
// by the skin at the waist, colliding with the whole body's triangles.
//
// With `stride` N, one simulated frame in N is output: the `garment` scene, a long one-layer
// skirt whose frames are far enough apart that the cloth moves several of its boxes' sizes
// between two of them (incoherent frames, as a simulation's output sampled sparsely).
#include <algorithm>
#include <cmath>
#include <memory>

#include "scenes/generators/cloth_scene.h"
#include "cdbench/core/error.h"
#include "scenes/generators/paper_scenes.h"
#include "scenes/generators/rng.h"
#include "scenes/generators/subdivision.h"

namespace cdb::scene {
namespace {

constexpr double kTurn = 2 * 3.141592653589793;  // radians in a full turn

// Where a waistband vertex sits on the body: a point of one triangle (barycentric weights)
// and a distance along that triangle's normal.
struct Anchor {
  uint32_t face;
  dvec3 weights;
  double offset;
};

dvec3 anchored(const Anchor& a, const std::vector<Tri>& faces, const std::vector<dvec3>& x) {
  const Tri& t = faces[a.face];
  const dvec3 p0 = x[t.v0], p1 = x[t.v1], p2 = x[t.v2];
  return a.weights.x * p0 + a.weights.y * p1 + a.weights.z * p2 + a.offset * normalized(cross(p1 - p0, p2 - p0));
}

// The first triangle a ray from `origin` along `dir` meets (Moller-Trumbore), with the
// barycentric weights of the hit; false when it meets none.
bool first_hit(dvec3 origin, dvec3 dir, const std::vector<Tri>& faces, const std::vector<dvec3>& x, Anchor& hit,
               double& distance) {
  distance = 1e300;
  bool found = false;
  for (uint32_t f = 0; f < faces.size(); ++f) {
    const dvec3 a = x[faces[f].v0], e1 = x[faces[f].v1] - a, e2 = x[faces[f].v2] - a;
    const dvec3 pv = cross(dir, e2);
    const double det = dot(e1, pv);
    if (std::abs(det) < 1e-14) continue;
    const dvec3 tv = origin - a;
    const double u = dot(tv, pv) / det;
    if (u < 0 || u > 1) continue;
    const dvec3 qv = cross(tv, e1);
    const double v = dot(dir, qv) / det;
    if (v < 0 || u + v > 1) continue;
    const double t = dot(e2, qv) / det;
    if (t > 0 && t < distance) distance = t, hit = {f, {1 - u - v, u, v}, 0}, found = true;
  }
  return found;
}

// A tube of `around` x `rows` vertices, row j at positions[j * around + i], closed around
// (the seam's cells join column around-1 to column 0); diagonals alternate as cloth_grid's.
void tube_faces(uint32_t base, uint32_t around, uint32_t rows, std::vector<Tri>& faces) {
  for (uint32_t j = 0; j + 1 < rows; ++j)
    for (uint32_t i = 0; i < around; ++i) {
      const uint32_t a = base + j * around + i, b = base + j * around + (i + 1) % around;
      grid_cell_faces(i, j, a, b, a + around, b + around, faces);
    }
}

// The body at any time of the simulation, from samples at the output frames' times: held
// at its first pose through the warm-up (the skirt settles), then moving linearly between
// samples, so vertex velocities are constant within a frame.
class BodyTrack {
 public:
  BodyTrack(std::vector<std::vector<dvec3>> samples, double frame_time, double start)
      : samples_(std::move(samples)), dt_(frame_time), start_(start) {}
  void at(double t, std::vector<dvec3>& x, std::vector<dvec3>* v) const {
    const double u = std::max(0.0, (t - start_) / dt_);
    const size_t last = samples_.size() - 1;
    const size_t i = std::min(size_t(u), last > 0 ? last - 1 : 0);
    const double f = last > 0 ? std::min(u - double(i), 1.0) : 0.0;
    const auto& a = samples_[i];
    const auto& b = samples_[std::min(i + 1, last)];
    x.resize(a.size());
    for (size_t k = 0; k < a.size(); ++k) x[k] = a[k] + f * (b[k] - a[k]);
    if (!v) return;
    v->resize(a.size());
    const double moving = t > start_ ? 1.0 / dt_ : 0.0;
    for (size_t k = 0; k < a.size(); ++k) (*v)[k] = moving * (b[k] - a[k]);
  }
  const std::vector<dvec3>& sample(size_t k) const { return samples_[k]; }

 private:
  std::vector<std::vector<dvec3>> samples_;
  double dt_, start_;
};

}  // namespace

std::unique_ptr<FrameSource> make_flamenco(Params& p, const SceneInputs& inputs) {
  // res: vertices around each layer; each layer has 4/5 as many rows plus one, so the default
  // 96 gives 3 x 14,592 cloth triangles and with the body's 5,126 the paper's 49K.
  const ClothCommon c = read_cloth_common(p, 96, 60, 20, 12);
  const uint32_t layers = p.count32("layers", 3, 1, 16);
  const double flare = p.number("flare", 0.55);
  const std::string body_file = p.text("body", "/usr/share/assimp/models/X/BCN_Epileptic.X");
  const uint32_t stride = p.count32("stride", 1, 1, 1000);
  const uint32_t body_levels = p.count32("body_subdivisions", 0, 0, 3);
  p.finish();
  if (c.res < 4) fail("generator 'flamenco', parameter 'res': must be at least 4 (vertices around a layer)");
  if (!(flare >= 0 && flare <= 4)) fail("generator 'flamenco', parameter 'flare': must be between 0 and 4");

  const InputAnimation body = inputs.animation(body_file);
  if (body.topology.faces.empty()) fail("flamenco: " + body_file + ": no triangles");
  ClothSceneSpec s;
  s.frames = c.frames;
  s.warmup = c.warmup;
  // Every `stride`-th simulated frame is output: the solver takes as many substeps between
  // two output frames as over `stride` frames, so the cloth moves as at stride 1 and the
  // output sees its motion `stride` times coarser (incoherent frames at large strides). The
  // warm-up counts output frames.
  const double dt = s.frame_time;
  s.frame_time = stride * dt;
  // One body sample per simulated frame and one past the last (the motion in the last frame).
  const uint32_t simulated = c.frames * stride;
  std::vector<std::vector<dvec3>> samples(simulated + 1);
  std::vector<vec3f> f;
  for (uint32_t k = 0; k <= simulated; ++k) {
    // The clip loops (BCN's jump ends in its first pose).
    body.at(body.seconds > 0 ? std::fmod(k * dt, body.seconds) : 0.0, f);
    samples[k].reserve(f.size());
    for (const vec3f& q : f) samples[k].push_back({q.x, q.y, q.z});
  }
  const std::vector<dvec3>& pose = samples[0];

  // The waist: 0.6 of the body's height above its lowest point (the hips of BCN, y up), its
  // centre the median of the vertices near that height (the arms hang symmetrically on
  // either side).
  double lo = 1e300, hi = -1e300;
  for (const dvec3& q : pose) lo = std::min(lo, q.y), hi = std::max(hi, q.y);
  const double height = hi - lo, waist = lo + 0.6 * height;
  std::vector<double> xs, zs;
  for (const dvec3& q : pose)
    if (std::abs(q.y - waist) < 0.03 * height) xs.push_back(q.x), zs.push_back(q.z);
  if (xs.empty()) fail("flamenco: " + body_file + ": no vertex near the waist");
  std::nth_element(xs.begin(), xs.begin() + xs.size() / 2, xs.end());
  std::nth_element(zs.begin(), zs.begin() + zs.size() / 2, zs.end());
  const double cx = xs[xs.size() / 2], cz = zs[zs.size() / 2];

  const std::vector<Tri>& body_faces = body.topology.faces;
  const double thickness = 0.004 * height;  // 7 mm on a 1.8 m figure
  const double gap = 0.004 * height;        // between the layers' waistbands
  const uint32_t around = c.res, rows = 4 * c.res / 5 + 1;
  std::vector<Anchor> anchors;
  // Innermost layer first: the longest, reaching the shins; the outer ones shorter
  // (tiers), each attached a little lower and further out.
  for (uint32_t l = 0; l < layers; ++l) {
    const double y = waist - 0.012 * height * l;
    const double length = height * (0.46 - (layers > 1 ? 0.2 * l / (layers - 1) : 0.0));
    const uint32_t base = uint32_t(s.cloth.size());
    std::vector<dvec3> top(around);
    double mean_radius = 0;
    for (uint32_t i = 0; i < around; ++i) {
      const double angle = kTurn * i / around;
      const dvec3 dir{std::cos(angle), 0, std::sin(angle)}, origin{cx, y, cz};
      // The innermost surface the ray from the axis meets is the torso, not an arm.
      Anchor a;
      double distance;
      if (!first_hit(origin, dir, body_faces, pose, a, distance))
        fail("flamenco: " + body_file + ": the waist is not closed around its centre at height " + std::to_string(y));
      a.offset = thickness + gap * (l + 1);
      anchors.push_back(a);
      top[i] = anchored(a, body_faces, pose);
      mean_radius += std::hypot(top[i].x - cx, top[i].z - cz) / around;
    }
    // Rows from the waistband (the body's shape) to a circle of the flared radius.
    const double bottom_radius = mean_radius + flare * length;
    for (uint32_t j = 0; j < rows; ++j) {
      const double t = double(j) / (rows - 1);
      for (uint32_t i = 0; i < around; ++i) {
        const double angle = kTurn * i / around;
        const dvec3 bottom{cx + bottom_radius * std::cos(angle), y - length, cz + bottom_radius * std::sin(angle)};
        s.cloth.push_back((1 - t) * top[i] + t * bottom);
      }
    }
    tube_faces(base, around, rows, s.cloth_faces);
    for (uint32_t i = 0; i < around; ++i) s.driven.push_back(base + i);
  }
  // Seeded radial jitter, a thousandth of a row, so the folds differ by seed.
  Rng rng{c.seed};
  for (dvec3& q : s.cloth) {
    const dvec3 radial = normalized(dvec3{q.x - cx, 0, q.z - cz});
    q += (1e-3 * height / rows * rng.symmetric()) * radial;
  }

  s.settings.substeps = c.substeps * stride;
  s.settings.friction = 0.3;
  s.settings.thickness = thickness;
  s.settings.bend_compliance = 1e-3;
  s.settings.damping = 0.2;

  auto track = std::make_shared<const BodyTrack>(std::move(samples), dt, c.warmup * s.frame_time);
  auto faces = std::make_shared<const std::vector<Tri>>(body_faces);
  // Vertices up to 3 cm inside the skin are pushed out; deeper ones went through a limb and
  // are left to come out on their own.
  const double depth = 0.017 * height;
  s.driven_at = [track, faces, anchors](double t, std::vector<dvec3>& out) {
    std::vector<dvec3> x;
    track->at(t, x, nullptr);
    out.resize(anchors.size());
    for (size_t i = 0; i < anchors.size(); ++i) out[i] = anchored(anchors[i], *faces, x);
  };
  s.colliders = [track, faces, thickness, depth](double t, Colliders& col) {
    std::vector<dvec3> x, v;
    track->at(t, x, &v);
    col.meshes.push_back({std::make_shared<const MeshSurface>(faces, std::move(x), std::move(v), depth + thickness), depth});
  };
  // The body the broad phase sees may be finer than the one the cloth collides with
  // (`body_subdivisions`): the same surface, so the cloth moves the same, in 4^levels as many
  // triangles, as an avatar's collision mesh is often finer than its skinned model.
  auto finer = std::make_shared<const Subdivision>(subdivide(body_faces, body.topology.num_vertices, body_levels));
  s.deforming.push_back({"body", finer->faces, finer->vertices(),
                         [track, stride, finer](uint32_t k, std::vector<dvec3>& out) {
                           out = track->sample(k * stride);
                           finer->apply(out);
                         }});
  const size_t tris = s.cloth_faces.size() + finer->faces.size();
  s.description = "flamenco: " + body_file + " (" + std::to_string(finer->faces.size()) + " triangles" +
                  (body_levels > 0 ? ", subdivided " + std::to_string(body_levels) + " times" : std::string()) +
                  ") dancing in a " +
                  std::to_string(layers) + "-layer skirt of " + std::to_string(around) + " x " + std::to_string(rows) +
                  " per layer (" + std::to_string(s.cloth_faces.size()) + " cloth triangles; " + std::to_string(tris) +
                  " triangles, " + std::to_string(s.frames) + " frames" +
                  (stride > 1 ? ", one in " + std::to_string(stride) + " simulated frames" : std::string()) + ")";
  return std::make_unique<ClothSceneSource>(std::move(s));
}

}  // namespace cdb::scene
