#include "scenes/load/obj_reader.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <cstdlib>
#include <fstream>
#include <string>

#include "cdbench/core/error.h"

namespace cdb {
namespace {

const char* skip_space(const char* p) {
  while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
  return p;
}

bool ends_token(char c) { return c == '\0' || c == ' ' || c == '\t' || c == '\r' || c == '#'; }

std::string coordinate_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// The first `n` characters of a token, for quoting a malformed one without echoing a line
// of megabytes.
std::string token_text(const char* p) {
  const char* e = p;
  while (!ends_token(*e) && e - p < 24) ++e;
  return std::string(p, e) + (ends_token(*e) ? "" : "...");
}

// A coordinate the pipelines cannot hold: they compute boxes in float, and x beyond
// +-FLT_MAX rounds to infinity. Found while reading, so the error names the line.
void check_coordinates(const double (&c)[3], const std::string& vertex, size_t line_no) {
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  const std::string position =
      " (" + coordinate_text(c[0]) + " " + coordinate_text(c[1]) + " " + coordinate_text(c[2]) + ") on line " + std::to_string(line_no);
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(c[a]))
      fail(vertex + ": non-finite position" + position + " (" + kAxis[a] + " is " + coordinate_text(c[a]) +
           "): every coordinate must be a finite number");
    if (std::fabs(c[a]) > double(std::numeric_limits<float>::max()))
      fail(vertex + ": position beyond float range" + position + " (" + kAxis[a] + " is " + coordinate_text(c[a]) +
           ", float holds magnitudes up to " + coordinate_text(double(std::numeric_limits<float>::max())) +
           "): boxes are computed in float; scale the frames down or move them nearer the origin");
  }
}

}  // namespace

size_t read_obj_file(const std::filesystem::path& file, Topology& topology, std::vector<vec3d>& positions,
                     int64_t frame) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string() + ": cannot open");
  topology.faces.clear();
  positions.clear();
  const std::string in_frame = file.string() + (frame >= 0 ? ": frame " + std::to_string(frame) : std::string());
  size_t polygons = 0, line_no = 0;
  std::string line;
  std::vector<uint32_t> corners;
  while (std::getline(in, line)) {
    ++line_no;
    // A UTF-8 byte-order mark (editors on Windows write one) is not part of the first
    // line: left there, it hid a first `v` line and its vertex was lost.
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    const std::string where = in_frame + (frame >= 0 ? ", line " : ": line ") + std::to_string(line_no);
    const char* p = skip_space(line.c_str());
    if (p[0] == 'v' && (p[1] == ' ' || p[1] == '\t')) {
      double c[3];
      p += 1;
      for (double& x : c) {
        p = skip_space(p);
        char* end = nullptr;
        x = std::strtod(p, &end);
        if (end == p && ends_token(*p)) fail(where + ": a vertex needs 3 coordinates");
        if (end == p || !ends_token(*end))
          fail(where + ": '" + token_text(p) + "' is not a number (a vertex is 'v x y z', each a decimal number)");
        p = end;
      }
      // What may follow x y z: w, or the r g b colours some exporters add; numbers only.
      for (p = skip_space(p); !ends_token(*p); p = skip_space(p)) {
        char* end = nullptr;
        std::strtod(p, &end);
        if (end == p || !ends_token(*end))
          fail(where + ": '" + token_text(p) + "' after the coordinates is not a number");
        p = end;
      }
      check_coordinates(c, in_frame + ", vertex " + std::to_string(positions.size()), line_no);
      positions.push_back({c[0], c[1], c[2]});
    } else if (p[0] == 'f' && (p[1] == ' ' || p[1] == '\t')) {
      corners.clear();
      p = skip_space(p + 1);
      while (*p && *p != '#') {
        long long index = 0;
        const auto [end, ec] = std::from_chars(p, line.c_str() + line.size(), index);
        if (ec != std::errc() || index == 0) fail(where + ": malformed face corner '" + token_text(p) + "'");
        const long long count = static_cast<long long>(positions.size());
        const long long zero_based = index > 0 ? index - 1 : count + index;
        if (zero_based < 0 || zero_based >= count)
          fail(where + ": vertex index " + std::to_string(index) + " out of range (" +
               std::to_string(count) + " vertices so far)");
        corners.push_back(static_cast<uint32_t>(zero_based));
        p = end;
        // Texture and normal indices (v/vt, v//vn, v/vt/vn) are not used, only checked to
        // be indices, so "1x" is not read as 1.
        if (*p == '/')
          while (*p == '/' || *p == '-' || (*p >= '0' && *p <= '9')) ++p;
        if (!ends_token(*p)) fail(where + ": malformed face corner '" + token_text(p) + "'");
        p = skip_space(p);
      }
      if (corners.size() < 3) fail(where + ": a face needs at least 3 corners");
      if (corners.size() > 3) ++polygons;
      for (size_t k = 1; k + 1 < corners.size(); ++k)
        topology.faces.push_back({corners[0], corners[k], corners[k + 1]});
    }
  }
  topology.num_vertices = static_cast<uint32_t>(positions.size());
  if (topology.faces.empty()) fail(file.string() + ": no triangles in this file (malformed or empty mesh)");
  return polygons;
}

}  // namespace cdb
