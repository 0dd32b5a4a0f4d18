// Seeded mutations of valid inputs (an OBJ frame sequence, scene descriptors, a results
// file written by a short CPU run) through the readers a user's files meet. Every mutated
// input must be read or refused with cdb::Error, its message naming the input in words:
// never a crash, a hang, another exception, or a library's own text. Each case runs in a
// child process (fork), so a crash or a hang is a finding of its own, not the end of the
// suite; a failing case prints its seed and mutation, which reproduce it.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <new>
#include <optional>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "scenes/generators/generators.h"
#include "scenes/load/obj_sequence.h"
#include "harness/results/results_file.h"
#include "harness/results/results_reader.h"
#include "scenes/load/scene.h"
#include "cdbench/pipeline/pipeline.h"
#include "cdbench/pipeline/run_summary.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {
namespace {

namespace fs = std::filesystem;

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// Text that is a library's, not cdbench's: what a user cannot act on.
bool raw_library_text(const std::string& m) {
  static const std::regex raw(
      R"(\[json\.exception|filesystem error|basic_string|std::|stou?l|stoi|stod|vector::|HDF5-DIAG|H5[A-Z][a-z_]*\(\)|errno = |bad_alloc|what\(\))");
  return std::regex_search(m, raw);
}

enum class Outcome { read, refused, finding };

struct Result {
  Outcome outcome = Outcome::read;
  std::string detail;  // the message, or what went wrong
};

// Runs `child(fd)` in a forked process, which ends with _exit and whatever it writes to
// `fd` is collected into `output`; waits up to `timeout_s` and kills it past the limit. A
// failed pipe, a hang (`hang` says how, before the limit) or a crash is a finding;
// otherwise `code` is its exit code.
std::optional<Result> run_child(const std::function<void(int)>& child, double timeout_s, const std::string& hang,
                                int& code, std::string& output) {
  int fds[2];
  if (pipe(fds) != 0) return Result{Outcome::finding, "pipe failed"};
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    child(fds[1]);
    _exit(127);
  }
  close(fds[1]);
  const int fd = fds[0];
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  char buf[4096];
  int status = 0;
  for (bool done = false; !done;) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 20) > 0) {
      const ssize_t n = read(fd, buf, sizeof buf);
      if (n > 0) output.append(buf, size_t(n));
    }
    done = waitpid(pid, &status, WNOHANG) == pid;
    if (!done && std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      close(fd);
      return Result{Outcome::finding, "hang: " + hang + " " + std::to_string(timeout_s) + " s"};
    }
  }
  for (ssize_t n; (n = read(fd, buf, sizeof buf)) > 0;) output.append(buf, size_t(n));
  close(fd);
  if (WIFSIGNALED(status)) return Result{Outcome::finding, std::string("crash: ") + strsignal(WTERMSIG(status))};
  code = WEXITSTATUS(status);
  return std::nullopt;
}

// A refusal's message: in words, naming the input, of a readable length.
Result judge_message(const std::string& message, const std::string& name) {
  if (raw_library_text(message)) return {Outcome::finding, "raw library text: " + message};
  if (message.find(name) == std::string::npos) return {Outcome::finding, "does not name " + name + ": " + message};
  if (message.size() > 2000) return {Outcome::finding, "a message of " + std::to_string(message.size()) + " bytes"};
  return {Outcome::refused, message};
}

// Runs `reader` in a child process under a memory limit (a huge mutated size must fail,
// not swap) and a time limit. `name`: what the message must mention.
Result run_isolated(const std::function<void()>& reader, const std::string& name, double timeout_s = 10.0) {
  auto child = [&](int fd) {
    // The readers' notes (polygons triangulated, frames re-read) are not under test.
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDERR_FILENO);
    const rlimit memory{size_t(2) << 30, size_t(2) << 30};
    setrlimit(RLIMIT_AS, &memory);
    int code = 0;
    std::string message;
    try {
      reader();
    } catch (const Error& e) {
      message = e.what();
      code = 1;
    } catch (const std::bad_alloc&) {
      // The CLI says "out of host memory" for it (app/library_errors.cpp).
      message = "out of host memory";
      code = 2;
    } catch (const std::exception& e) {
      message = std::string("not a cdb::Error: ") + typeid(e).name() + ": " + e.what();
      code = 3;
    } catch (...) {
      message = "a non-exception was thrown";
      code = 3;
    }
    const ssize_t ignored = write(fd, message.data(), std::min<size_t>(message.size(), 1 << 16));
    (void)ignored;
    _exit(code);
  };
  int code = 0;
  std::string message;
  if (auto finding = run_child(child, timeout_s, "no answer within", code, message)) return *finding;
  if (code == 0) return {Outcome::read, ""};
  if (code == 3) return {Outcome::finding, message};
  if (code == 2) return {Outcome::refused, message};
  return judge_message(message, name);
}

// `cdbench report --csv FILE` as a user runs it: exit 0 or 1, stderr in words naming the
// file; a crash, a hang or another exit code is a finding.
Result run_report(const std::string& cdbench, const std::string& file, double timeout_s) {
  auto child = [&](int fd) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    execl(cdbench.c_str(), cdbench.c_str(), "report", "--csv", file.c_str(), static_cast<char*>(nullptr));
  };
  int code = 0;
  std::string message;
  if (auto finding = run_child(child, timeout_s, "cdbench report still running after", code, message)) return *finding;
  if (code == 0 && message.empty()) return {Outcome::read, ""};
  if (code != 1) return {Outcome::finding, "exit " + std::to_string(code) + ": " + message};
  return judge_message(message, file);
}

// One seeded mutation of `in`; `what` says which, for the report of a failing case.
class Mutator {
 public:
  explicit Mutator(uint64_t seed) : rng_(seed) {}

  std::string text(const std::string& in, std::string& what) {
    std::string s = in;
    switch (pick(9)) {
      case 0: {  // flip one byte to any value
        const size_t at = pick(s.size());
        const char c = char(pick(256));
        what = "byte " + std::to_string(at) + " set to " + std::to_string(uint8_t(c));
        s[at] = c;
        break;
      }
      case 1: {  // cut short
        const size_t at = pick(s.size());
        what = "truncated at " + std::to_string(at);
        s.resize(at);
        break;
      }
      case 2:
      case 3: {  // a token inserted anywhere
        static const std::vector<std::string> tokens = {
            "1e39", "-1e39", "nan", "-inf", "inf", "1e999999", "0x1p9999", "1e308", "99999999999999999999999",
            "-0", "\xff\xfe", "{", "}", "[", "]", ",", "\"", ":", "f 1 2", "v 1 2", "//", "#",
            std::string("\0", 1), "4294967296", "-4294967297", "\"x\": 1, ", "\"x\": 1, \"x\": 2, ", "\n", "\r",
            " ", "1", "0", "-1", "null", "true", "[[[[[[[[[[", "\xc3\xa9"};
        const size_t at = pick(s.size() + 1);
        const std::string t = tokens[pick(tokens.size())];
        what = "inserted '" + t + "' at " + std::to_string(at);
        s.insert(at, t);
        break;
      }
      case 4: {  // a number replaced
        std::vector<std::pair<size_t, size_t>> numbers;
        for (size_t i = 0; i < s.size();) {
          if (std::isdigit(static_cast<unsigned char>(s[i]))) {
            size_t j = i;
            while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.' || s[j] == 'e' || s[j] == '-'))
              ++j;
            numbers.push_back({i, j - i});
            i = j;
          } else {
            ++i;
          }
        }
        if (numbers.empty()) return text(in, what);
        static const char* values[] = {"1e39", "nan", "inf", "-1e400", "0", "-1", "4294967295", "4294967296",
                                       "18446744073709551616", "1e-320", "3.5", "0x10", "1e", "--1", "1..2"};
        const auto [at, len] = numbers[pick(numbers.size())];
        const std::string v = values[pick(std::size(values))];
        what = "number at " + std::to_string(at) + " (" + s.substr(at, len) + ") replaced by " + v;
        s.replace(at, len, v);
        break;
      }
      case 5:
      case 6:
      case 7: {  // a line duplicated, deleted or swapped with another
        std::vector<std::string> lines;
        std::istringstream is(s);
        for (std::string l; std::getline(is, l);) lines.push_back(l);
        if (lines.size() < 2) return text(in, what);
        const size_t a = pick(lines.size()), b = pick(lines.size());
        const int kind = int(pick(3));
        if (kind == 0) {
          what = "line " + std::to_string(a + 1) + " duplicated";
          lines.insert(lines.begin() + long(a), lines[a]);
        } else if (kind == 1) {
          what = "line " + std::to_string(a + 1) + " deleted";
          lines.erase(lines.begin() + long(a));
        } else {
          what = "lines " + std::to_string(a + 1) + " and " + std::to_string(b + 1) + " swapped";
          std::swap(lines[a], lines[b]);
        }
        s.clear();
        for (const auto& l : lines) s += l + "\n";
        break;
      }
      default: {  // several bytes flipped
        const size_t n = 1 + pick(8);
        what = std::to_string(n) + " random bytes set";
        for (size_t k = 0; k < n && !s.empty(); ++k) s[pick(s.size())] = char(pick(256));
      }
    }
    return s;
  }

  // A binary file: bytes set, a block zeroed, cut short, or bytes inserted.
  std::string binary(const std::string& in, std::string& what) {
    std::string s = in;
    switch (pick(5)) {
      case 0:
      case 1: {
        const size_t n = 1 + pick(16);
        const size_t at = pick(s.size());
        what = std::to_string(n) + " bytes from " + std::to_string(at) + " set";
        for (size_t k = 0; k < n; ++k) s[std::min(s.size() - 1, at + pick(64))] = char(pick(256));
        break;
      }
      case 2: {
        const size_t at = pick(s.size()), len = 1 + pick(512);
        what = std::to_string(len) + " bytes zeroed at " + std::to_string(at);
        for (size_t k = at; k < std::min(s.size(), at + len); ++k) s[k] = 0;
        break;
      }
      case 3: {
        const size_t at = pick(s.size());
        what = "truncated at " + std::to_string(at);
        s.resize(at);
        break;
      }
      default: {
        const size_t at = pick(s.size()), len = 1 + pick(64);
        what = std::to_string(len) + " bytes inserted at " + std::to_string(at);
        std::string junk(len, '\0');
        for (char& c : junk) c = char(pick(256));
        s.insert(at, junk);
      }
    }
    return s;
  }

 private:
  size_t pick(size_t n) { return n == 0 ? 0 : size_t(rng_() % n); }
  std::mt19937_64 rng_;
};

struct Tally {
  size_t read = 0, refused = 0;
  std::vector<std::string> findings;
  void add(const Result& r, uint64_t seed, const std::string& what) {
    if (r.outcome == Outcome::read) ++read;
    if (r.outcome == Outcome::refused) ++refused;
    if (r.outcome == Outcome::finding)
      findings.push_back("seed " + std::to_string(seed) + " (" + what + "): " + r.detail);
  }
  void expect_none(const char* suite) {
    std::printf("%s: %zu cases, %zu read, %zu refused, %zu findings\n", suite, read + refused + findings.size(),
                read, refused, findings.size());
    for (size_t i = 0; i < findings.size() && i < 20; ++i) ADD_FAILURE() << findings[i];
    EXPECT_TRUE(findings.empty()) << findings.size() << " findings";
  }
};

class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("cdb_mutations_" + std::to_string(getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// A three-frame OBJ sequence of a small folded strip: vertices with normals and a
// comment, faces in every corner form OBJ allows.
void write_sequence(const fs::path& dir) {
  fs::create_directories(dir);
  for (int f = 0; f < 3; ++f) {
    std::ostringstream o;
    o << "# frame " << f << "\no strip\n";
    for (int i = 0; i < 6; ++i) o << "v " << 0.25 * i << " " << (i % 2) << " " << 0.125 * f * i << "\n";
    o << "vn 0 0 1\nvt 0 0\n";
    o << "f 1 2 3\nf 2/1 3/1 4/1\nf 3//1 4//1 5//1\nf 4/1/1 5/1/1 6/1/1 1/1/1\nf -1 -2 -3\n";
    write_bytes(dir / ("frame_000" + std::to_string(f) + ".obj"), o.str());
  }
}

void read_all_frames(const FrameSource& s) {
  std::vector<vec3d> p;
  for (uint32_t k = 0; k < s.num_frames() && k < 4; ++k) s.positions(k, p);
}

constexpr uint64_t kSeed = 20261127;

TEST(InputMutations, ObjSequence) {
  TempDir tmp;
  const fs::path good = tmp.path() / "good", dir = tmp.path() / "mutated";
  write_sequence(good);
  ASSERT_EQ(run_isolated([&] { read_all_frames(*open_mesh_sequence(good)); }, "good").outcome, Outcome::read);
  Tally tally;
  for (uint64_t i = 0; i < 2000; ++i) {
    Mutator m(kSeed + i);
    fs::remove_all(dir);
    fs::copy(good, dir);
    const fs::path frame = dir / ("frame_000" + std::to_string(i % 3) + ".obj");
    std::string what;
    write_bytes(frame, m.text(read_bytes(frame), what));
    what = frame.filename().string() + ": " + what;
    tally.add(run_isolated([&] { read_all_frames(*open_mesh_sequence(dir)); }, "frame_000"), kSeed + i, what);
  }
  tally.expect_none("OBJ sequence");
}

TEST(InputMutations, SceneDescriptors) {
  TempDir tmp;
  write_sequence(tmp.path() / "seq");
  write_bytes(tmp.path() / "tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n");
  const std::vector<std::string> descriptors = {
      R"({"description": "generated", "generator": "cloth-wave", "params": {"res": 4, "frames": 3}})",
      R"({"frames": "seq", "placement": {"scale": 2, "offset": [1, 2, 3]}})",
      R"({"description": "parts",
 "parts": [
  {"name": "cloth", "generator": "cloth-wave", "params": {"res": 4, "frames": 3}},
  {"name": "tet", "mesh": {"file": "tet.obj", "scale": 0.5},
   "motion": {"fps": 30, "position": [0.5, 0.5, 0.5], "velocity": [0, -0.9, 0], "axis": [1, 0.3, 0], "angular_velocity": 2.0}}
 ],
 "queries": {"self": ["cloth"], "inter": [["cloth", "tet"]]}
})"};
  const fs::path file = tmp.path() / "scene.json";
  for (const auto& d : descriptors) {
    write_bytes(file, d);
    ASSERT_EQ(run_isolated([&] { read_all_frames(*open_scene(file.string(), tmp.path()).source); }, "scene.json").outcome,
              Outcome::read)
        << d;
  }
  Tally tally;
  for (uint64_t i = 0; i < 1200; ++i) {
    Mutator m(kSeed + i);
    std::string what;
    write_bytes(file, m.text(descriptors[i % descriptors.size()], what));
    what = "descriptor " + std::to_string(i % descriptors.size()) + ": " + what;
    tally.add(run_isolated([&] { read_all_frames(*open_scene(file.string(), tmp.path()).source); }, "scene.json"),
              kSeed + i, what);
  }
  tally.expect_none("scene descriptors");
}

// A results file of three frames of bvh on a small funnel, run on the CPU in a child
// process (this process stays free of OpenMP's threads, which a fork would not copy).
void write_results(const fs::path& path) {
  const Result made = run_isolated(
      [&] {
        auto scene = make_generator("funnel", {{"res", 8}, {"frames", 3}});
        PipelineConfig cfg;
        cfg.name = "bvh";
        cfg.device = "cpu";
        auto p = make_pipeline(cfg);
        p->set_topology(scene->topology());
        RunInfo info;
        info.scene = "funnel";
        info.scene_description = "small funnel";
        info.pipeline = "bvh";
        info.backend = "cpu";
        info.device_name = "test cpu";
        info.params_json = R"({"command": "run", "options": {"frames": "0:3", "set": ["res=8"]}})";
        info.frame_last = 3;
        info.triangles = scene->topology().faces.size();
        info.vertices = scene->topology().num_vertices;
        ResultsFile out(path, info);
        std::vector<FrameStats> frames;
        std::vector<vec3f> v;
        for (uint32_t f = 0; f < 3; ++f) {
          scene->frame(f, v);
          frames.push_back(p->run_frame(v));
          out.append_frame(f, frames.back(), p->memory());
          out.write_pairs(f, p->sorted_pairs());
        }
        out.finish(summarize_run(frames, 1), p->memory());
      },
      path.string(), 120);
  ASSERT_EQ(made.outcome, Outcome::read) << made.detail;
}

// Through `cdbench report`, whose guard (app/damaged_file_guard.h) ends the reads that
// HDF5 itself would follow into a loop or a crash; the in-process reader is the same one.
TEST(InputMutations, ResultsFile) {
  const char* cdbench = std::getenv("CDBENCH");
  ASSERT_TRUE(cdbench && *cdbench) << "CDBENCH names the cdbench binary (tests/CMakeLists.txt sets it)";
  TempDir tmp;
  const fs::path good = tmp.path() / "good.h5", file = tmp.path() / "mutated.h5";
  write_results(good);
  const std::string bytes = read_bytes(good);
  write_bytes(file, bytes);
  ASSERT_EQ(run_report(cdbench, file.string(), 60).outcome, Outcome::read);
  Tally tally;
  for (uint64_t i = 0; i < 300; ++i) {
    Mutator m(kSeed + i);
    std::string what;
    write_bytes(file, m.binary(bytes, what));
    tally.add(run_report(cdbench, file.string(), 60), kSeed + i, what);
  }
  tally.expect_none("results file");
}

}  // namespace
}  // namespace cdb::test

int main(int argc, char** argv) {
  // The generators' frames are not cached on disk: each case reads what it is given.
  setenv("CDBENCH_FRAME_CACHE", "off", 1);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
