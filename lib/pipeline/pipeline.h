#pragma once
// What the CLI, the verifier and the tests see of a broad phase: a state machine that is
// given the topology once and then one frame of vertex positions at a time.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cdbench/bvh/refit_tiles.h"
#include "cdbench/core/morton.h"
#include "cdbench/core/pair.h"
#include "cdbench/core/phase.h"
#include "cdbench/exec/memory.h"
#include "cdbench/geometry/margin_range.h"
#include "cdbench/geometry/mesh.h"
#include "cdbench/geometry/object_split.h"
#include "cdbench/geometry/position_rounding.h"
#include "cdbench/pipeline/plan_step.h"

namespace cdb {

// How triangle boxes are computed (docs/design.md "Box precision"): fp32, the exact box of
// the positions rounded to float; fp64, the positions rebased on a double origin before
// rounding (geometry/position_rounding.h), so scenes far from the origin keep their
// features; q16, the fp32 box snapped outward onto a 16-bit grid per axis over the frame's
// vertex bounds. All three are conservative against the double geometry (fp32 and q16 with
// no --box-margin; fp64 with any).
enum class BoxPrecision { fp32, fp64, q16 };

const char* box_precision_name(BoxPrecision p);
// Throws cdb::Error naming the known values.
BoxPrecision parse_box_precision(const std::string& name);

// A launch choice that is on, off, or made per frame by a measured rule (automatic):
// --preserve-warp and --update-warp (FrontConfig::preserve_warp), --preserve-bound
// (FrontConfig::preserve_bound).
enum class AutoSwitch { automatic, on, off };

// Whether `choice` is on for a launch whose measured rule says `rule_holds`.
inline bool switched_on(AutoSwitch choice, bool rule_holds) {
  return choice == AutoSwitch::on || (choice == AutoSwitch::automatic && rule_holds);
}

const char* auto_switch_name(AutoSwitch w);
// Throws cdb::Error naming the known values.
AutoSwitch parse_auto_switch(const std::string& name);

// The triangle boxes every pipeline and baseline sees, made in face_box (geometry/mesh.h)
// (docs/design.md "Speed/accuracy knobs").
struct BoxConfig {
  // Fat boxes: every triangle box grows by this much (scene units) on each side.
  // Conservative: a superset of the exact box-overlap pairs.
  float margin = 0.0f;
  // Swept boxes: each box bounds the triangle at the previous and the current frame (the
  // first frame its own positions). Conservative with respect to the discrete pairs.
  bool swept = false;
  // Rebased or 16-bit quantized boxes (BoxPrecision).
  BoxPrecision precision = BoxPrecision::fp32;
};

// fp64's rounding keeps every overlap on its own; with a margin each box first widens by
// one float spacing (geometry/position_rounding.h, geometry/mesh.h).
inline bool widens_boxes(const BoxConfig& b) { return b.precision == BoxPrecision::fp64 && b.margin > 0.0f; }

// The hierarchy's build and upkeep.
struct TreeConfig {
  MortonBits morton_bits = MortonBits::b63;
  // bvh: rebuild the hierarchy every this many frames (0: only on the first frame).
  uint32_t rebuild_every = 0;
  // Front pipelines and bvh: refit only every this many frames (1: every frame), keeping
  // the stale boxes in between. NOT conservative: pairs can be missed. Baselines ignore it.
  uint32_t refit_every = 1;
  // Refit: trees of up to this many leaves refit their top (the nodes spanning refit
  // tiles) in one block, larger ones hand it over between blocks; 0: always hand over.
  // Default and limit: kRefitTopMaxLeaves and kRefitTopLeavesLimit (bvh/refit_tiles.h).
  uint32_t refit_top_leaves = kRefitTopMaxLeaves;
  // Refit: each tile (treelet) level by level with block barriers (bvh/refit_levels.h);
  // off: each leaf's thread climbs, handing nodes over through atomics (bvh/refit.h).
  // auto: on the GPU (its refit 13% faster on the 1M cloth), off on the host, where a tile
  // runs on one thread and its lanes once per level (funnel refit 0.233 against 0.200 ms).
  AutoSwitch refit_levels = AutoSwitch::automatic;
  // Builds of T_D key each leaf by its connected piece first (bvh/build.h PieceOrder), so
  // every piece of up to 2^12 has subtrees of its own and a refitted tree loosens only above
  // the pieces as they move apart; off: plain Morton codes; auto: where the pieces average
  // kPieceMinMeanFaces faces or more (DeviceMesh::set_pieces).
  AutoSwitch build_pieces = AutoSwitch::automatic;
  // Front pipelines under --front-cycle auto: a maintenance rebuilds the tree (and generates
  // every front) instead of updating once the rent the fronts paid on the degraded tree pays
  // for it (pipeline/tree_maintenance.h); off: only --rebuild-every and pipeline c's Formula 2.
  bool rebuild_degraded = true;
  // Front pipelines: a rebuild after the first frame is built ahead, on a side stream beside
  // the frames, which preserve the current fronts until it is adopted
  // (pipeline/front_pipeline.h); off: the rebuilding frame builds and generates itself.
  // auto: on the GPU, off on the host (where the side's work runs in the frame).
  AutoSwitch rebuild_ahead = AutoSwitch::automatic;
  // Front pipelines that build ahead: each maintenance due (an update or a generate) is a
  // rebuild built ahead instead, so that no frame waits for one; pipeline c then never
  // inspects (its inspections follow updates). auto: the way whose last maintenance cycle
  // cost less per pair (pipeline/maintenance_choice.h); measured no faster than off
  // (docs/front-maintenance.md "Maintenances built ahead").
  AutoSwitch maintain_ahead = AutoSwitch::off;
  // Builds and updates ahead: the second self fronts are generated (or updated) twice,
  // counting each tree node's front nodes and then placing each at its sorted place,
  // straight into the produced arrays the current fronts lend (front/ordering.h
  // PlacedFrontSink): two sets of front arrays at the peak, as a build or update in its
  // frame, for a second traversal on the side stream. Off: one run into the lent arrays,
  // then the histogram sort's scatter into arrays of the second fronts' own (three sets).
  bool ahead_placed = false;
  // --rebuild-degraded: the growth of the fronts (an update's count over a rebuild's) past
  // which a maintenance rebuilds (pipeline/tree_maintenance.h).
  double rebuild_growth = kRebuildGrowth;
  // Scenes with declared queries: which objects the second tree T_R takes
  // (geometry/object_split.h). rigid: the rigid objects only; queries: also the deformable
  // ones only an inter with the first tree names (an avatar), whose own self front finds
  // nothing the queries keep. rigid by default: on the H200 the avatar apart ran the
  // garment with its avatar and flamenco slower (their cloth's self pairs dominate, and a
  // split scene builds no rebuild ahead; docs/experiments.md).
  SplitRule split = SplitRule::rigid;
};

// Front maintenance of the front pipelines (pipeline/front_maintenance.h, frame_plan.h).
struct FrontConfig {
  // When fronts are updated (pipelines b and c balance first) instead of preserved.
  // 0 (--front-cycle auto): when the measured growth of the steady frames' cost since the
  // last update has paid for one; K: every K-th frame since the fronts were generated, the
  // paper's fixed cycle.
  uint32_t cycle = 0;
  // --front-cycle auto: each maintenance runs an update or a generate of new fronts,
  // whichever measured cheaper last; off: always an update (the paper). The periodic
  // strategy keeps its own alternation. On by default: measured faster on sphere and within
  // noise elsewhere (docs/front-maintenance.md "Update or generate").
  bool regenerate = true;
  // Ordered pipelines: histogram-sort the front an update produces (the paper). Off: the
  // update's output is kept in the order its blocks wrote it (each block's nodes together,
  // so near its input's order), and only generate and restructure sort; b and c still
  // count the front per node, so their balance before the next update sorts it.
  bool order_updates = true;
  // An update writes only what changes, into the current front (holes and an appended
  // tail: front/operations.h PatchFrontFn); once those changes reach compact_share of the
  // front's nodes, the next update produces the front whole and ordered again. Off
  // (default): every update produces the whole front (the paper). Off measured as fast or
  // faster under --front-cycle auto, on faster only when fronts update every frame
  // (docs/front-maintenance.md "Updates in place").
  bool update_in_place = false;
  double compact_share = 0.5;
  // The preserves before an update count what it can produce, and the front buffers grow
  // to that after their frame (pipeline/frame_plan.h, probe); off: an update that outgrows
  // them grows them inside its frame and runs again.
  bool update_probe = true;
  // Front pipelines that build ahead (--rebuild-ahead): a due update of T_D's self fronts
  // runs on the side stream, from the current fronts against a copy of the tree's boxes,
  // while the frames preserve the current fronts; the first frame that finds it done adopts
  // the updated fronts (pipeline/front_pipeline.h). Off: updates run in their frames.
  AutoSwitch update_ahead = AutoSwitch::off;
  // Preserve and update on CUDA (front/warp_traversal.h): share each front node's
  // traversal with the idle lanes of its warp. automatic: while the fronts fit in
  // kWarpSharingWaves (exec/tuning.h) waves of the GPU's resident threads, where the
  // launch's tail is its longest lanes; past that the SMs are full anyway and the sharing's
  // votes cost more than they save.
  AutoSwitch preserve_warp = AutoSwitch::automatic;
  AutoSwitch update_warp = AutoSwitch::automatic;
  // Preserve on CUDA launched under its register bound (kPreserveMinBlocks blocks an SM,
  // exec/tuning.h): more resident warps to hide its loads' latency, fewer registers each
  // (some spilled). automatic: while the fronts fill kPreserveBoundedWaves waves of
  // resident threads; a launch of a few waves is slower bounded.
  AutoSwitch preserve_bound = AutoSwitch::automatic;
  // Preserve with two front nodes a thread, their gathered loads in flight together
  // (PreserveTwoNodesFn, front/operations.h), where no launch spreads. automatic: on CUDA
  // while the fronts fill kPreserveTwoNodesWaves waves of resident threads (exec/tuning.h).
  AutoSwitch preserve_two_nodes = AutoSwitch::automatic;
};

// Pipeline c's inspection and Formula 2 (paper §4.1-4.2, docs/design.md "Quality and
// restructuring"). A node is degraded when its Q (Formula 1) exceeds `quality` times Q of
// the root right after the last rebuild; candidates are the topmost degraded subtrees of
// min_leaves to max_fraction * N leaves. Formula 2 on the share of leaves inside
// candidates: below threshold_refit only refit, below threshold_build restructure the
// candidates, otherwise rebuild.
struct RestructureConfig {
  double quality = 3.0;
  uint32_t min_leaves = 32;
  double max_fraction = 0.25;
  double threshold_refit = 0.05;
  double threshold_build = 0.5;
  // A restructure runs only where what this run measured says it pays for itself
  // (pipeline/restructure_price.h); off: wherever Formula 2 says (the paper).
  bool priced = true;
};

// First capacities of the growing buffers; each grows (counted, listed after the run) when
// exceeded.
struct CapacityConfig {
  double pairs_per_triangle = 8.0;
  // Front nodes per triangle and kind (internal, external).
  double front_per_triangle = 8.0;
};

// How kernels are launched and timed.
struct LaunchConfig {
  // Front pipelines on CUDA: the steady-state frame (refit and preserve, the same kernels
  // with the same arguments frame after frame) is captured once in a CUDA graph and
  // replayed while nothing it launches changes. The host executor ignores it. Off by
  // default: plain launches with dependent launch ran steady frames faster than replays,
  // and every update costs a new recording (docs/design.md "CUDA graphs for steady frames").
  bool cuda_graph = false;
  // CUDA: launch kernels so that each may be scheduled while the one before it runs
  // (ExecOptions::dependent_launch). The host executor ignores it.
  bool dependent_launch = true;
  // Time each phase of a frame (refit, preserve, ...) with events; off: only the frame and
  // its upload, so no event stands between two kernels.
  bool phase_timing = true;
};

struct PipelineConfig {
  std::string name = "bvh";     // see pipeline_names()
  std::string device = "cuda";  // cuda | cpu
  // Co-vertex filtering: pairs of triangles sharing a vertex are not reported.
  bool skip_adjacent = false;
  BoxConfig boxes;
  TreeConfig tree;
  FrontConfig fronts;
  RestructureConfig restructure;
  CapacityConfig capacity;
  LaunchConfig launch;
};

// Whether a frame builds its hierarchy: the first, and with --rebuild-every K every K-th.
inline bool rebuild_due(uint64_t frame, uint32_t rebuild_every) {
  return frame == 0 || (rebuild_every > 0 && frame % rebuild_every == 0);
}

// --refit-every: whether a frame that does not rebuild refits its hierarchy (otherwise it
// keeps the last frame's boxes: not conservative).
inline bool refit_due(uint64_t frame, uint32_t refit_every) {
  return refit_every <= 1 || frame % refit_every == 0;
}

// What a frame cost. Under --repeat the times are the mean over the passes.
struct FrameTiming {
  std::array<double, kPhaseCount> phase_ms{};
  double total_ms = 0.0;      // the frame without its upload
  uint32_t repeats = 1;       // passes the times are the mean of
  double total_noise = 0.0;   // relative standard deviation of total_ms over them (0: one pass)
  uint32_t query_reruns = 0;  // queries re-run because the pair buffer had to grow
  uint32_t host_syncs = 0;    // host-device synchronizations in the frame (target: 1)
  // Buffers allocated between the frame's start and stop in its first run (not a re-run
  // after a growth, which comes after the stop). Front pipelines fill it; 0 elsewhere.
  uint32_t allocations = 0;
  // --rebuild-ahead, on a frame that adopted a build ahead: what that build ran on its side
  // stream, beside earlier frames (not part of total_ms); 0 elsewhere.
  double ahead_ms = 0.0;
  // Bytes the frame must move at least (positions and faces read, pairs written): the
  // bandwidth floor's numerator, filled by the frame loop.
  uint64_t bytes_floor = 0;
  // --cuda-graph: "captured" (the frame recorded its graph, then launched it), "replayed"
  // (it launched a graph recorded earlier) or "" (ran as plain launches).
  std::string graph;
};

// The front pipelines' fronts after a frame, in nodes.
struct FrontSizes {
  uint64_t internal = 0, external = 0;  // the self fronts of T_D
  // A split scene's other fronts (internal + external nodes): T_D's leaves against T_R, and
  // T_R's self fronts (docs/design.md "Deformable and rigid objects").
  uint64_t inter = 0, rigid = 0;
  // --update-in-place: how far the fronts' order has decayed (FrontQuery::disorder), the
  // largest of the queries.
  double disorder = 0.0;
  // --front-cycle auto: on a frame that probed before a maintenance, the front nodes an
  // update would make over those a rebuild would (pipeline/tree_maintenance.h; 0: no probe).
  double rebuild_growth = 0.0;
  // On a probing frame: the front nodes an update of the fronts would make at most, all
  // queries (FrontQuery::update_yield; 0: no probe).
  uint64_t update_yield = 0;
};

// The quality of T_D (paper §4.1): Formula 1 at the root, and in pipeline c what this
// frame's inspection found (candidates, their leaves, their mean Q) and the Formula 2
// decision taken at its start on the previous inspection ("" if none).
struct QualityStats {
  double q_root = 0.0;  // internal / external front nodes, when ordered
  uint64_t candidates = 0, candidate_leaves = 0;
  double q_candidates = 0.0;
  std::string decision;
};

// --check: the frame's pairs against the exact oracle (recall must be 1 for every
// conservative pipeline; precision < 1 means pairs the oracle does not have).
struct FrameCheck {
  bool checked = false;
  double recall = 0.0, precision = 0.0;
  uint64_t missed = 0, false_positives = 0;
  // Narrow phase: reported pairs whose triangles are in contact, i.e. within
  // --contact-distance (0: intersecting; exact tests, lib/narrow), and their share of the
  // reported pairs (1 when there are none).
  uint64_t contacts = 0;
  double contact_precision = 0.0;
  // Reported pairs the discrete oracle lacks (only swept or fat boxes find them) whose
  // triangles come within --contact-distance at a sampled time of the interval from the
  // previous frame to this one: contacts of the interval that discrete boxes miss (a lower
  // bound: narrow/contacts.h count_interval_contacts).
  uint64_t discrete_missed_contacts = 0;
};

// A frame's pairs by query kind in a scene that declares queries: within one object (self)
// and between two (inter); self + inter = pairs.
struct QueryPairs {
  uint64_t self = 0, inter = 0;
};

struct FrameStats {
  uint64_t pairs = 0;
  // Scenes with declared queries: the pairs by query kind (counted by the run loop after the
  // frame, outside its time); none otherwise.
  std::optional<QueryPairs> query_pairs;
  std::string op;  // what the frame did: hierarchy (build/refit) + front operation
  // Front pipelines: the frame's plan step (pipeline/plan_step.h), recorded per pass in the
  // results file and replayed by later passes; none for pipelines without a frame plan.
  std::optional<PlanStep> plan;
  // --repeat: passes whose plan step at this frame differs from the recorded pass's (0: every
  // pass ran the same operations, so the frame's mean is over like work).
  uint32_t plan_mixed = 0;
  FrameTiming timing;
  FrontSizes fronts;
  QualityStats quality;
  FrameCheck check;
};

struct RecordedPlan;  // pipeline/plan_record.h

// A frame's float positions, `count` of them: in host memory, uploaded to the executor
// (resident = false), or already in the executor's memory and read where they lie (resident:
// device memory the caller owns on CUDA, host memory on the host executor). With swept boxes a
// resident frame is copied once on the executor, since the next frame's boxes read it after
// the caller has moved on.
struct FrameVertices {
  const vec3f* data = nullptr;
  size_t count = 0;
  bool resident = false;
  // Resident on CUDA: the cudaStream_t (nullptr: the legacy default stream) whose work so far
  // writes the positions; the frame's kernels wait for it on the device, the host does not.
  void* stream = nullptr;
};

// The last frame's pairs where the pipeline keeps them (executor memory: device memory on
// CUDA), unsorted; valid until the next frame or set_topology.
struct ResidentPairs {
  const PrimPair* data = nullptr;
  size_t count = 0;
};

class Pipeline {
 public:
  virtual ~Pipeline() = default;
  virtual void set_topology(const Topology& topology) = 0;
  // Front pipelines, from the next set_topology on: every frame runs its step of `plan`
  // instead of planning its own (FramePlanner::replay; nullptr: plan again). Throws Error
  // naming the plan's frame when a step cannot run on this pipeline. False for pipelines
  // without a frame plan, which ignore it.
  virtual bool replay_plan(std::shared_ptr<const RecordedPlan>) { return false; }
  // A frame of float positions, run as they are.
  virtual FrameStats run_frame(const FrameVertices& vertices) = 0;
  FrameStats run_frame(const std::vector<vec3f>& vertices) { return run_frame(FrameVertices{vertices.data(), vertices.size()}); }
  // A frame as the scene holds it, in double: rounded to floats as the box precision says
  // (fp64 rebases; the origin is picked at the first frame after set_topology), then run.
  // The rounding is host work before the frame, not part of its time. Throws UsageError
  // when --box-margin takes a box of the rounded frame past float range.
  FrameStats run_frame(const std::vector<vec3d>& positions) {
    rounding_.round(positions, rounded_);
    check_margin_in_float_range(rounded_, margin_, widen_);
    return run_frame(rounded_);
  }
  // The last frame's pairs, sorted, for verification (a download; not part of a frame).
  virtual std::vector<PrimPair> sorted_pairs() = 0;
  virtual ResidentPairs resident_pairs() const = 0;
  virtual const MemoryStats& memory() const = 0;

 protected:
  explicit Pipeline(const BoxConfig& boxes)
      : rounding_(boxes.precision == BoxPrecision::fp64), margin_(boxes.margin), widen_(widens_boxes(boxes)) {}
  // For set_topology: the next double frame picks the origin again.
  void restart_rounding() { rounding_.restart(); }

 private:
  PositionRounding rounding_;
  std::vector<vec3f> rounded_;
  float margin_;
  bool widen_;
};

// The GPU this process would run on, or why there is none.
struct CudaDeviceInfo {
  bool available = false;
  std::string name, reason;
  int driver_version = 0, runtime_version = 0;
  size_t total_bytes = 0;
  int device_count = 0;  // GPUs visible to this process
};
CudaDeviceInfo cuda_device_info();

}  // namespace cdb
