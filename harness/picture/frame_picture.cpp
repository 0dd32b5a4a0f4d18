#include "harness/picture/frame_picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "harness/picture/face_buffer.h"

namespace cdb {
namespace {

double dot(const vec3d& a, const vec3d& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
vec3d minus(const vec3d& a, const vec3d& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
vec3d cross(const vec3d& a, const vec3d& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The objects' colours, cycled: greys, blues and greens, none near the contact colour.
constexpr std::array<Rgb, 6> kObjectColours = {
    Rgb{165, 175, 190}, Rgb{95, 140, 205}, Rgb{120, 175, 150},
    Rgb{150, 130, 195}, Rgb{90, 170, 185}, Rgb{175, 175, 150}};

// What lights the picture: a quarter of the colour everywhere, the rest by the cosine to a
// light a little above and right of the viewer, so faces square to the view are bright
// and the folds of a surface seen head-on still show.
constexpr double kAmbient = 0.25;

// The scene's vertices projected: the view's right and up around the bounds' centre,
// scaled so the larger extent spans the picture less a small border.
struct Projection {
  ViewBasis basis;
  vec3d centre;
  double scale;
  double half_size;

  ScreenPoint operator()(const vec3d& p) const {
    const vec3d d = minus(p, centre);
    return {float(half_size + scale * dot(d, basis.right)), float(half_size - scale * dot(d, basis.up)),
            float(-scale * dot(d, basis.toward_viewer))};
  }
};

Projection fit_projection(const Topology& topology, const std::vector<vec3d>& positions, PictureView view,
                          uint32_t size) {
  const ViewBasis basis = view_basis(view);
  constexpr double inf = std::numeric_limits<double>::infinity();
  vec3d lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (const Tri& t : topology.faces)
    for (uint32_t v : {t.v0, t.v1, t.v2}) {
      const vec3d& p = positions[v];
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  if (topology.faces.empty()) lo = hi = {0, 0, 0};
  const vec3d centre{(lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2};
  // The extent on the screen: the bounding box's corners projected.
  double extent = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const vec3d p{corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z};
    const vec3d d = minus(p, centre);
    extent = std::max({extent, std::abs(dot(d, basis.right)), std::abs(dot(d, basis.up))});
  }
  const double half_size = size / 2.0;
  const double border = std::max(2.0, size * 0.03);
  return {basis, centre, extent > 0 ? (half_size - border) / extent : 1.0, half_size};
}

// Per face, its object's index (0 for a scene of one object).
std::vector<uint32_t> face_objects(const Topology& topology) {
  std::vector<uint32_t> object(topology.faces.size(), 0);
  for (size_t o = 0; o < topology.objects.size(); ++o) {
    const SceneObject& s = topology.objects[o];
    const size_t end = std::min<size_t>(size_t(s.first_face) + s.num_faces, object.size());
    for (size_t f = s.first_face; f < end; ++f) object[f] = uint32_t(o);
  }
  return object;
}

Rgb shaded(Rgb colour, double light) {
  const auto channel = [light](uint8_t c) { return uint8_t(std::lround(std::clamp(c * light, 0.0, 255.0))); };
  return {channel(colour.r), channel(colour.g), channel(colour.b)};
}

}  // namespace

std::vector<uint8_t> faces_in_pairs(const std::vector<PrimPair>& pairs, size_t num_faces) {
  std::vector<uint8_t> marked(num_faces, 0);
  for (const PrimPair& p : pairs) {
    if (p.a < num_faces) marked[p.a] = 1;
    if (p.b < num_faces) marked[p.b] = 1;
  }
  return marked;
}

RgbImage frame_picture(const Topology& topology, const std::vector<vec3d>& positions,
                       const std::vector<uint8_t>& marked, PictureView view, uint32_t size) {
  const Projection project = fit_projection(topology, positions, view, size);
  std::vector<ScreenPoint> screen(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) screen[v] = project(positions[v]);

  FaceBuffer buffer(size, size);
  const uint32_t num_faces = uint32_t(topology.faces.size());
  for (uint32_t f = 0; f < num_faces; ++f) {
    const Tri& t = topology.faces[f];
    buffer.draw(screen[t.v0], screen[t.v1], screen[t.v2], f);
  }
  // Marked triangles that won no pixel: their centroid's pixel, unless a surface more than
  // two pixels in front of them hides it (a contact lies on or near the surface it touches).
  std::vector<uint8_t> shown(num_faces, 0);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x)
      if (buffer.face(x, y) != kNoFace) shown[buffer.face(x, y)] = 1;
  for (uint32_t f = 0; f < num_faces; ++f) {
    if (!marked[f] || shown[f]) continue;
    const Tri& t = topology.faces[f];
    const ScreenPoint &a = screen[t.v0], &b = screen[t.v1], &c = screen[t.v2];
    const float cx = (a.x + b.x + c.x) / 3, cy = (a.y + b.y + c.y) / 3, depth = (a.depth + b.depth + c.depth) / 3;
    if (cx >= 0 && cy >= 0) buffer.splat(uint32_t(cx), uint32_t(cy), depth, 2.0f, f);
  }

  const std::vector<uint32_t> object = face_objects(topology);
  const ViewBasis& basis = project.basis;
  vec3d light{basis.toward_viewer.x + 0.3 * basis.up.x + 0.2 * basis.right.x,
              basis.toward_viewer.y + 0.3 * basis.up.y + 0.2 * basis.right.y,
              basis.toward_viewer.z + 0.3 * basis.up.z + 0.2 * basis.right.z};
  const double light_length = std::sqrt(dot(light, light));
  light = {light.x / light_length, light.y / light_length, light.z / light_length};

  RgbImage image(size, size, kBackgroundColour);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) {
      const uint32_t f = buffer.face(x, y);
      if (f == kNoFace) continue;
      const Tri& t = topology.faces[f];
      const vec3d n = cross(minus(positions[t.v1], positions[t.v0]), minus(positions[t.v2], positions[t.v0]));
      const double length = std::sqrt(dot(n, n));
      const double lambert = length > 0 ? std::abs(dot(n, light)) / length : 0;
      const Rgb colour = marked[f] ? kContactColour : kObjectColours[object[f] % kObjectColours.size()];
      image.at(x, y) = shaded(colour, kAmbient + (1 - kAmbient) * lambert);
    }
  return image;
}

}  // namespace cdb
