#include "scenes/generators/cloth_scenes.h"

#include <cmath>

#include "scenes/generators/cloth_scene.h"

namespace cdb::scene {
namespace {

constexpr double kPi = 3.141592653589793;

std::string count_text(const ClothSceneSpec& s) {
  size_t tris = s.cloth_faces.size();
  for (const auto& b : s.bodies) tris += b.mesh.faces.size();
  return std::to_string(tris) + " triangles, " + std::to_string(s.frames) + " frames";
}

// The profile with each edge cut into `pieces` shorter ones, so the mesh's triangles are
// not long slivers.
Profile refine(const Profile& p, const std::vector<uint32_t>& pieces) {
  Profile out{p.front()};
  for (size_t e = 0; e + 1 < p.size(); ++e)
    for (uint32_t k = 1; k <= pieces[e]; ++k) {
      const double t = double(k) / pieces[e];
      out.push_back({p[e].rho + t * (p[e + 1].rho - p[e].rho), p[e].y + t * (p[e + 1].y - p[e].y)});
    }
  return out;
}

// Funnel geometry: a cone from the rim (radius 1 at y = 0) to the throat (radius 0.3 at
// y = -0.9), then a straight spout down to y = -1.3.
const Profile kFunnel = {{1.0, 0.0}, {0.3, -0.9}, {0.3, -1.3}};
const std::vector<uint32_t> kFunnelPieces = {10, 4};

Pose translation(dvec3 t) {
  Pose p;
  p.t = t;
  return p;
}

}  // namespace

// Paper's Funnel: a square cloth lies over a funnel; a ball comes down on it and pushes it
// into the funnel, where the narrowing wall gathers it into folds, and on through the
// throat. The warm-up (1 s by default) starts the output with the ball already inside
// the funnel and the cloth folded around it.
std::unique_ptr<FrameSource> make_funnel(Params& p) {
  const ClothCommon c = read_cloth_common(p, 56, 20, 30, 12);
  const uint32_t segments = p.count32("segments", 48, 3, 100000);
  const uint32_t level = p.count32("ball_level", 3, 0, 8);
  const double speed = p.number("ball_speed", 0.9);
  p.finish();
  const double size = 1.6, radius = 0.22;
  ClothSceneSpec s;
  const double h = size / (c.res - 1);
  cloth_grid(c.res, c.res, {-size / 2, 0.1, -size / 2}, {h, 0, 0}, {0, 0, h}, s.cloth, s.cloth_faces);
  perturb(s.cloth, {0, 1, 0}, 1e-3 * h, c.seed);
  s.settings.substeps = c.substeps;
  s.settings.friction = 0.2;
  s.settings.thickness = 0.01;
  s.settings.bend_compliance = 1e-4;
  s.frames = c.frames;
  s.warmup = c.warmup;
  // The ball starts above the cloth and comes straight down the axis until it is well
  // below the spout.
  auto centre = [speed](double t) { return dvec3{0, std::max(0.6 - speed * t, -2.2), 0}; };
  auto velocity = [speed](double t) { return dvec3{0, 0.6 - speed * t > -2.2 ? -speed : 0.0, 0}; };
  s.bodies.push_back({"funnel", revolve(refine(kFunnel, kFunnelPieces), segments), [](double) { return Pose{}; }});
  s.bodies.push_back({"ball", icosphere(level, radius), [centre](double t) { return translation(centre(t)); }});
  s.colliders = [centre, velocity, radius](double t, Colliders& col) {
    col.revolved.push_back({{0, 0, 0}, kFunnel, false, {}});
    col.spheres.push_back({centre(t), radius, velocity(t), {}});
  };
  s.description = "funnel: " + std::to_string(c.res) + "x" + std::to_string(c.res) +
                  " cloth pushed by a ball through a funnel (" + count_text(s) + ")";
  return std::make_unique<ClothSceneSource>(std::move(s));
}

// Paper's Cloth Ball (kDet's Whirling Cloth): a square cloth falls onto a ball and drapes
// over it; the ball turns slowly about the vertical, and over the last 30% of the scene
// spins up so that friction twists the cloth around it.
std::unique_ptr<FrameSource> make_cloth_ball(Params& p) {
  const ClothCommon c = read_cloth_common(p, 64, 40, 20, 12);
  const uint32_t level = p.count32("ball_level", 3, 0, 8);
  const double spin = p.number("spin", 0.5), twist = p.number("twist_spin", 5.0);
  p.finish();
  const double size = 3.0, radius = 0.5;
  ClothSceneSpec s;
  const double h = size / (c.res - 1);
  cloth_grid(c.res, c.res, {-size / 2, radius + 0.06, -size / 2}, {h, 0, 0}, {0, 0, h}, s.cloth, s.cloth_faces);
  perturb(s.cloth, {0, 1, 0}, 1e-3 * h, c.seed);
  s.settings.substeps = c.substeps;
  s.settings.friction = 0.6;
  s.settings.thickness = 0.01;
  s.settings.bend_compliance = 1e-3;
  s.frames = c.frames;
  s.warmup = c.warmup;
  const double end = (c.warmup + c.frames) * s.frame_time;
  const double ramp_start = (c.warmup + 0.7 * c.frames) * s.frame_time;
  const double ramp = std::max(end - ramp_start, 1e-9);
  // Angular speed: `spin` until ramp_start, then rising linearly to `twist` at the end.
  auto omega = [=](double t) { return spin + (twist - spin) * std::clamp((t - ramp_start) / ramp, 0.0, 1.0); };
  auto angle = [=](double t) {
    const double u = std::clamp((t - ramp_start) / ramp, 0.0, 1.0);
    return spin * t + (twist - spin) * 0.5 * u * u * ramp;
  };
  s.bodies.push_back({"ball", icosphere(level, radius), [angle](double t) { return rotation({0, 1, 0}, angle(t)); }});
  s.colliders = [omega, radius](double t, Colliders& col) {
    col.spheres.push_back({{0, 0, 0}, radius, {}, {0, omega(t), 0}});
  };
  s.description = "cloth-ball: " + std::to_string(c.res) + "x" + std::to_string(c.res) +
                  " cloth draped over a spinning ball (" + count_text(s) + ")";
  return std::make_unique<ClothSceneSource>(std::move(s));
}

// A flag on a pole in gusty wind: the left edge is pinned along the pole; the wind blows
// along +x with gusts and a sideways component that travels down the flag, so it
// flutters, and when a gust drops it sags and folds onto itself.
std::unique_ptr<FrameSource> make_flag(Params& p) {
  const ClothCommon c = read_cloth_common(p, 48, 40, 30, 12);
  const double wind = p.number("wind", 10.0);
  const uint32_t segments = p.count32("segments", 12, 3, 100000);
  p.finish();
  const double width = 1.5, height = 1.0, pole = 0.03;
  ClothSceneSpec s;
  cloth_grid(c.res, c.res, {pole + 0.02, 2.3, 0}, {width / (c.res - 1), 0, 0}, {0, -height / (c.res - 1), 0},
             s.cloth, s.cloth_faces);
  perturb(s.cloth, {0, 0, 1}, 1e-3 * height / (c.res - 1), c.seed);
  for (uint32_t j = 0; j < c.res; ++j) s.pins.push_back(j * c.res);
  s.settings.substeps = c.substeps;
  s.settings.friction = 0.1;
  s.settings.thickness = 0.005;
  s.settings.bend_compliance = 1e-4;
  s.settings.damping = 0.05;
  s.settings.drag = 1.0;
  s.frames = c.frames;
  s.warmup = c.warmup;
  s.bodies.push_back({"pole", revolve(capsule_profile(pole, 2.4, 4), segments), [](double) { return Pose{}; }});
  s.colliders = [pole](double, Colliders& col) { col.capsules.push_back({{0, 0, 0}, {0, 2.4, 0}, pole}); };
  s.wind = [wind](double t, dvec3 x) {
    const double gust = 1.0 + 0.6 * std::sin(1.3 * t) + 0.2 * std::sin(4.1 * t + 2.0 * x.x);
    return dvec3{wind * gust, 0.1 * wind * std::sin(0.9 * t + 1.3 * x.x),
                 0.35 * wind * std::sin(2.3 * t - 3.0 * x.x + 1.1 * x.y)};
  };
  s.description = "flag: " + std::to_string(c.res) + "x" + std::to_string(c.res) + " flag in gusty wind (" +
                  count_text(s) + ")";
  return std::make_unique<ClothSceneSource>(std::move(s));
}

// A curtain hit by a ball that swings into it and back. The curtain's top edge is held
// gathered to 60% of its width in pleats, so it hangs in vertical folds; the ball presses
// the folds together and wraps the curtain around itself, and the curtain swings back.
std::unique_ptr<FrameSource> make_sphere_hit(Params& p) {
  const ClothCommon c = read_cloth_common(p, 48, 40, 20, 12);
  const uint32_t level = p.count32("ball_level", 3, 0, 8);
  p.finish();
  const double size = 1.6, radius = 0.3, period = 2.4;
  ClothSceneSpec s;
  cloth_grid(c.res, c.res, {-size / 2, 1.8, 0}, {size / (c.res - 1), 0, 0}, {0, -size / (c.res - 1), 0},
             s.cloth, s.cloth_faces);
  perturb(s.cloth, {0, 0, 1}, 1e-3 * size / (c.res - 1), c.seed);
  const double pleat = 0.6 * size / (c.res - 1);
  for (uint32_t i = 0; i < c.res; ++i)
    s.moved_pins.push_back({i, {0.6 * s.cloth[i].x, s.cloth[i].y, i % 2 ? pleat : -pleat}});
  s.settings.substeps = c.substeps;
  s.settings.friction = 0.3;
  s.settings.thickness = 0.01;
  s.settings.bend_compliance = 1e-4;
  s.frames = c.frames;
  s.warmup = c.warmup;
  const double w = 2 * kPi / period;
  // The ball swings on an arc: forward through the curtain's plane and back, sideways a little.
  auto centre = [w](double t) { return dvec3{0.3 * std::sin(w * t), 0.9, -0.9 * std::cos(w * t)}; };
  auto velocity = [w](double t) { return dvec3{0.3 * w * std::cos(w * t), 0, 0.9 * w * std::sin(w * t)}; };
  s.bodies.push_back({"ball", icosphere(level, radius), [centre](double t) { return translation(centre(t)); }});
  s.colliders = [centre, velocity, radius](double t, Colliders& col) {
    col.spheres.push_back({centre(t), radius, velocity(t), {}});
  };
  s.description = "sphere: " + std::to_string(c.res) + "x" + std::to_string(c.res) +
                  " curtain hit by a swinging ball (" + count_text(s) + ")";
  return std::make_unique<ClothSceneSource>(std::move(s));
}

}  // namespace cdb::scene
