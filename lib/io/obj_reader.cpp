#include "io/obj_reader.h"

#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/error.h"

namespace cdb {
namespace {

const char* skip_space(const char* p) {
  while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
  return p;
}

}  // namespace

size_t read_obj_file(const std::filesystem::path& file, Topology& topology, std::vector<vec3d>& positions) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string() + ": cannot open");
  topology.faces.clear();
  positions.clear();
  size_t polygons = 0, line_no = 0;
  std::string line;
  std::vector<uint32_t> corners;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = file.string() + ": line " + std::to_string(line_no);
    const char* p = skip_space(line.c_str());
    if (p[0] == 'v' && (p[1] == ' ' || p[1] == '\t')) {
      double c[3];
      p += 1;
      for (double& x : c) {
        p = skip_space(p);
        char* end = nullptr;
        errno = 0;
        x = std::strtod(p, &end);
        if (end == p) fail(where + ": a vertex needs 3 coordinates");
        p = end;
      }
      positions.push_back({c[0], c[1], c[2]});
    } else if (p[0] == 'f' && (p[1] == ' ' || p[1] == '\t')) {
      corners.clear();
      p = skip_space(p + 1);
      while (*p) {
        long long index = 0;
        const auto [end, ec] = std::from_chars(p, line.c_str() + line.size(), index);
        if (ec != std::errc() || index == 0) fail(where + ": malformed face corner");
        const long long count = static_cast<long long>(positions.size());
        const long long zero_based = index > 0 ? index - 1 : count + index;
        if (zero_based < 0 || zero_based >= count)
          fail(where + ": vertex index " + std::to_string(index) + " out of range (" +
               std::to_string(count) + " vertices so far)");
        corners.push_back(static_cast<uint32_t>(zero_based));
        p = end;
        while (*p && *p != ' ' && *p != '\t' && *p != '\r') ++p;  // texture/normal indices
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
