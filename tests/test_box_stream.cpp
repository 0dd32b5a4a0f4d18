// Box streams (io/box_stream.h): per-frame primitive boxes read as a scene. The three
// formats and the .npy header variants, every validation error with the file, frame and box
// it names, and the claim the representation rests on: a box's degenerate face has exactly
// the input box, so a box scene and a mesh scene of triangles with those boxes give every
// pipeline, the oracle and each box knob the same pair sets.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cdbench/oracle/sweep_oracle.h"
#include "cdbench/core/error.h"
#include "cdbench/core/pair_set.h"
#include "scenes/load/box_stream.h"
#include "scenes/load/npy_header.h"
#include "scenes/load/scene.h"
#include "cdbench/pipeline/pipeline.h"
#include "error_of.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A scratch directory, removed at the end; the scene cache points into it.
struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("cdb_box_stream_" + std::to_string(::getpid()));
  Scratch() {
    fs::remove_all(dir);
    fs::create_directories(dir);
    ::setenv("CDBENCH_CACHE", (dir / "cache").c_str(), 1);
  }
  ~Scratch() { fs::remove_all(dir); }
  fs::path sub(const std::string& name) const {
    fs::create_directories(dir / name);
    return dir / name;
  }
};

// Little-endian bytes of each value, whatever the host's order.
std::string le_bytes(const std::vector<double>& values, bool f64) {
  std::string out;
  for (double v : values) {
    const uint64_t bits = f64 ? std::bit_cast<uint64_t>(v) : std::bit_cast<uint32_t>(float(v));
    for (int i = 0; i < (f64 ? 8 : 4); ++i) out.push_back(char((bits >> (8 * i)) & 0xff));
  }
  return out;
}

void write_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

// A .npy file as NumPy writes it: magic, version, header length, the dict padded with
// spaces to a multiple of 64 bytes and ended by a newline, then the data.
std::string npy_bytes(const std::string& dict, int major, const std::string& data) {
  const size_t length_bytes = major == 1 ? 2 : 4, prefix = 8 + length_bytes;
  std::string header = dict;
  while ((prefix + header.size() + 1) % 64) header += ' ';
  header += '\n';
  std::string out("\x93NUMPY", 6);
  out.push_back(char(major));
  out.push_back(0);
  for (size_t i = 0; i < length_bytes; ++i) out.push_back(char((header.size() >> (8 * i)) & 0xff));
  return out + header + data;
}

// Two boxes per frame: they touch at x = 1 (closed bounds: a pair) on frame 0 and move
// apart by k / 4 on frame k.
std::vector<double> two_boxes(int k) {
  const double dx = k / 4.0;
  return {0, 0, 0, 1, 1, 1, 1 + dx, 0.5, 0.25, 2 + dx, 1.5, 0.75};
}

std::vector<vec3d> positions_of(const FrameSource& s, uint32_t k) {
  std::vector<vec3d> p;
  s.positions(k, p);
  return p;
}

TEST(BoxStream, Float32BoxesBecomeDegenerateFacesWhoseBoxIsTheInputBox) {
  Scratch s;
  const fs::path dir = s.sub("f32");
  // Natural order: f2 before f10.
  write_bytes(dir / "f1.boxes", le_bytes(two_boxes(0), false));
  write_bytes(dir / "f10.boxes", le_bytes(two_boxes(2), false));
  write_bytes(dir / "f2.boxes", le_bytes(two_boxes(1), false));
  const Scene scene = open_scene(dir.string(), s.dir);
  const FrameSource& src = *scene.source;
  const Topology& t = src.topology();
  EXPECT_EQ(scene.name, "f32");
  EXPECT_NE(scene.description.find("box stream"), std::string::npos) << scene.description;
  EXPECT_NE(scene.description.find("2 boxes (boxes), 3 frames"), std::string::npos) << scene.description;
  ASSERT_EQ(src.num_frames(), 3u);
  ASSERT_EQ(t.faces.size(), 2u);
  EXPECT_EQ(t.box_faces, 2u);
  EXPECT_EQ(t.num_vertices, 4u);
  EXPECT_TRUE(t.objects.empty());
  EXPECT_EQ(t.faces[1].v0, 2u);
  EXPECT_EQ(t.faces[1].v1, 3u);
  EXPECT_EQ(t.faces[1].v2, 3u);
  for (uint32_t k = 0; k < 3; ++k) {
    std::vector<vec3f> v;
    src.frame(k, v);
    const std::vector<double> want = two_boxes(int(k));
    const MeshView mesh{v.data(), t.faces.data(), uint32_t(t.faces.size())};
    for (uint32_t b = 0; b < 2; ++b) {
      vec4f lo, hi;
      face_box(mesh, b, lo, hi);
      const double* w = want.data() + 6 * b;
      EXPECT_EQ(lo.x, w[0]);
      EXPECT_EQ(lo.y, w[1]);
      EXPECT_EQ(lo.z, w[2]);
      EXPECT_EQ(hi.x, w[3]);
      EXPECT_EQ(hi.y, w[4]);
      EXPECT_EQ(hi.z, w[5]);
    }
  }
  // Touching on the first frame (f1), apart on the others.
  EXPECT_EQ(sweep_oracle_pairs(t, positions_of(src, 0)).size(), 1u);
  EXPECT_TRUE(sweep_oracle_pairs(t, positions_of(src, 1)).empty());
}

TEST(BoxStream, Float64BoxesKeepEveryDigit) {
  Scratch s;
  const fs::path dir = s.sub("f64");
  const std::vector<double> boxes = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  write_bytes(dir / "a.boxes64", le_bytes(boxes, true));
  const std::unique_ptr<FrameSource> src = open_box_stream(dir);
  const std::vector<vec3d> p = positions_of(*src, 0);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].x, 0.1);
  EXPECT_EQ(p[0].z, 0.3);
  EXPECT_EQ(p[1].y, 0.5);
  EXPECT_NE(src->describe().find("(boxes64)"), std::string::npos);
}

TEST(BoxStream, NpyHeaderVariantsReadTheSameBoxes) {
  Scratch s;
  const std::vector<double> boxes = two_boxes(0);
  const std::string f4 = le_bytes(boxes, false), f8 = le_bytes(boxes, true);
  const struct {
    const char* name;
    std::string bytes;
  } variants[] = {
      {"v1_n6_f4", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 6), }", 1, f4)},
      {"v2_n23_f8", npy_bytes("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 2, 3), }", 2, f8)},
      {"v3_no_trailing_comma", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 6)}", 3, f4)},
      {"key_order_and_quotes", npy_bytes("{\"shape\": (2,6), \"fortran_order\": False, \"descr\": \"<f8\"}", 1, f8)},
      {"python2_long", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2L, 6L), }", 1, f4)},
  };
  for (const auto& v : variants) {
    SCOPED_TRACE(v.name);
    const fs::path dir = s.sub(v.name);
    write_bytes(dir / "frame.npy", v.bytes);
    const std::unique_ptr<FrameSource> src = open_box_stream(dir);
    ASSERT_EQ(src->topology().box_faces, 2u);
    const std::vector<vec3d> p = positions_of(*src, 0);
    for (size_t b = 0; b < 2; ++b) {
      EXPECT_EQ(p[2 * b].x, boxes[6 * b + 0]);
      EXPECT_EQ(p[2 * b].y, boxes[6 * b + 1]);
      EXPECT_EQ(p[2 * b].z, boxes[6 * b + 2]);
      EXPECT_EQ(p[2 * b + 1].x, boxes[6 * b + 3]);
      EXPECT_EQ(p[2 * b + 1].y, boxes[6 * b + 4]);
      EXPECT_EQ(p[2 * b + 1].z, boxes[6 * b + 5]);
    }
  }
  const std::string vector_file = npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (7,), }", 1, "");
  NpyHeader h = parse_npy_header(vector_file, "x");
  EXPECT_EQ(h.data_offset, vector_file.size());
  EXPECT_EQ(h.descr, "<f4");
  EXPECT_EQ(shape_text(h.shape), "(7,)");
  h = parse_npy_header(npy_bytes("{'descr': '<f4', 'fortran_order': True, 'shape': (), }", 2, ""), "x");
  EXPECT_TRUE(h.fortran_order);
  EXPECT_EQ(shape_text(h.shape), "()");
}

// The error of opening the box stream in `dir`, whose frame files are `files` (name, bytes).
std::string stream_error(const Scratch& s, const std::string& test,
                         const std::vector<std::pair<std::string, std::string>>& files) {
  const fs::path dir = s.sub(test);
  for (const auto& [name, bytes] : files) write_bytes(dir / name, bytes);
  return error_of([&] { open_box_stream(dir); });
}

// `text` contains `part`, shown in full when not.
::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' lacks '" << part << "'";
}

// A frame name on a directory or a link to a device is refused, not skipped with the later
// frames renumbered (.boxes and .npy alike).
TEST(BoxStream, FrameThatIsNotARegularFileRefused) {
  Scratch s;
  const std::string good = le_bytes(two_boxes(0), false);
  for (const std::string ext : {".boxes", ".npy"}) {
    const fs::path dir = s.sub("odd" + ext.substr(1));
    write_bytes(dir / ("f0" + ext), good);
    write_bytes(dir / ("f2" + ext), good);
    fs::create_directory(dir / ("f1" + ext));
    EXPECT_TRUE(contains(error_of([&] { open_box_stream(dir); }), "f1" + ext + ": this frame is a directory, not a regular file"));
    fs::remove(dir / ("f1" + ext));
    fs::create_symlink("/dev/zero", dir / ("f1" + ext));
    EXPECT_TRUE(contains(error_of([&] { open_box_stream(dir); }), "f1" + ext + ": this frame is a character device"));
  }
}

TEST(BoxStream, RawFrameErrorsNameTheFileFrameAndBox) {
  Scratch s;
  const std::string good = le_bytes(two_boxes(0), false);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  std::vector<double> b = two_boxes(0);
  b[7] = nan;
  const std::string with_nan = le_bytes(b, false);
  b = two_boxes(0);
  b[5] = inf;
  const std::string with_inf = le_bytes(b, true);
  b = two_boxes(0);
  b[6] = 2.5;  // box 1: min.x 2.5 > max.x 2
  const std::string inverted = le_bytes(b, false);

  const fs::path d = s.dir;
  EXPECT_TRUE(contains(stream_error(s, "size", {{"f0.boxes", good + "x"}}),
                       (d / "size" / "f0.boxes").string() +
                           ": frame 0: 49 bytes is not a whole number of boxes (24 bytes each: float32 min.x"));
  EXPECT_TRUE(contains(stream_error(s, "size64b", {{"f0.boxes64", good + "abcd"}}),
                       "f0.boxes64: frame 0: 52 bytes is not a whole number of boxes (48 bytes each: float64"));
  EXPECT_TRUE(contains(stream_error(s, "nan", {{"f0.boxes", good}, {"f1.boxes", with_nan}}),
                       (d / "nan" / "f1.boxes").string() + ": frame 1, box 1: min.y is nan (coordinates must be finite)"));
  EXPECT_TRUE(contains(stream_error(s, "inf", {{"f0.boxes64", with_inf}}),
                       "f0.boxes64: frame 0, box 0: max.z is inf (coordinates must be finite)"));
  EXPECT_TRUE(contains(stream_error(s, "inverted", {{"f0.boxes", good}, {"f1.boxes", good}, {"f2.boxes", inverted}}),
                       "f2.boxes: frame 2, box 1: min.x 2.5 > max.x 2 (min must not exceed max)"));
  EXPECT_TRUE(contains(stream_error(s, "empty", {{"f0.boxes", good}, {"f1.boxes", ""}}),
                       "f1.boxes: frame 1: no boxes (an empty frame)"));
  EXPECT_TRUE(contains(stream_error(s, "count", {{"f0.boxes", good}, {"f1.boxes", good.substr(0, 24)}}),
                       "f1.boxes: frame 1 has 1 boxes, frame 0 has 2 (the box count must stay fixed)"));
  EXPECT_TRUE(contains(stream_error(s, "formats", {{"f0.boxes", good}, {"f1.npy", good}}),
                       "mixes box formats (f0.boxes, f1.npy): one format per stream"));
  EXPECT_TRUE(contains(stream_error(s, "none", {{"notes.txt", "x"}}),
                       "no box frames (.boxes, .boxes64, .npy) in this directory"));
}

TEST(BoxStream, FramesReplacedAfterOpeningNamed) {
  // Every frame had frame 0's count when the stream was opened; a file rewritten since is
  // said to have changed, not compared with itself as "frame 0 has 1 boxes, frame 0 has 2".
  Scratch s;
  const fs::path d = s.sub("replaced");
  write_bytes(d / "f0.boxes", le_bytes(two_boxes(0), false));
  write_bytes(d / "f1.boxes", le_bytes(two_boxes(1), false));
  const auto stream = open_box_stream(d);
  write_bytes(d / "f0.boxes", le_bytes(two_boxes(0), false).substr(0, 24));
  std::string error = error_of([&] { positions_of(*stream, 0); });
  EXPECT_TRUE(contains(error, (d / "f0.boxes").string() +
                                  ": frame 0 changed after the scene was opened: it has 1 boxes, the scene 2 when it "
                                  "was opened"))
      << error;
  EXPECT_FALSE(contains(error, "frame 0 has")) << error;
  write_bytes(d / "f1.boxes", le_bytes(two_boxes(1), false) + le_bytes(two_boxes(1), false));
  error = error_of([&] { positions_of(*stream, 1); });
  EXPECT_TRUE(contains(error, (d / "f1.boxes").string() +
                                  ": frame 1 changed after the scene was opened: it has 4 boxes, the scene 2"))
      << error;
}

TEST(BoxStream, NpyErrorsNameTheFileAndWhatIsWrong) {
  Scratch s;
  const std::string f4 = le_bytes(two_boxes(0), false);
  const auto npy = [&](const std::string& dict, const std::string& data, int major = 1) {
    return std::vector<std::pair<std::string, std::string>>{{"f0.npy", npy_bytes(dict, major, data)}};
  };
  const std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 6), }";
  EXPECT_TRUE(contains(stream_error(s, "magic", {{"f0.npy", f4}}), "f0.npy: frame 0: not a .npy file"));
  EXPECT_TRUE(contains(stream_error(s, "version", npy(header, f4, 4)),
                       "f0.npy: frame 0: .npy format version 4.0 is not supported"));
  EXPECT_TRUE(contains(stream_error(s, "short", npy(header, f4.substr(0, 40))),
                       "f0.npy: frame 0: shape (2, 6) needs more than 40 bytes of data, the file has 40"));
  EXPECT_TRUE(contains(stream_error(s, "long", npy(header, f4 + "xxxx")),
                       "f0.npy: frame 0: shape (2, 6) needs 48 bytes of data, the file has 52"));
  EXPECT_TRUE(contains(stream_error(s, "empty", npy("{'descr': '<f4', 'fortran_order': False, 'shape': (0, 6), }", "")),
                       "f0.npy: frame 0: no boxes (an empty frame)"));
  // Headers over the two boxes' bytes, each wrong in the one way its message names.
  const struct {
    const char* test;
    const char* header;
    const char* message;
  } bad_headers[] = {
      {"big", "{'descr': '>f4', 'fortran_order': False, 'shape': (2, 6), }",
       "f0.npy: frame 0: dtype '>f4': expected '<f4' or '<f8'"},
      {"int", "{'descr': '<i4', 'fortran_order': False, 'shape': (2, 6), }", "dtype '<i4': expected '<f4' or '<f8'"},
      {"fortran", "{'descr': '<f4', 'fortran_order': True, 'shape': (2, 6), }",
       "f0.npy: frame 0: fortran_order is True: expected C order"},
      {"shape", "{'descr': '<f4', 'fortran_order': False, 'shape': (4, 3), }",
       "f0.npy: frame 0: shape (4, 3): expected (N, 6) or (N, 2, 3)"},
      {"colon", "{'descr' '<f4', 'fortran_order': False, 'shape': (2, 6), }",
       "f0.npy: frame 0: malformed .npy header at character 9: expected ':'"},
      {"lacks", "{'descr': '<f4', 'fortran_order': False}", "f0.npy: frame 0: .npy header lacks 'shape'"},
      {"unknown", "{'descr': '<f4', 'order': 'C', 'shape': (2, 6)}", "unknown key 'order'"},
  };
  for (const auto& c : bad_headers) EXPECT_TRUE(contains(stream_error(s, c.test, npy(c.header, f4)), c.message));
  EXPECT_TRUE(contains(stream_error(s, "truncated", {{"f0.npy", npy_bytes(header, 1, f4).substr(0, 30)}}),
                       "f0.npy: frame 0: truncated .npy header (118 header bytes announced, 20 in the file)"));
  // The values are checked whatever the container.
  std::vector<double> b = two_boxes(0);
  b[1] = 3;
  EXPECT_TRUE(contains(stream_error(s, "values", npy("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 2, 3), }",
                                                     le_bytes(b, true))),
                       "f0.npy: frame 0, box 0: min.y 3 > max.y 1"));
}

TEST(BoxStream, SceneDirectoriesAndDescriptorsTellBoxesFromMeshes) {
  Scratch s;
  const fs::path mixed = s.sub("mixed");
  write_bytes(mixed / "f0.boxes", le_bytes(two_boxes(0), false));
  std::ofstream(mixed / "f0.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_TRUE(contains(error_of([&] { open_scene(mixed.string(), s.dir); }),
                       mixed.string() + ": mixes box frames (f0.boxes) and mesh frames (f0.obj)"));
  const fs::path meshes = s.sub("meshes");
  std::ofstream(meshes / "f0.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const fs::path boxes = s.sub("boxes");
  write_bytes(boxes / "f0.boxes", le_bytes(two_boxes(0), false));
  const auto descriptor = [&](const json& j) {
    const fs::path f = s.dir / "scene.json";
    std::ofstream(f) << j.dump();
    return f.string();
  };
  // "frames" reads either kind, "boxes" only box frames; both relative to the descriptor.
  EXPECT_EQ(open_scene(descriptor({{"frames", "boxes"}}), s.dir).source->topology().box_faces, 2u);
  EXPECT_EQ(open_scene(descriptor({{"boxes", "boxes"}}), s.dir).source->topology().box_faces, 2u);
  EXPECT_EQ(open_scene(descriptor({{"frames", "meshes"}}), s.dir).source->topology().box_faces, 0u);
  const std::string file = (s.dir / "scene.json").string();
  EXPECT_TRUE(contains(error_of([&] { open_scene(descriptor({{"boxes", "meshes"}}), s.dir); }),
                       file + ": /boxes: " + meshes.string() + ": no box frames"));
  EXPECT_TRUE(contains(error_of([&] { open_scene(descriptor({{"boxes", "nowhere"}}), s.dir); }),
                       file + ": /boxes: " + (s.dir / "nowhere").string() + " is not a directory"));
  EXPECT_TRUE(contains(error_of([&] { open_scene(descriptor({{"boxes", 3}}), s.dir); }),
                       file + ": /boxes: must be a string (a directory)"));
  EXPECT_TRUE(contains(error_of([&] { open_scene(descriptor({{"boxes", "boxes"}, {"frames", "meshes"}}), s.dir); }),
                       file + ": needs exactly one of"));
  EXPECT_TRUE(contains(
      error_of([&] { open_scene(descriptor({{"parts", {{{"name", "p"}, {"boxes", "boxes"}, {"frames", "meshes"}}}}}), s.dir); }),
      file + ": /parts/0: needs exactly one of generator, animation, keyframes, crowd, frames, boxes, mesh"));
}


// The same pair set, or what differs.
::testing::AssertionResult same_pairs(const std::vector<PrimPair>& expected, const std::vector<PrimPair>& actual) {
  const PairSetDiff d = diff_pair_sets(expected, actual);
  if (d.equal()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << d.missing_count << " of " << expected.size() << " pairs missing, "
                                       << d.unexpected_count << " unexpected";
}

// Random small triangles on a 1/16 grid (exact in float and double, so boxes touch exactly
// and closed bounds matter), drifting by a grid step per frame.
std::vector<std::vector<vec3d>> drifting_triangles(uint32_t triangles, uint32_t frames) {
  uint64_t state = 12345;
  const auto next = [&](int range) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return int((state >> 33) % uint64_t(range));
  };
  std::vector<vec3d> base(3 * size_t(triangles)), drift(triangles);
  for (uint32_t t = 0; t < triangles; ++t) {
    const vec3d c{next(48) / 16.0, next(48) / 16.0, next(48) / 16.0};
    for (int k = 0; k < 3; ++k) base[3 * t + k] = {c.x + next(5) / 16.0, c.y + next(5) / 16.0, c.z + next(5) / 16.0};
    drift[t] = {(next(3) - 1) / 16.0, (next(3) - 1) / 16.0, (next(3) - 1) / 16.0};
  }
  std::vector<std::vector<vec3d>> out(frames);
  for (uint32_t f = 0; f < frames; ++f)
    for (size_t v = 0; v < base.size(); ++v) {
      const vec3d d = drift[v / 3];
      out[f].push_back({base[v].x + f * d.x, base[v].y + f * d.y, base[v].z + f * d.z});
    }
  return out;
}

// The triangles as OBJ frames and their boxes as .boxes frames of the same scene.
void write_both(const std::vector<std::vector<vec3d>>& frames, const fs::path& meshes, const fs::path& boxes) {
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::vector<vec3d>& v = frames[f];
    const std::string name = std::string("frame_").append(std::to_string(f));
    std::ofstream obj(meshes / (name + ".obj"));
    char line[128];
    for (const vec3d& p : v) {
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
      obj << line;
    }
    std::vector<double> b;
    for (size_t t = 0; t < v.size() / 3; ++t) {
      obj << "f " << 3 * t + 1 << " " << 3 * t + 2 << " " << 3 * t + 3 << "\n";
      const vec3d p = v[3 * t], q = v[3 * t + 1], r = v[3 * t + 2];
      for (const double c : {std::min({p.x, q.x, r.x}), std::min({p.y, q.y, r.y}), std::min({p.z, q.z, r.z}),
                             std::max({p.x, q.x, r.x}), std::max({p.y, q.y, r.y}), std::max({p.z, q.z, r.z})})
        b.push_back(c);
    }
    write_bytes(boxes / (name + ".boxes"), le_bytes(b, false));
  }
}

// Each frame's pairs of the configured pipeline on `scene`.
std::vector<std::vector<PrimPair>> pairs_per_frame(const PipelineConfig& config, const FrameSource& scene) {
  const std::unique_ptr<Pipeline> pipeline = make_pipeline(config);
  pipeline->set_topology(scene.topology());
  std::vector<std::vector<PrimPair>> out;
  for (uint32_t f = 0; f < scene.num_frames(); ++f) {
    pipeline->run_frame(positions_of(scene, f));
    out.push_back(pipeline->sorted_pairs());
  }
  return out;
}

TEST(BoxStream, BoxSceneGivesTheMeshScenesPairsInEveryPipelineAndKnob) {
  Scratch s;
  const fs::path meshes = s.sub("meshes"), boxes = s.sub("boxes");
  const uint32_t frames = 4;
  write_both(drifting_triangles(300, frames), meshes, boxes);
  const Scene mesh = open_scene(meshes.string(), s.dir), box = open_scene(boxes.string(), s.dir);
  ASSERT_EQ(box.source->topology().box_faces, 300u);
  ASSERT_EQ(mesh.source->topology().box_faces, 0u);
  size_t total = 0;
  for (uint32_t f = 0; f < frames; ++f) {
    const std::vector<PrimPair> exact = sweep_oracle_pairs(mesh.source->topology(), positions_of(*mesh.source, f));
    EXPECT_TRUE(same_pairs(exact, sweep_oracle_pairs(box.source->topology(), positions_of(*box.source, f))))
        << "frame " << f;
    total += exact.size();
  }
  EXPECT_GT(total, 100u);  // the comparison has pairs to compare
  // Every knob goes through face_box, whose box is the same for a triangle and for its box:
  // the pair sets agree with the mesh scene's under each, and without knobs with the oracle.
  struct Knob {
    const char* name;
    std::function<void(PipelineConfig&)> set;
  };
  const std::vector<Knob> knobs = {
      {"plain", [](PipelineConfig&) {}},
      {"margin", [](PipelineConfig& c) { c.boxes.margin = 0.03f; }},
      {"swept", [](PipelineConfig& c) { c.boxes.swept = true; }},
      {"q16", [](PipelineConfig& c) { c.boxes.precision = BoxPrecision::q16; }},
      {"fp64 margin",
       [](PipelineConfig& c) {
         c.boxes.precision = BoxPrecision::fp64;
         c.boxes.margin = 0.03f;
       }},
  };
  for (const std::string& name : pipeline_names())
    for (const Knob& knob : knobs) {
      SCOPED_TRACE(name + ", " + knob.name);
      PipelineConfig c;
      c.device = "cpu";
      c.name = name;
      knob.set(c);
      const auto from_boxes = pairs_per_frame(c, *box.source), from_meshes = pairs_per_frame(c, *mesh.source);
      for (uint32_t f = 0; f < frames; ++f) {
        EXPECT_TRUE(same_pairs(from_meshes[f], from_boxes[f])) << "frame " << f;
        if (std::string(knob.name) == "plain") {
          EXPECT_TRUE(same_pairs(sweep_oracle_pairs(box.source->topology(), positions_of(*box.source, f)),
                                 from_boxes[f]))
              << "frame " << f;
        }
      }
    }
}

TEST(BoxStream, PartsOfBoxesAndMeshFramesWithDeclaredQueries) {
  Scratch s;
  const fs::path meshes = s.sub("cloth"), boxes = s.sub("particles");
  write_both(drifting_triangles(40, 3), meshes, boxes);
  const json d = {{"parts", {{{"name", "cloth"}, {"frames", "cloth"}}, {{"name", "particles"}, {"boxes", "particles"}}}},
                  {"queries", {{"self", {"cloth"}}, {"inter", json::array({json::array({"cloth", "particles"})})}}}};
  const fs::path file = s.dir / "parts.json";
  std::ofstream(file) << d.dump();
  const Scene scene = open_scene(file.string(), s.dir);
  const Topology& t = scene.source->topology();
  ASSERT_EQ(t.objects.size(), 2u);
  EXPECT_EQ(t.objects[0].name, "cloth");
  EXPECT_EQ(t.objects[1].name, "particles");
  EXPECT_EQ(t.objects[1].first_face, 40u);
  EXPECT_EQ(t.box_faces, 40u);
  EXPECT_TRUE(t.queries.declared);
  EXPECT_NE(scene.description.find("box stream"), std::string::npos);
  // Each particle box is its cloth triangle's box: the inter query pairs every triangle with
  // its own box, and no particle-particle pair (no self query on particles) is reported.
  const std::vector<PrimPair> pairs = sweep_oracle_pairs(t, positions_of(*scene.source, 1));
  size_t own = 0;
  for (const PrimPair& p : pairs) {
    EXPECT_LT(std::min(p.a, p.b), 40u);
    own += std::max(p.a, p.b) == std::min(p.a, p.b) + 40;
  }
  EXPECT_EQ(own, 40u);
  for (const std::string& name : pipeline_names()) {
    SCOPED_TRACE(name);
    PipelineConfig c;
    c.device = "cpu";
    c.name = name;
    const auto got = pairs_per_frame(c, *scene.source);
    for (uint32_t f = 0; f < scene.source->num_frames(); ++f)
      EXPECT_TRUE(same_pairs(sweep_oracle_pairs(t, positions_of(*scene.source, f)), got[f])) << "frame " << f;
  }
}

}  // namespace
}  // namespace cdb::test
