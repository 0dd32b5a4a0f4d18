#include "harness/results/results_columns.h"

#include "cdbench/core/phase.h"

namespace cdb {

const std::vector<FrameColumn>& frame_columns() {
  static const std::vector<FrameColumn> columns = [] {
    using T = ColumnType;
    using R = const FrameRow&;
    std::vector<FrameColumn> c = {
        {"frame", T::u32, "frame index in the scene", [](R r) -> ColumnValue { return uint64_t(r.frame); }},
        {"t_total_ms", T::f64, "frame time without its upload, ms", [](R r) -> ColumnValue { return r.stats.timing.total_ms; }},
    };
    for (size_t p = 0; p < kPhaseCount; ++p)
      c.push_back({std::string("t_") + kPhaseNames[p] + "_ms", T::f64,
                   std::string("time in phase ") + kPhaseNames[p] + ", ms (0: did not run)",
                   [p](R r) -> ColumnValue { return r.stats.timing.phase_ms[p]; }});
    const std::vector<FrameColumn> rest = {
        {"pairs", T::u64, "pairs reported", [](R r) -> ColumnValue { return r.stats.pairs; }},
        {"repeats", T::u32, "--repeat: passes the frame's times are the mean of", [](R r) -> ColumnValue { return uint64_t(r.stats.timing.repeats); }},
        {"t_total_noise", T::f64, "--repeat: relative standard deviation of t_total_ms over the passes (0: one pass)", [](R r) -> ColumnValue { return r.stats.timing.total_noise; }},
        {"host_syncs", T::u32, "host-device synchronizations in the frame (target: 1, the counters' read-back)", [](R r) -> ColumnValue { return uint64_t(r.stats.timing.host_syncs); }},
        {"bytes_floor", T::u64, "bytes the frame must move at least: 12 per vertex and per face read, 8 per pair written", [](R r) -> ColumnValue { return r.stats.timing.bytes_floor; }},
        {"t_ahead_ms", T::f64, "--rebuild-ahead: on a frame that adopted a build ahead, what the build ran on its side stream beside earlier frames, ms (not in t_total_ms; 0: none)", [](R r) -> ColumnValue { return r.stats.timing.ahead_ms; }},
        {"query_reruns", T::u32, "queries re-run because a buffer grew", [](R r) -> ColumnValue { return uint64_t(r.stats.timing.query_reruns); }},
        {"allocations", T::u32, "front pipelines: buffers allocated between the frame's start and stop, its first run, the most of any --repeat pass (growths after a read-back come after the stop; 0 elsewhere)", [](R r) -> ColumnValue { return uint64_t(r.stats.timing.allocations); }},
        {"front_int", T::u64, "internal front nodes after the frame", [](R r) -> ColumnValue { return r.stats.fronts.internal; }},
        {"front_ext", T::u64, "external front nodes after the frame", [](R r) -> ColumnValue { return r.stats.fronts.external; }},
        {"front_inter", T::u64, "split scene: front nodes of the deformable leaves against the rigid tree after the frame", [](R r) -> ColumnValue { return r.stats.fronts.inter; }},
        {"front_disorder", T::f64, "front pipelines: entries changed by updates in place since the fronts were last produced whole (holes plus appended nodes), as a share of their nodes; the largest of the queries", [](R r) -> ColumnValue { return r.stats.fronts.disorder; }},
        {"rebuild_growth", T::f64, "--front-cycle auto: on a frame that probed before a maintenance, the front nodes an update would make over those a rebuild would (0: no probe)", [](R r) -> ColumnValue { return r.stats.fronts.rebuild_growth; }},
        {"front_rigid", T::u64, "split scene: self front nodes of the rigid tree after the frame", [](R r) -> ColumnValue { return r.stats.fronts.rigid; }},
        {"q_root", T::f64, "Formula 1 at the root (ordered pipelines; else 0)", [](R r) -> ColumnValue { return r.stats.quality.q_root; }},
        {"candidates", T::u64, "pipeline c: restructure candidates found by this frame's inspection", [](R r) -> ColumnValue { return r.stats.quality.candidates; }},
        {"candidate_leaves", T::u64, "pipeline c: leaves inside those candidates", [](R r) -> ColumnValue { return r.stats.quality.candidate_leaves; }},
        {"q_candidates", T::f64, "pipeline c: mean Q (Formula 1) of those candidates", [](R r) -> ColumnValue { return r.stats.quality.q_candidates; }},
        {"decision", T::text, "pipeline c: Formula 2 decision taken at the frame's start (refit, restructure, rebuild; empty: none)", [](R r) -> ColumnValue { return r.stats.quality.decision; }},
        {"checked", T::u32, "--check: 1 when this frame was compared with the exact oracle", [](R r) -> ColumnValue { return uint64_t(r.stats.check.checked); }},
        {"recall", T::f64, "--check: oracle pairs found / oracle pairs (0 when not checked)", [](R r) -> ColumnValue { return r.stats.check.recall; }},
        {"precision", T::f64, "--check: reported pairs the oracle has / reported pairs (0 when not checked)", [](R r) -> ColumnValue { return r.stats.check.precision; }},
        {"missed", T::u64, "--check: oracle pairs not reported", [](R r) -> ColumnValue { return r.stats.check.missed; }},
        {"false_positives", T::u64, "--check: reported pairs the oracle does not have", [](R r) -> ColumnValue { return r.stats.check.false_positives; }},
        {"contacts", T::u64, "--check: reported pairs whose triangles lie within --contact-distance (0: intersect; exact tests; co-vertex pairs count)", [](R r) -> ColumnValue { return r.stats.check.contacts; }},
        {"contact_precision", T::f64, "--check: contacts / reported pairs (1 with no pairs; 0 when not checked)", [](R r) -> ColumnValue { return r.stats.check.contact_precision; }},
        {"discrete_missed_contacts", T::u64, "--check: reported pairs the discrete oracle lacks whose triangles come within --contact-distance at one of the --contact-substeps samples of the interval from the previous frame (a lower bound)", [](R r) -> ColumnValue { return r.stats.check.discrete_missed_contacts; }},
        {"op", T::text, "what the frame did: hierarchy + front operation; --repeat-plan free: the passes' different operations joined by |", [](R r) -> ColumnValue { return r.stats.op; }},
        {"plan_mixed", T::u32, "--repeat: passes whose plan step (/plans) at this frame differs from the recorded pass's (0: every pass ran the same operations)", [](R r) -> ColumnValue { return uint64_t(r.stats.plan_mixed); }},
        {"graph", T::text, "--cuda-graph: captured (recorded its CUDA graph, then launched it), replayed (launched one recorded earlier) or empty (plain launches)", [](R r) -> ColumnValue { return r.stats.timing.graph; }},
        {"device_bytes", T::u64, "executor memory in use after the frame, bytes", [](R r) -> ColumnValue { return uint64_t(r.memory.current_bytes); }},
        {"device_peak_bytes", T::u64, "executor memory peak so far, bytes", [](R r) -> ColumnValue { return uint64_t(r.memory.peak_bytes); }},
        {"buffer_growths", T::u64, "buffer growths so far", [](R r) -> ColumnValue { return uint64_t(r.memory.growths); }},
    };
    c.insert(c.end(), rest.begin(), rest.end());
    return c;
  }();
  return columns;
}

const std::vector<FrameColumn>& query_pair_columns() {
  static const std::vector<FrameColumn> columns = [] {
    using T = ColumnType;
    using R = const FrameRow&;
    return std::vector<FrameColumn>{
        {"pairs_self", T::u64, "declared queries: pairs within one object (the self queries); pairs_self + pairs_inter = pairs", [](R r) -> ColumnValue { return r.stats.query_pairs->self; }},
        {"pairs_inter", T::u64, "declared queries: pairs between two objects (the inter queries)", [](R r) -> ColumnValue { return r.stats.query_pairs->inter; }},
    };
  }();
  return columns;
}

const std::vector<PlanColumn>& plan_columns() {
  static const std::vector<PlanColumn> columns = [] {
    using T = ColumnType;
    using R = const PlanRow&;
    std::vector<PlanColumn> c = {
        {"pass", T::u32, "--repeat: the pass over the frames (0: the first)", [](R r) -> ColumnValue { return uint64_t(r.pass); }},
        {"frame", T::u32, "frame index in the scene", [](R r) -> ColumnValue { return uint64_t(r.frame); }},
        {"trees", T::text, "the hierarchy: build, refit or stale (--refit-every kept its boxes)", [](R r) -> ColumnValue { return std::string(tree_step_name(r.step.trees)); }},
    };
    for (Query q : kQueries)
      c.push_back({query_name(q), T::text,
                   std::string("the ") + query_name(q) + " query's front operation: generate, preserve, update or restructure (empty: the query does not run in the scene)",
                   [q](R r) -> ColumnValue { return std::string(r.step.op(q) ? front_op_name(*r.step.op(q)) : ""); }});
    c.push_back({"decision", T::text, "pipeline c: the Formula 2 decision taken at the frame's start (refit, restructure, rebuild; empty: none)", [](R r) -> ColumnValue { return std::string(formula2_name(r.step.decision)); }});
    c.push_back({"inspect", T::u32, "pipeline c: 1 when the frame inspected the tree's quality", [](R r) -> ColumnValue { return uint64_t(r.step.inspect); }});
    c.push_back({"probe", T::u32, "1 when the frame's preserve counted what an update would make (the probe before a maintenance)", [](R r) -> ColumnValue { return uint64_t(r.step.probe); }});
    return c;
  }();
  return columns;
}

const std::vector<MemoryColumn>& memory_columns() {
  static const std::vector<MemoryColumn> columns = [] {
    using T = ColumnType;
    using R = const MemoryRow&;
    return std::vector<MemoryColumn>{
        {"buffer", T::text, "the executor buffer's name (tree and front prefixes: bvh., rigid_bvh., ahead_bvh., front_internal., ahead_front_external., ...)", [](R r) -> ColumnValue { return r.buffer.buffer; }},
        {"bytes_at_peak", T::u64, "bytes the buffer held when the run's executor memory peaked (the rows sum to peak_bytes)", [](R r) -> ColumnValue { return uint64_t(r.buffer.bytes); }},
    };
  }();
  return columns;
}

}  // namespace cdb
