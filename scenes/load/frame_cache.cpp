#include "scenes/load/frame_cache.h"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <system_error>

#include "cdbench/core/build_info.h"
#include "cdbench/core/content_hash.h"
#include "cdbench/core/error.h"
#include "scenes/load/archive_cache.h"
#include "scenes/load/replace_file.h"

namespace cdb {
namespace {

// This binary's identity: a rebuilt cdbench may simulate differently, even at one sha.
std::string binary_identity() {
  const std::string sha = build_info().git_sha;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return sha;
  const auto size = std::filesystem::file_size(exe, ec);
  const auto time = std::filesystem::last_write_time(exe, ec);
  return ec ? sha : sha + "/" + std::to_string(size) + "/" + std::to_string(time.time_since_epoch().count());
}

// 03: a checksum of the positions (02 had none, 01 held floats).
constexpr char kMagic[8] = {'c', 'd', 'b', 'f', 'r', 'm', '0', '3'};

struct FrameHeader {
  char magic[8];
  uint32_t frame, num_vertices;
  // ContentHash of the positions' bytes: a file overwritten with other finite numbers (a
  // copy from another scene, a disk fault) reads whole and finite, and only this tells.
  uint64_t checksum;
};
static_assert(sizeof(FrameHeader) == 24, "the header is written as raw bytes");

uint64_t positions_checksum(const std::vector<vec3d>& v) {
  ContentHash h;
  h.add_bytes(v.data(), v.size() * sizeof(vec3d));
  return h.value();
}

class DiskCachedFrames final : public FrameSource {
 public:
  DiskCachedFrames(std::unique_ptr<FrameSource> source, std::filesystem::path dir)
      : source_(std::move(source)), dir_(std::move(dir)) {}
  const Topology& topology() const override { return source_->topology(); }
  uint32_t num_frames() const override { return source_->num_frames(); }
  std::string describe() const override { return source_->describe(); }

  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    const std::filesystem::path file = dir_ / ("frame_" + std::to_string(k) + ".f64");
    const std::string why = read(file, k, out);
    if (why.empty()) return;
    if (why != kAbsent)
      std::fprintf(stderr, "cdbench: cached frame %s %s; simulating the frame again\n", file.c_str(), why.c_str());
    source_->positions(k, out);
    write(file, k, out);
  }

 private:
  static constexpr const char* kAbsent = "absent";

  // "" when `file` holds frame k whole and unchanged, else why not (kAbsent: no file yet).
  std::string read(const std::filesystem::path& file, uint32_t k, std::vector<vec3d>& out) const {
    std::ifstream in(file, std::ios::binary);
    if (!in) return kAbsent;
    FrameHeader h{};
    const uint32_t n = topology().num_vertices;
    if (!in.read(reinterpret_cast<char*>(&h), sizeof h) || std::string(h.magic, 8) != std::string(kMagic, 8))
      return "is not a frame file of this version";
    if (h.frame != k || h.num_vertices != n) return "holds another frame or vertex count";
    out.resize(n);
    if (!in.read(reinterpret_cast<char*>(out.data()), std::streamsize(n * sizeof(vec3d))) || in.peek() != EOF)
      return "has another size than its header says";
    if (positions_checksum(out) != h.checksum) return "does not match its checksum (changed since it was written)";
    for (const vec3d& p : out)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return "holds a non-finite position";
    return {};
  }

  // Best effort: a cache that cannot be written costs time, never a result.
  void write(const std::filesystem::path& file, uint32_t k, const std::vector<vec3d>& v) const {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    FrameHeader h{};
    std::copy(kMagic, kMagic + 8, h.magic);
    h.frame = k;
    h.num_vertices = uint32_t(v.size());
    h.checksum = positions_checksum(v);
    const std::string failed = replace_file(file, [&](std::ostream& os) {
      os.write(reinterpret_cast<const char*>(&h), sizeof h);
      os.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(vec3d)));
    });
    if (!failed.empty()) warn_once();
  }

  void warn_once() const {
    std::call_once(warned_, [&] {
      std::fprintf(stderr, "cdbench: cannot write the frame cache %s; frames are simulated each run\n",
                   dir_.c_str());
    });
  }

  std::unique_ptr<FrameSource> source_;
  std::filesystem::path dir_;
  mutable std::once_flag warned_;
};

}  // namespace

std::filesystem::path frame_cache_dir() {
  if (const char* off = std::getenv("CDBENCH_FRAME_CACHE"); off && std::string(off) == "off") return {};
  try {
    return scene_cache_dir();
  } catch (const Error&) {
    return {};  // nowhere to keep frames: simulate every run
  }
}

std::unique_ptr<FrameSource> cache_frames(std::unique_ptr<FrameSource> source, const std::string& identity,
                                          const std::filesystem::path& dir, uint64_t max_bytes) {
  const uint64_t bytes = uint64_t(source->topology().num_vertices) * sizeof(vec3d) * source->num_frames();
  if (dir.empty() || bytes > max_bytes) return source;
  const std::string key = identity + "\n" + binary_identity();
  ContentHash h;
  h.add_bytes(key.data(), key.size());
  return std::make_unique<DiskCachedFrames>(std::move(source), dir / "frames" / hash_hex(h.value()));
}

}  // namespace cdb
