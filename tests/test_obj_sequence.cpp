// Directories of OBJ frames: natural frame order, and every frame checked when the
// directory is opened (before any frame is timed), with errors naming file, frame and field.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "scenes/load/input_files.h"
#include "scenes/load/obj_sequence.h"
#include "scenes/load/replace_file.h"

namespace cdb::test {
namespace {

namespace fs = std::filesystem;

class FrameDir {
 public:
  FrameDir() : dir_(fs::temp_directory_path() / ("cdb_obj_sequence_" + std::to_string(::getpid()))) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~FrameDir() { fs::remove_all(dir_); }
  const fs::path& path() const { return dir_; }
  // Two triangles over four vertices; the last vertex's z is `z` (text, so "nan" fits).
  void write(const std::string& name, const std::string& z, bool extra_triangle = false) const {
    std::ofstream os(dir_ / name);
    os << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 " << z << "\nf 1 2 3\nf 1 2 4\n";
    if (extra_triangle) os << "f 2 3 4\n";
  }

 private:
  fs::path dir_;
};

// f<k>.obj, built by appending (GCC 12 warns falsely on "f" + std::string).
std::string frame_name(int k) { return std::string("f").append(std::to_string(k)).append(".obj"); }

std::string error_of(const fs::path& dir) {
  try {
    open_mesh_sequence(dir);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// What a directory holds besides `keep`.
std::vector<std::string> others(const fs::path& dir, const std::string& keep) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename() != keep) names.push_back(e.path().filename().string());
  return names;
}

// replace_file: the file whole in place and no temporary left; a write that cannot start
// (a missing directory) and a rename that cannot land (a directory in the way) each name the
// file and the system's reason, and leave no temporary either.
TEST(ReplaceFile, WholeFileOrANamedFailureAndNoTemporary) {
  FrameDir d;
  const fs::path file = d.path() / "status.json";
  EXPECT_EQ(replace_file(file, [](std::ostream& os) { os << "first\n"; }), "");
  EXPECT_EQ(replace_file(file, [](std::ostream& os) { os << "second\n"; }), "");
  std::ifstream in(file);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_EQ(text, "second\n");
  EXPECT_TRUE(others(d.path(), "status.json").empty());

  const fs::path missing = d.path() / "no-such-dir" / "frame.bin";
  EXPECT_EQ(replace_file(missing, [](std::ostream& os) { os << "x"; }),
            missing.string() + ": write failed: No such file or directory");

  const fs::path blocked = d.path() / "blocked";
  fs::create_directories(blocked / "inside");
  const std::string failed = replace_file(blocked, [](std::ostream& os) { os << "x"; });
  EXPECT_EQ(failed.rfind(blocked.string() + ": cannot move the written file into place: ", 0), 0u) << failed;
  EXPECT_EQ(others(d.path(), "status.json"), std::vector<std::string>{"blocked"});
}

TEST(NaturalOrder, DigitRunsCompareByValue) {
  EXPECT_TRUE(natural_less("f2.obj", "f10.obj"));
  EXPECT_FALSE(natural_less("f10.obj", "f2.obj"));
  EXPECT_TRUE(natural_less("frame_0009.obj", "frame_0010.obj"));
  EXPECT_TRUE(natural_less("a9b", "a10a"));
  EXPECT_TRUE(natural_less("f", "f0"));  // a prefix first
  EXPECT_TRUE(natural_less("a.obj", "b.obj"));
  // Longer than any integer type: still by value.
  EXPECT_TRUE(natural_less("f99999999999999999999999", "f100000000000000000000000"));
  // Equal by value, different text: still a strict, total order.
  EXPECT_NE(natural_less("f01", "f1"), natural_less("f1", "f01"));
  EXPECT_FALSE(natural_less("f1", "f1"));
}

TEST(NaturalOrder, SortsFrameNames) {
  std::vector<std::string> names = {"f10", "f0", "f11", "f2", "f1"};
  std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) { return natural_less(a, b); });
  EXPECT_EQ(names, (std::vector<std::string>{"f0", "f1", "f2", "f10", "f11"}));
}

TEST(MeshSequence, FramesInNaturalOrder) {
  FrameDir dir;
  for (int k : {0, 1, 2, 10, 11}) dir.write(frame_name(k), std::to_string(k));
  const auto seq = open_mesh_sequence(dir.path());
  ASSERT_EQ(seq->num_frames(), 5u);
  std::vector<vec3f> v;
  const float expected_z[] = {0, 1, 2, 10, 11};
  for (uint32_t k = 0; k < 5; ++k) {
    seq->frame(k, v);
    ASSERT_EQ(v.size(), 4u);
    EXPECT_EQ(v[3].z, expected_z[k]) << "frame " << k;
  }
}

TEST(MeshSequence, NonFiniteFrameFoundWhenOpened) {
  FrameDir dir;
  for (int k : {0, 1, 2, 10}) dir.write(frame_name(k), std::to_string(k));
  dir.write("f10.obj", "inf");
  const std::string error = error_of(dir.path());
  EXPECT_NE(error.find("f10.obj: frame 3, vertex 3: non-finite position"), std::string::npos) << error;
}

TEST(MeshSequence, ChangedCountsFoundWhenOpened) {
  FrameDir dir;
  dir.write("f0.obj", "0");
  dir.write("f1.obj", "1");
  dir.write("f2.obj", "2", true);
  std::string error = error_of(dir.path());
  EXPECT_NE(error.find("f2.obj: frame 2 has 3 triangles, frame 0 has 2"), std::string::npos) << error;
  // Same triangles, one vertex more.
  dir.write("f2.obj", "2\nv 5 5 5");
  error = error_of(dir.path());
  EXPECT_NE(error.find("f2.obj: frame 2 has 5 vertices, frame 0 has 4"), std::string::npos) << error;
}

TEST(MeshSequence, FramesReplacedAfterOpeningNamed) {
  // Every frame matched frame 0 when the directory was opened; a file rewritten since is
  // said to have changed, not compared with itself as "frame 0 has 3, frame 0 has 2".
  FrameDir dir;
  dir.write("f0.obj", "0");
  dir.write("f1.obj", "1");
  const auto seq = open_mesh_sequence(dir.path());
  std::vector<vec3d> positions;
  dir.write("f0.obj", "0", true);
  std::string error;
  try {
    seq->positions(0, positions);
  } catch (const Error& e) {
    error = e.what();
  }
  EXPECT_NE(error.find((dir.path() / "f0.obj").string() +
                       ": frame 0 changed after the scene was opened: it has 3 triangles and 4 vertices, the "
                       "scene 2 and 4 when the scene was opened"),
            std::string::npos)
      << error;
  EXPECT_EQ(error.find("frame 0 has"), std::string::npos) << error;
  // Same counts, other faces.
  std::ofstream(dir.path() / "f1.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 2 3 4\n";
  error.clear();
  try {
    seq->positions(1, positions);
  } catch (const Error& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("f1.obj: frame 1 changed after the scene was opened: it has other faces than it had when"),
            std::string::npos)
      << error;
}

TEST(MeshSequence, ByteOrderMarkBeforeTheFirstVertex) {
  FrameDir dir;
  dir.write("f0.obj", "0");
  {
    std::ofstream os(dir.path() / "f1.obj");
    os << "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n";
  }
  const auto seq = open_mesh_sequence(dir.path());
  ASSERT_EQ(seq->num_frames(), 2u);
  std::vector<vec3f> v;
  seq->frame(1, v);
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(v[3].z, 1.0f);
}

// An entry with a frame's name that is not a file is refused, naming it, rather than
// skipped with the later frames renumbered.
TEST(MeshSequence, FrameThatIsNotARegularFileRefused) {
  for (const std::string kind : {"directory", "fifo", "device"}) {
    FrameDir dir;
    for (int k : {0, 2}) dir.write(frame_name(k), std::to_string(k));
    const fs::path odd = dir.path() / "f1.obj";
    if (kind == "directory") fs::create_directory(odd);
    if (kind == "fifo") ASSERT_EQ(mkfifo(odd.c_str(), 0644), 0);
    if (kind == "device") fs::create_symlink("/dev/zero", odd);
    const std::string error = error_of(dir.path());
    const std::string want = kind == "directory" ? "f1.obj: this frame is a directory, not a regular file"
                             : kind == "fifo"    ? "f1.obj: this frame is a FIFO (named pipe), not a regular file"
                                                 : "f1.obj: this frame is a character device, not a regular file";
    EXPECT_NE(error.find(want), std::string::npos) << kind << ": " << error;
  }
}

}  // namespace
}  // namespace cdb::test
