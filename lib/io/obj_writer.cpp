#include "io/obj_writer.h"

#include <cstdio>
#include <memory>

#include "core/error.h"

namespace cdb {

void write_obj_sequence(const FrameSource& source, const std::filesystem::path& out_dir) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) fail(out_dir.string() + ": cannot create directory: " + ec.message());
  const Topology& topology = source.topology();
  std::vector<vec3d> positions;
  for (uint32_t k = 0; k < source.num_frames(); ++k) {
    source.positions(k, positions);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04u.obj", k);
    const std::filesystem::path file = out_dir / name;
    std::unique_ptr<FILE, int (*)(FILE*)> out(std::fopen(file.c_str(), "w"), std::fclose);
    if (!out) fail(file.string() + ": cannot open for writing");
    // %.17g: seventeen significant digits read back to the same double.
    for (const vec3d& p : positions) std::fprintf(out.get(), "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
    for (const Tri& t : topology.faces) std::fprintf(out.get(), "f %u %u %u\n", t.v0 + 1, t.v1 + 1, t.v2 + 1);
    if (std::ferror(out.get()) || std::fclose(out.release()) != 0) fail(file.string() + ": write failed");
  }
}

}  // namespace cdb
