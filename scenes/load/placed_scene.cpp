#include "scenes/load/placed_scene.h"

#include <cmath>
#include <string>

#include "cdbench/core/error.h"

namespace cdb {
namespace {

class PlacedScene final : public FrameSource {
 public:
  PlacedScene(std::unique_ptr<FrameSource> inner, const Placement& p) : inner_(std::move(inner)), p_(p) {}
  const Topology& topology() const override { return inner_->topology(); }
  uint32_t num_frames() const override { return inner_->num_frames(); }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    inner_->positions(k, out);
    for (vec3d& v : out)
      v = {p_.scale * v.x + p_.offset[0], p_.scale * v.y + p_.offset[1], p_.scale * v.z + p_.offset[2]};
  }
  std::string describe() const override {
    char text[160];
    std::snprintf(text, sizeof text, ", scaled by %.6g and moved by (%.6g, %.6g, %.6g)", p_.scale, p_.offset[0],
                  p_.offset[1], p_.offset[2]);
    return inner_->describe() + text;
  }

 private:
  std::unique_ptr<FrameSource> inner_;
  Placement p_;
};

double finite_number(const nlohmann::json& v, const std::string& where) {
  if (!v.is_number() || !std::isfinite(v.get<double>())) fail(where + ": must be a finite number");
  return v.get<double>();
}

}  // namespace

Placement parse_placement(const nlohmann::json& j, const std::string& where) {
  Placement p;
  if (j.contains("placement.scale")) {
    p.scale = finite_number(j["placement.scale"], where + "placement.scale");
    if (!(p.scale > 0)) fail(where + "placement.scale: must be positive");
  }
  if (j.contains("placement.offset")) {
    const nlohmann::json& o = j["placement.offset"];
    const std::string at = where + "placement.offset";
    if (o.is_array()) {
      if (o.size() != 3) fail(at + ": must be a number or [x, y, z]");
      for (size_t a = 0; a < 3; ++a) p.offset[a] = finite_number(o[a], at);
    } else {
      const double d = finite_number(o, at);
      p.offset = {d, d, d};
    }
  }
  return p;
}

std::unique_ptr<FrameSource> place_scene(std::unique_ptr<FrameSource> source, const Placement& placement) {
  if (placement.identity()) return source;
  return std::make_unique<PlacedScene>(std::move(source), placement);
}

}  // namespace cdb
