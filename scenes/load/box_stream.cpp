#include "scenes/load/box_stream.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "cdbench/core/error.h"
#include "scenes/load/input_files.h"
#include "scenes/load/npy_header.h"

namespace cdb {
namespace {

constexpr const char* kFieldNames[6] = {"min.x", "min.y", "min.z", "max.x", "max.y", "max.z"};

std::string number_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

// Where the coordinates start, their width and the box count, from the format's framing.
struct Layout {
  size_t offset = 0;
  bool f64 = false;
  uint64_t boxes = 0;
};

Layout npy_layout(const std::string& bytes, const std::string& where) {
  const NpyHeader h = parse_npy_header(bytes, where);
  Layout l;
  l.offset = h.data_offset;
  if (h.descr == "<f4") l.f64 = false;
  else if (h.descr == "<f8") l.f64 = true;
  else fail(where + ": dtype '" + h.descr + "': expected '<f4' or '<f8' (little-endian float32 or float64)");
  if (h.fortran_order) fail(where + ": fortran_order is True: expected C order (numpy.ascontiguousarray)");
  const bool flat = h.shape.size() == 2 && h.shape[1] == 6;
  const bool corners = h.shape.size() == 3 && h.shape[1] == 2 && h.shape[2] == 3;
  if (!flat && !corners) fail(where + ": shape " + shape_text(h.shape) + ": expected (N, 6) or (N, 2, 3)");
  l.boxes = h.shape[0];
  const uint64_t record = l.f64 ? 48 : 24, data = bytes.size() - l.offset;
  if (l.boxes > data / record || data != l.boxes * record)
    fail(where + ": shape " + shape_text(h.shape) + " needs " +
         (l.boxes > data / record ? "more than " + std::to_string(data) : std::to_string(l.boxes * record)) +
         " bytes of data, the file has " + std::to_string(data));
  return l;
}

// One frame's boxes, 6 coordinates each in the order above, widened to double; `frame`
// is only for messages.
void read_box_frame(const std::filesystem::path& file, uint32_t frame, std::vector<double>& boxes) {
  const std::string where = file.string() + ": frame " + std::to_string(frame);
  const std::string bytes = read_file(file);
  Layout l;
  if (lower_extension(file) == ".npy") {
    l = npy_layout(bytes, where);
  } else {
    l.f64 = lower_extension(file) == ".boxes64";
    const size_t record = l.f64 ? 48 : 24;
    if (bytes.size() % record)
      fail(where + ": " + std::to_string(bytes.size()) + " bytes is not a whole number of boxes (" +
           std::to_string(record) + " bytes each: " + (l.f64 ? "float64" : "float32") +
           " min.x min.y min.z max.x max.y max.z)");
    l.boxes = bytes.size() / record;
  }
  if (l.boxes == 0) fail(where + ": no boxes (an empty frame)");
  // Two vertices per box, numbered in 32 bits.
  if (l.boxes > UINT32_MAX / 2)
    fail(where + ": " + std::to_string(l.boxes) + " boxes exceed 32-bit vertex indices (2 per box)");
  boxes.resize(l.boxes * 6);
  for (size_t i = 0; i < boxes.size(); ++i) {
    const uint64_t bits = little_endian(bytes.data() + l.offset + i * (l.f64 ? 8 : 4), l.f64 ? 8 : 4);
    boxes[i] = l.f64 ? std::bit_cast<double>(bits) : std::bit_cast<float>(uint32_t(bits));
  }
  const double float_max = std::numeric_limits<float>::max();
  for (size_t b = 0; b < l.boxes; ++b) {
    const double* c = boxes.data() + 6 * b;
    const auto refuse = [&](int a, const std::string& why) {
      fail(where + ", box " + std::to_string(b) + ": " + kFieldNames[a] + why);
    };
    for (int a = 0; a < 6; ++a)
      if (!std::isfinite(c[a])) refuse(a, " is " + number_text(c[a]) + " (coordinates must be finite)");
    // The pipelines hold boxes in float: past +-FLT_MAX a corner rounds to infinity, which
    // was found only after frame 0 ran; refused here, before any frame is timed.
    for (int a = 0; a < 6; ++a)
      if (std::fabs(c[a]) > float_max)
        refuse(a, " is " + number_text(c[a]) + ", beyond float range (magnitudes up to " + number_text(float_max) +
                      "): boxes are computed in float; scale the boxes down or move them nearer the origin");
    for (int a = 0; a < 3; ++a)
      if (c[a] > c[a + 3])
        refuse(a, " " + number_text(c[a]) + " > " + kFieldNames[a + 3] + " " + number_text(c[a + 3]) +
                      " (min must not exceed max)");
  }
}

class BoxStream final : public FrameSource {
 public:
  explicit BoxStream(const std::filesystem::path& dir) : dir_(dir) {
    files_ = frame_files(dir, is_box_frame_file);
    if (files_.empty()) fail(dir.string() + ": no box frames (.boxes, .boxes64, .npy) in this directory");
    for (const auto& f : files_)
      if (lower_extension(f) != lower_extension(files_[0]))
        fail(dir.string() + ": mixes box formats (" + files_[0].filename().string() + ", " +
             f.filename().string() + "): one format per stream");
    std::vector<double> boxes;
    read_box_frame(files_[0], 0, boxes);
    const uint32_t n = uint32_t(boxes.size() / 6);
    topology_.faces.resize(n);
    for (uint32_t i = 0; i < n; ++i) topology_.faces[i] = {2 * i, 2 * i + 1, 2 * i + 1};
    topology_.num_vertices = 2 * n;
    topology_.box_faces = n;
    // Every frame is read once here, so a bad frame stops the program before the first
    // one is timed (as io/obj_sequence.h does).
    std::vector<vec3d> positions;
    for (uint32_t k = 1; k < files_.size(); ++k) this->positions(k, positions);
    opened_ = true;
  }
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return uint32_t(files_.size()); }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    std::vector<double> boxes;
    read_box_frame(files_.at(k), k, boxes);
    const size_t n = boxes.size() / 6;
    // Every frame had frame 0's box count when the scene was opened, so a frame that has
    // not now was replaced since (frame 0 itself too): said so, with the file, rather than
    // as a count against frame 0's.
    if (opened_ && n != topology_.box_faces)
      fail(files_[k].string() + ": frame " + std::to_string(k) + " changed after the scene was opened: it has " +
           std::to_string(n) + " boxes, the scene " + std::to_string(topology_.box_faces) +
           " when it was opened; the box frame files were replaced while they were read: write them before the "
           "run starts");
    if (n != topology_.box_faces)
      fail(files_[k].string() + ": frame " + std::to_string(k) + " has " + std::to_string(n) + " boxes, frame 0 has " +
           std::to_string(topology_.box_faces) + " (the box count must stay fixed)");
    out.resize(2 * n);
    for (size_t i = 0; i < n; ++i) {
      const double* c = boxes.data() + 6 * i;
      out[2 * i] = {c[0], c[1], c[2]};
      out[2 * i + 1] = {c[3], c[4], c[5]};
    }
  }
  std::string describe() const override {
    const std::string ext = lower_extension(files_[0]);
    return "box stream " + dir_.string() + ": " + std::to_string(topology_.box_faces) + " boxes (" + ext.substr(1) +
           "), " + std::to_string(files_.size()) + " frames";
  }

 private:
  std::filesystem::path dir_;
  std::vector<std::filesystem::path> files_;
  Topology topology_;
  bool opened_ = false;  // every frame checked against frame 0
};

}  // namespace

bool is_box_frame_file(const std::filesystem::path& file) {
  const std::string ext = lower_extension(file);
  return ext == ".boxes" || ext == ".boxes64" || ext == ".npy";
}

std::unique_ptr<FrameSource> open_box_stream(const std::filesystem::path& dir) {
  return std::make_unique<BoxStream>(dir);
}

}  // namespace cdb
