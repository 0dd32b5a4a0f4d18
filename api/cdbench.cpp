#include "cdbench/cdbench.h"

#include <algorithm>
#include <cstring>

#include "cdbench/geometry/mesh.h"
#include "cdbench/oracle/sweep_oracle.h"
#include "cdbench/pipeline/pipeline.h"
#include "registry/pipeline_kinds.h"

namespace cdbench {

static_assert(sizeof(Triangle) == sizeof(cdb::Tri) && sizeof(cdb::vec3f) == 3 * sizeof(float) &&
                  sizeof(cdb::vec3d) == 3 * sizeof(double),
              "frames and triangles are read in place as packed x, y, z and v0, v1, v2");
static_assert(std::tuple_size_v<decltype(FrameStats::phase_ms)> == cdb::kPhaseCount, "one entry per phase");

namespace {

using cdb::fail;

// The engine's topology, checked: every vertex index in range (the pipelines read positions
// through them unchecked).
cdb::Topology engine_topology(const Topology& t) {
  cdb::Topology out;
  out.num_vertices = t.num_vertices;
  out.box_faces = t.num_boxes;
  out.faces.resize(t.triangles.size());
  for (size_t f = 0; f < t.triangles.size(); ++f) {
    const Triangle& tri = t.triangles[f];
    for (uint32_t v : {tri.v0, tri.v1, tri.v2})
      if (v >= t.num_vertices)
        fail("triangle " + std::to_string(f) + " has vertex " + std::to_string(v) + ", but the topology has " +
             std::to_string(t.num_vertices) + " vertices (0-based)");
    out.faces[f] = {tri.v0, tri.v1, tri.v2};
  }
  for (const Object& o : t.objects) out.objects.push_back({o.name, o.first_triangle, o.num_triangles, o.rigid});
  out.queries.declared = !t.self_queries.empty() || !t.inter_queries.empty();
  out.queries.self = t.self_queries;
  out.queries.inter = t.inter_queries;
  if (out.queries.declared && out.objects.empty()) fail("queries are declared, but the topology has no objects");
  // Objects overlapping, leaving gaps or too many, queries out of range: the engine's messages.
  if (!out.objects.empty()) cdb::pair_filter_tables(out.objects, out.queries, out.faces.size());
  return out;
}

cdb::PipelineConfig engine_config(const Options& o) {
  cdb::PipelineConfig c;
  c.name = o.pipeline;
  c.device = o.executor;
  c.skip_adjacent = o.skip_adjacent;
  c.boxes.margin = o.margin;
  c.boxes.swept = o.swept;
  c.boxes.precision = cdb::parse_box_precision(o.box_precision);
  return c;
}

void check_count(size_t given, size_t expected) {
  if (given != expected)
    fail("frame has " + std::to_string(given) + " vertices, topology has " + std::to_string(expected));
}

}  // namespace

Topology Topology::mesh(std::vector<Triangle> triangles, uint32_t num_vertices) {
  Topology t;
  t.triangles = std::move(triangles);
  t.num_vertices = num_vertices;
  return t;
}

Topology Topology::boxes(uint32_t count) {
  if (count > (uint32_t(1) << 31) - 1) fail("more boxes than 2^31-1");
  Topology t;
  t.triangles.resize(count);
  // The box stream's faces (scenes/load/box_stream.cpp): (min, max, max), whose box is the box.
  for (uint32_t i = 0; i < count; ++i) t.triangles[i] = {2 * i, 2 * i + 1, 2 * i + 1};
  t.num_vertices = 2 * count;
  t.num_boxes = count;
  return t;
}

const std::array<const char*, 13>& phase_names() { return cdb::kPhaseNames; }

struct BroadPhase::State {
  Options options;
  std::unique_ptr<cdb::Pipeline> pipeline;
  size_t num_vertices = 0, num_triangles = 0;
  FrameStats stats;
  std::vector<cdb::vec3d> doubles;  // run(double*)'s frame, reused
  size_t allocations = 0;           // the executor's, up to the last frame

  const FrameStats& keep(const cdb::FrameStats& s) {
    const size_t now = pipeline->memory().allocations;
    stats.buffer_allocations = uint32_t(now - allocations);
    allocations = now;
    stats.pairs = s.pairs;
    stats.time_ms = s.timing.total_ms;
    stats.upload_ms = s.timing.phase_ms[size_t(cdb::Phase::upload)];
    std::copy(s.timing.phase_ms.begin(), s.timing.phase_ms.end(), stats.phase_ms.begin());
    stats.op = s.op;
    stats.front_internal = s.fronts.internal;
    stats.front_external = s.fronts.external;
    stats.q_root = s.quality.q_root;
    stats.query_reruns = s.timing.query_reruns;
    stats.host_syncs = s.timing.host_syncs;
    return stats;
  }
  bool on_cuda() const { return options.executor == "cuda"; }
};

BroadPhase::BroadPhase(const Options& options, const Topology& topology) : state_(std::make_unique<State>()) {
  state_->options = options;
  const cdb::Topology t = engine_topology(topology);
  state_->pipeline = cdb::make_pipeline(engine_config(options));
  state_->pipeline->set_topology(t);
  state_->allocations = state_->pipeline->memory().allocations;
  state_->num_vertices = t.num_vertices;
  state_->num_triangles = t.faces.size();
}

BroadPhase::~BroadPhase() = default;
BroadPhase::BroadPhase(BroadPhase&&) noexcept = default;
BroadPhase& BroadPhase::operator=(BroadPhase&&) noexcept = default;

const FrameStats& BroadPhase::run(const float* xyz, size_t num_vertices) {
  check_count(num_vertices, state_->num_vertices);
  // On the host executor its memory is the caller's: the positions are read in place.
  const cdb::FrameVertices frame{reinterpret_cast<const cdb::vec3f*>(xyz), num_vertices, !state_->on_cuda()};
  return state_->keep(state_->pipeline->run_frame(frame));
}

const FrameStats& BroadPhase::run(const double* xyz, size_t num_vertices) {
  check_count(num_vertices, state_->num_vertices);
  state_->doubles.resize(num_vertices);
  std::memcpy(state_->doubles.data(), xyz, num_vertices * sizeof(cdb::vec3d));
  return state_->keep(state_->pipeline->run_frame(state_->doubles));
}

const FrameStats& BroadPhase::run_device(const float* device_xyz, size_t num_vertices, void* cuda_stream) {
  if (!state_->on_cuda()) fail("run_device: the executor is cpu; device memory needs executor cuda");
  check_count(num_vertices, state_->num_vertices);
  const cdb::FrameVertices frame{reinterpret_cast<const cdb::vec3f*>(device_xyz), num_vertices, true, cuda_stream};
  return state_->keep(state_->pipeline->run_frame(frame));
}

std::vector<Pair> BroadPhase::pairs() const { return state_->pipeline->sorted_pairs(); }

void BroadPhase::pairs(std::vector<Pair>& out) const {
  if (state_->on_cuda()) {
    out = state_->pipeline->sorted_pairs();
    return;
  }
  const cdb::ResidentPairs r = state_->pipeline->resident_pairs();
  out.assign(r.data, r.data + r.count);
  std::sort(out.begin(), out.end(), [](Pair x, Pair y) { return cdb::pair_key(x) < cdb::pair_key(y); });
}

DevicePairs BroadPhase::device_pairs() const {
  if (!state_->on_cuda()) fail("device_pairs: the executor is cpu; its pairs are in host memory (pairs())");
  const cdb::ResidentPairs r = state_->pipeline->resident_pairs();
  return {r.data, r.count};
}

const FrameStats& BroadPhase::stats() const { return state_->stats; }
const Options& BroadPhase::options() const { return state_->options; }
size_t BroadPhase::num_vertices() const { return state_->num_vertices; }
size_t BroadPhase::num_triangles() const { return state_->num_triangles; }

std::vector<std::string> pipelines() { return cdb::pipeline_names(); }

bool cuda_available(std::string* reason) {
  const cdb::CudaDeviceInfo info = cdb::cuda_device_info();
  if (reason) *reason = info.available ? "" : info.reason;
  return info.available;
}

template <class T>
static std::vector<Pair> oracle(const Topology& topology, const T* xyz, size_t num_vertices, bool skip_adjacent) {
  const cdb::Topology t = engine_topology(topology);
  check_count(num_vertices, t.num_vertices);
  const auto* p = reinterpret_cast<const cdb::vec3<T>*>(xyz);
  return cdb::sweep_oracle_pairs(t, std::vector<cdb::vec3<T>>(p, p + num_vertices), skip_adjacent);
}

std::vector<Pair> oracle_pairs(const Topology& topology, const float* xyz, size_t num_vertices, bool skip_adjacent) {
  return oracle(topology, xyz, num_vertices, skip_adjacent);
}

std::vector<Pair> oracle_pairs(const Topology& topology, const double* xyz, size_t num_vertices, bool skip_adjacent) {
  return oracle(topology, xyz, num_vertices, skip_adjacent);
}

}  // namespace cdbench
