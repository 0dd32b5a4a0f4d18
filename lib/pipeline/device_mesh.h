#pragma once
// Pieces every pipeline's frame loop shares: the mesh on the executor, the ordered LBVH's
// per-frame upkeep, and the pair buffer with its counters.
#include <cmath>
#include <cstddef>
#include <cstring>
#include <type_traits>
#include <string>
#include <vector>

#include "cdbench/bvh/build.h"
#include "cdbench/bvh/lbvh.h"
#include "cdbench/bvh/order.h"
#include "cdbench/bvh/refit.h"
#include "cdbench/core/error.h"
#include "cdbench/core/pair_set.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/geometry/face_subset.h"
#include "cdbench/geometry/mesh.h"
#include "cdbench/geometry/mesh_pieces.h"
#include "cdbench/geometry/object_split.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {

template <class Exec>
class DeviceMesh {
 public:
  explicit DeviceMesh(Exec& exec) {
    vertices_[0].bind(exec.memory(), "mesh.vertices");
    vertices_[1].bind(exec.memory(), "mesh.prev_vertices");
    faces_.bind(exec.memory(), "mesh.faces");
    face_object_.bind(exec.memory(), "mesh.face_object");
    partners_.bind(exec.memory(), "mesh.partners");
    deformable_faces_.bind(exec.memory(), "mesh.deformable_faces");
    rigid_faces_.bind(exec.memory(), "mesh.rigid_faces");
    leaf_piece_.bind(exec.memory(), "mesh.leaf_piece");
    piece_first_.bind(exec.memory(), "mesh.piece_first");
    bounds_.bind(exec.memory(), "mesh.bounds");
    grid_.bind(exec.memory(), "mesh.box_grid");
    grid_temp_.bind(exec.memory(), "mesh.bounds_temp");
  }
  void set_topology(Exec& exec, const Topology& topology, SplitRule split_rule) {
    if (topology.faces.size() > kMaxLeaves) fail("scene has more triangles than 2^31-1");
    num_vertices_ = topology.num_vertices;
    num_faces_ = static_cast<uint32_t>(topology.faces.size());
    pieces_ = {};
    vertices_[0].reserve(num_vertices_);
    if (swept_) vertices_[1].reserve(num_vertices_);
    exec.reserve_upload(num_vertices_ * sizeof(vec3f));
    current_ = 0;
    uploaded_ = have_previous_ = false;
    if (quantized()) {
      bounds_.reserve(1);
      grid_.reserve(1);
      grid_temp_.reserve(exec.reduce_temp_bytes(num_vertices_));
    }
    upload_table(exec, faces_, topology.faces);
    queries_declared_ = topology.queries.declared;
    if (queries_declared_) {
      const PairFilterTables t = pair_filter_tables(topology.objects, topology.queries, num_faces_);
      upload_table(exec, face_object_, t.face_object);
      upload_table(exec, partners_, t.partners);
    }
    split_ = split_objects(topology, split_rule);
    upload_table(exec, deformable_faces_, split_.deformable_faces);
    upload_table(exec, rigid_faces_, split_.rigid_faces);
  }
  // T_D's connected pieces for a piece ordered build (--build-pieces): found on the host once
  // a topology, after set_topology, by the pipelines that build trees. Off, one piece, more
  // than 2^kMaxPieceBits, too many for `bits`' keys, or (auto) pieces of fewer than
  // kPieceMinMeanFaces faces on average (a soup, particles, boxes: the keys would order the
  // faces of a cell by piece index, not by place): none, and the build keys are plain
  // Morton codes.
  void set_pieces(Exec& exec, const Topology& topology, AutoSwitch choice, MortonBits bits) {
    pieces_ = {};
    if (choice == AutoSwitch::off || deformable().count == 0) return;
    const MeshPieces p = mesh_pieces(topology.faces, topology.num_vertices, split_.deformable_faces);
    const uint32_t piece_bits = cdb::piece_bits(p.count());
    const bool small = p.leaf_piece.size() < size_t(kPieceMinMeanFaces) * p.count();
    if (p.count() < 2 || piece_bits > kMaxPieceBits || !piece_order_fits(bits, piece_bits) ||
        (choice == AutoSwitch::automatic && small))
      return;
    upload_table(exec, leaf_piece_, p.leaf_piece);
    upload_table(exec, piece_first_, p.piece_first);
    pieces_ = {leaf_piece_.data(), piece_first_.data(), piece_bits};
  }
  // The piece order of T_D's builds; off (the default PieceOrder) where set_pieces found none.
  PieceOrder pieces() const { return pieces_; }
  // Which trees and traversals the scene's queries need (geometry/object_split.h).
  const ObjectSplit& split() const { return split_; }
  // The faces of T_D (every face when the scene is not split) and of T_R; none when no
  // declared query needs the tree.
  FaceSubset deformable() const {
    if (!split_.split) return {nullptr, num_faces_};
    return {deformable_faces_.data(), split_.deformable_tree() ? uint32_t(split_.deformable_faces.size()) : 0u};
  }
  FaceSubset rigid() const {
    return {rigid_faces_.data(), split_.rigid_tree() ? uint32_t(split_.rigid_faces.size()) : 0u};
  }
  // The scene's declared queries as the pair sink reads them, or nulls: every pair.
  const uint32_t* face_object() const { return queries_declared_ ? face_object_.data() : nullptr; }
  const uint64_t* partners() const { return queries_declared_ ? partners_.data() : nullptr; }
  // The box knobs of PipelineConfig; call before set_topology (swept boxes need the
  // second vertex buffer, reserved there).
  void set_box_knobs(const PipelineConfig& config) {
    if (!(config.boxes.margin >= 0.0f) || !std::isfinite(config.boxes.margin))
      fail("--box-margin must be a finite number >= 0");
    swept_ = config.boxes.swept;
    margin_ = config.boxes.margin;
    precision_ = config.boxes.precision;
    widen_ = widens_boxes(config.boxes);
  }
  bool quantized() const { return precision_ == BoxPrecision::q16; }
  // Swept boxes: the two vertex buffers swap roles, the new positions go over the older
  // frame's; no allocation. A resident frame is read where it lies (FrameVertices), once the
  // caller's stream has written it; with swept boxes it is copied, the previous frame's
  // positions having to outlive the caller's buffer.
  void upload(Exec& exec, const FrameVertices& frame) {
    if (frame.count != num_vertices_)
      fail("frame has " + std::to_string(frame.count) + " vertices, topology has " +
           std::to_string(num_vertices_));
    if (swept_) {
      have_previous_ = have_previous_ || uploaded_;
      current_ ^= 1u;
    }
    uploaded_ = true;
    if (!frame.resident) {
      exec.upload(vertices_[current_].data(), frame.data, num_vertices_);
      frame_vertices_ = vertices_[current_].data();
      return;
    }
    exec.wait_for_stream(frame.stream);
    if (swept_) {
      exec.copy(vertices_[current_].data(), frame.data, num_vertices_);
      frame_vertices_ = vertices_[current_].data();
    } else {
      frame_vertices_ = frame.data;
    }
  }
  void upload(Exec& exec, const std::vector<vec3f>& vertices) {
    upload(exec, FrameVertices{vertices.data(), vertices.size()});
  }
  // q16: this frame's grid over its vertex bounds (with swept boxes the previous frame's
  // too, so the grid spans every box it snaps), reduced and laid out on the executor into
  // buffers reserved in set_topology: no read-back, no allocation.
  void update_grid(Exec& exec) {
    if (!quantized()) return;
    exec.reduce_box(num_vertices_, VertexBoundsFn{frame_vertices_, previous()}, bounds_.data(),
                    grid_temp_.data(), grid_temp_.size());
    exec.for_each_n(1, BoxGridFn{bounds_.data(), grid_.data()});
  }
  MeshView view() const {
    return {frame_vertices_, faces_.data(), num_faces_, previous(), margin_,
            quantized() ? grid_.data() : nullptr, widen_};
  }
  // The faces' vertex indices, 3 per face, for co-vertex filtering.
  const uint32_t* face_vertices() const { return reinterpret_cast<const uint32_t*>(faces_.data()); }
  uint32_t num_faces() const { return num_faces_; }

 private:
  // A host table into an executor array sized to it.
  template <class T>
  static void upload_table(Exec& exec, Array<T>& array, const std::vector<T>& table) {
    array.reserve(table.size());
    exec.copy_from_host(array.data(), table.data(), table.size());
  }
  const vec3f* previous() const { return swept_ && have_previous_ ? vertices_[current_ ^ 1u].data() : nullptr; }

  Array<vec3f> vertices_[2];  // current_ is this frame's; the other the previous frame's
  const vec3f* frame_vertices_ = nullptr;  // this frame's: vertices_[current_], or resident
  Array<Tri> faces_;
  Array<uint32_t> face_object_;
  Array<uint64_t> partners_;
  Array<uint32_t> deformable_faces_, rigid_faces_;
  Array<uint32_t> leaf_piece_, piece_first_;
  PieceOrder pieces_;
  ObjectSplit split_;
  bool queries_declared_ = false;
  uint32_t num_vertices_ = 0, num_faces_ = 0;
  bool swept_ = false;
  float margin_ = 0.0f;
  bool widen_ = false;
  BoxPrecision precision_ = BoxPrecision::fp32;
  Array<Aabb<float>> bounds_;
  Array<BoxGrid> grid_;
  Array<std::byte> grid_temp_;
  uint32_t current_ = 0;
  bool uploaded_ = false, have_previous_ = false;
};

// Runs `work` as phase p of the frame's timing.
template <class Timer, class F>
void time_phase(Timer& timer, Phase p, F&& work) {
  timer.start(p);
  work();
  timer.stop(p);
}

// Starts a frame's timing and uploads its vertices (timed apart: upload is left out of the
// frame total, since simulators hold their vertices on the device already); with q16 boxes
// the frame's grid follows, in the boxes phase, for every pipeline and baseline alike.
template <class Exec, class Timer>
MeshView begin_frame(Exec& exec, Timer& timer, DeviceMesh<Exec>& mesh, const FrameVertices& vertices) {
  timer.start_frame();
  time_phase(timer, Phase::upload, [&] { mesh.upload(exec, vertices); });
  if (mesh.quantized()) time_phase(timer, Phase::boxes, [&] { mesh.update_grid(exec); });
  return mesh.view();
}

// Copies the frame's phase times into its stats, after the frame's read-back.
template <class Timer>
void record_timings(const Timer& timer, FrameStats& stats) {
  for (size_t p = 0; p < kPhaseCount; ++p) stats.timing.phase_ms[p] = timer.phase_ms(Phase(p));
  stats.timing.total_ms = timer.frame_ms() - stats.timing.phase_ms[size_t(Phase::upload)];
  stats.timing.host_syncs = uint32_t(timer.frame_syncs());
}

// Rebuild (build + depth-first order, by histogram or, for the radix baseline, by a key
// sort) or refit the hierarchy over `faces` (grouped by `face_group` or ordered by `pieces`
// if given: build.h);
// returns which ran.
template <class Exec, class Timer>
std::string update_hierarchy(Exec& exec, Timer& timer, Lbvh<Exec>& bvh, const MeshView& mesh,
                             FaceSubset faces, bool rebuild, MortonBits bits, bool radix_order = false,
                             const uint32_t* face_group = nullptr, PieceOrder pieces = {}) {
  if (!rebuild) {
    time_phase(timer, Phase::refit, [&] { refit(exec, bvh, mesh); });
    return "refit";
  }
  time_phase(timer, Phase::build, [&] { build_hierarchy(exec, bvh, mesh, bits, faces, face_group, pieces); });
  time_phase(timer, Phase::order,
             [&] { radix_order ? order_depth_first_radix(exec, bvh) : order_depth_first(exec, bvh); });
  return "build";
}

// The pair buffer: pairs plus a block of device counters read back once a frame, typed by
// the pipeline: `Counters` is a struct of unsigned long long counters whose first is the
// pairs (pipeline/front_counters.h, PairCounters in pipeline/pair_pipeline.h).
template <class Exec, class Counters>
class PairBuffer {
  static_assert(offsetof(Counters, pairs) == 0, "the pair count comes first: pair sinks count there");
  static_assert(sizeof(Counters) % sizeof(unsigned long long) == 0 && std::is_trivially_copyable_v<Counters>);

 public:
  static constexpr size_t kWords = sizeof(Counters) / sizeof(unsigned long long);
  // `prefix`: of the buffers' names (the memory report's), where a pipeline holds two.
  explicit PairBuffer(Exec& exec, const std::string& prefix = "") {
    pairs_.bind(exec.memory(), prefix + "pairs");
    counters_.bind(exec.memory(), prefix + "counters");
  }
  void reserve(size_t capacity) {
    pairs_.reserve(std::max<size_t>(1024, capacity));
    counters_.reserve(kWords);
    ++revision_;
  }
  // Changes whenever the pair buffer moves (reserve, growth): what a recorded frame's
  // launches read.
  uint64_t revision() const { return revision_; }
  void reset_counters(Exec& exec) { exec.fill(counters_.data(), kWords, 0ull); }
  // The same reset, done by a refit on its way (bvh/refit.h).
  CounterReset counter_reset() { return {counters_.data(), uint32_t(kWords)}; }
  PairSink sink() {
    return {pairs_.data(), counters_.data(), pairs_.capacity(), skip_adjacent_faces_, face_object_, partners_};
  }
  // Keep only the pairs the scene's declared queries ask for (nulls: every pair).
  void filter_queries(const uint32_t* face_object, const uint64_t* partners) {
    face_object_ = face_object;
    partners_ = partners;
  }
  // Drop pairs of triangles sharing a vertex (faces: 3 vertex indices each), or keep all.
  void skip_adjacent(const uint32_t* faces) { skip_adjacent_faces_ = faces; }
  // The block in device memory, for the addresses of its counters (`&device()->field`):
  // never read through on the host.
  Counters* device() { return reinterpret_cast<Counters*>(counters_.data()); }
  // The frame's one synchronization: all counters at once.
  const Counters& read_counters(Exec& exec) {
    unsigned long long words[kWords];
    exec.copy_to_host(words, counters_.data(), kWords);
    std::memcpy(&last_, words, sizeof last_);
    return last_;
  }
  const Counters& last_counters() const { return last_; }
  // After a read-back: if the pairs did not fit, grow to the measured need
  // (counted) and say so; the caller re-runs the query.
  bool grow_if_needed() { return count() > pairs_.capacity() && grow_past_count(); }
  // Before a frame, outside its timing: when the last frame's pairs filled more than seven
  // eighths of the buffer, it grows to a quarter past them, so that a count that grows from
  // frame to frame is met between frames instead of overflowing one and running its query
  // twice (docs/design.md "Constants and their measurements"). The buffer holds the last
  // frame's pairs, which are read between frames (sorted_pairs) and dead once the next frame
  // starts. True if it grew.
  bool reserve_ahead() { return count() > pairs_.capacity() - pairs_.capacity() / 8 && grow_past_count(); }
  uint64_t count() const { return last_.pairs; }
  // The last frame's pairs in executor memory, count() of them, unsorted.
  const PrimPair* data() const { return pairs_.data(); }
  size_t capacity() const { return pairs_.capacity(); }
  std::vector<PrimPair> sorted_pairs(Exec& exec) const {
    std::vector<PrimPair> out(count());
    exec.copy_to_host(out.data(), pairs_.data(), out.size());
    sort_by_pair_key(out);
    return out;
  }

 private:
  // Grows to a quarter past the last frame's pair count; true.
  bool grow_past_count() {
    pairs_.reserve(size_t(count() + count() / 4));
    ++revision_;
    return true;
  }

  Array<PrimPair> pairs_;
  Array<unsigned long long> counters_;
  const uint32_t* skip_adjacent_faces_ = nullptr;
  const uint32_t* face_object_ = nullptr;
  const uint64_t* partners_ = nullptr;
  Counters last_{};
  uint64_t revision_ = 0;
};

}  // namespace cdb
