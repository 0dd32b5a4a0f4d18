#pragma once
// cdbench as a library: the broad phase of your own simulator, frame by frame.
//
//   cdbench::BroadPhase bp({.pipeline = "c", .executor = "cpu"},
//                          cdbench::Topology::mesh(triangles, num_vertices));
//   for (each step) {
//     bp.run(positions.data(), num_vertices);   // x, y, z per vertex, float or double
//     for (cdbench::Pair p : bp.pairs()) ...    // triangle indices, a < b, sorted
//   }
//
// A BroadPhase is one pipeline of the benchmark (any name of `cdbench run --pipeline`,
// pipelines()) on one executor: "cpu" (OpenMP) or "cuda". It is given the topology once, then
// one frame of positions at a time, from host memory or, on CUDA, from device memory the caller
// owns (run_device: read in place, after the work queued on the caller's stream). After each
// frame it holds the frame's pairs (pairs(), and on CUDA device_pairs()) and statistics
// (stats()). Every tuning knob keeps the command line's default; the options below are the
// ones that change the pair set. Failures are thrown as cdbench::Error (a std::runtime_error)
// with the library's message; nothing is printed. oracle_pairs() is the exact serial
// reference the benchmark checks every pipeline against. docs/library.md has the details.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/core/pair.h"

namespace cdbench {

// Every failure: an unknown name, a frame of the wrong size, a CUDA error, ...
using Error = cdb::Error;

// A reported pair: two triangle (or box) indices, 0-based, a < b.
using Pair = cdb::PrimPair;

// Vertex indices of one triangle, 0-based.
struct Triangle {
  uint32_t v0, v1, v2;
};

// A contiguous range of triangles, deformable or rigid (a rigid object's tree is built once
// and refitted; docs/design.md "Deformable and rigid objects").
struct Object {
  std::string name;
  uint32_t first_triangle = 0, num_triangles = 0;
  bool rigid = false;
};

// What stays fixed from frame to frame: the triangles, or a number of boxes.
struct Topology {
  std::vector<Triangle> triangles;
  uint32_t num_vertices = 0;
  // Optional objects covering every triangle, in order, without gaps (at most 64); with
  // queries declared (either list non-empty) only the pairs they ask for are reported:
  // pairs inside each object of self_queries and between each pair of inter_queries
  // (object indices). No queries: every pair.
  std::vector<Object> objects;
  std::vector<uint32_t> self_queries;
  std::vector<std::pair<uint32_t, uint32_t>> inter_queries;
  // Set by boxes(): each "vertex" pair is a box's min and max corner.
  uint32_t num_boxes = 0;

  static Topology mesh(std::vector<Triangle> triangles, uint32_t num_vertices);
  // `count` boxes: a frame is 2 * count points, box i's min corner then its max corner
  // (6 floats a box: min x, y, z, max x, y, z). Pairs are box indices.
  static Topology boxes(uint32_t count);
};

struct Options {
  std::string pipeline = "c";    // a name of pipelines()
  std::string executor = "cpu";  // "cpu" or "cuda"
  // Leave out pairs of triangles sharing a vertex (a cloth solver's collision step does).
  bool skip_adjacent = false;
  // Every box grows by this much (scene units) on each side: more pairs, none missed.
  float margin = 0.0f;
  // Every box also bounds its triangle at the previous frame.
  bool swept = false;
  // "fp32" (default), "fp64" (positions rebased on a double origin before rounding: scenes
  // far from the origin, with run() of doubles) or "q16" (boxes snapped outward onto a 16-bit
  // grid). docs/design.md "Box precision".
  std::string box_precision = "fp32";
};

// What one frame did and cost (cdb::FrameStats, reduced).
struct FrameStats {
  uint64_t pairs = 0;
  double time_ms = 0.0;    // the frame, its upload left out
  double upload_ms = 0.0;  // the positions' upload (0 when read in place)
  // Per phase (phase_names()), 0 for those the frame did not run.
  std::array<double, 13> phase_ms{};
  std::string op;  // what it did: "build+generate", "refit+preserve", "refit", ...
  // Front pipelines: the fronts' nodes after the frame, and Q(root) (paper §4.1).
  uint64_t front_internal = 0, front_external = 0;
  double q_root = 0.0;
  uint32_t query_reruns = 0;  // queries run again because a buffer had to grow
  uint32_t host_syncs = 0;    // host-device synchronizations (1 once sizes settle)
  // Executor buffers (device memory on "cuda") allocated by the call, to hold a count that
  // outgrew them: 0 once sizes settle, when a frame allocates nothing at all.
  uint32_t buffer_allocations = 0;
};

// The names of FrameStats::phase_ms's entries.
const std::array<const char*, 13>& phase_names();

// A frame's pairs in device memory (executor "cuda"), unsorted: `count` Pairs at `data`, valid
// until the next frame.
struct DevicePairs {
  const Pair* data = nullptr;
  size_t count = 0;
};

class BroadPhase {
 public:
  BroadPhase(const Options& options, const Topology& topology);
  ~BroadPhase();
  BroadPhase(BroadPhase&&) noexcept;
  BroadPhase& operator=(BroadPhase&&) noexcept;

  // One frame from host memory: num_vertices x, y, z triples (2 * num_boxes corners for
  // boxes). Float positions run as they are (on "cpu" read in place, no copy); doubles are
  // rounded as box_precision says. Returns the frame's statistics.
  const FrameStats& run(const float* xyz, size_t num_vertices);
  const FrameStats& run(const double* xyz, size_t num_vertices);
  // Executor "cuda": one frame from device memory the caller owns, read in place (no copy;
  // with swept boxes copied once on the device). The frame's kernels wait on the device for
  // the work queued so far on `cuda_stream` (a cudaStream_t; nullptr: the default stream);
  // the call returns once the frame is done, so later work on any stream may read its pairs.
  const FrameStats& run_device(const float* device_xyz, size_t num_vertices, void* cuda_stream = nullptr);

  // The last frame's pairs, sorted by (a, b). The second form reuses `out`'s memory: on "cpu"
  // it allocates nothing once the pair count has settled.
  std::vector<Pair> pairs() const;
  void pairs(std::vector<Pair>& out) const;
  // Executor "cuda": the last frame's pairs where they lie (throws on "cpu").
  DevicePairs device_pairs() const;
  const FrameStats& stats() const;

  const Options& options() const;
  size_t num_vertices() const;
  size_t num_triangles() const;  // or boxes

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The pipelines' names, in the benchmark's order.
std::vector<std::string> pipelines();

// Whether executor "cuda" can run here; if not, `reason` says why.
bool cuda_available(std::string* reason = nullptr);

// The exact reference: the pairs whose triangles' boxes overlap (closed boxes, in the
// positions' own precision, no margin), with the topology's queries and skip_adjacent,
// sorted by (a, b). Serial and independent of every pipeline: a pipeline given the same
// floats with the default box options reports exactly these pairs.
std::vector<Pair> oracle_pairs(const Topology& topology, const float* xyz, size_t num_vertices,
                               bool skip_adjacent = false);
std::vector<Pair> oracle_pairs(const Topology& topology, const double* xyz, size_t num_vertices,
                               bool skip_adjacent = false);

}  // namespace cdbench
