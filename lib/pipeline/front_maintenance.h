#pragma once
// When a front pipeline updates its fronts (paper Fig. 4, operation 3) instead of preserving
// them (2). Preserving stale fronts is exact (a front partitions its leaf's range however
// stale: front/front.h), but its cost grows as the geometry drifts from the fronts; an update
// costs more than a preserve once and starts the growth over.
//
// Fixed cycle (--front-cycle K, the paper's scheme): every K-th frame since the fronts were
// generated updates.
//
// Adaptive (--front-cycle auto): rent or buy, on measured frame times. Each steady frame
// (refit + preserve) since the fronts were last produced pays rent: its cost over the
// cheapest steady frame of the same stretch, i.e. what the fronts' staleness costs. The
// fronts update once the rent paid reaches what an update of fresh fronts costs over a
// steady frame. For rent that grows linearly with time (a per frame) this updates every
// sqrt(2U/a) frames, the best fixed cycle's length; whatever the growth, the total stays
// within twice that of the best schedule in hindsight (the ski-rental bound). Scenes whose
// fronts barely degrade update rarely, scenes whose fronts degrade fast often, and timing
// noise alone only lets the rent creep up, so an update still comes now and then.
//
// The price U of an update is per front node: the cheapest measured so far, per node of the
// front it updated, times the nodes of the front now. An update's work follows the front's
// size, which changes as a scene folds or spreads, and its staleness: an update of stale
// fronts costs more than one of fresh fronts, by about a constant per frame of staleness,
// which is rent too. That moves the best cycle's cost, not its length, so the price that sets
// the length is the fresh update's, the cheapest. Pricing by the last update instead feeds on
// itself: a late update is dear, which makes the next one later still. Updates that outgrew
// their buffers ran twice and price only until one runs once. Until an update is measured,
// the price is the build frame's cost (its first pass, where it ran again) over a steady
// frame divided by kBuildPerUpdate, a ratio measured on the anchor scenes, so fronts that
// degrade fast get a first update soon and fronts that barely degrade none in a short run. Figures and what
// was tried: docs/front-maintenance.md.
//
// What a maintenance runs (regenerate): an update, or a generate of new fronts from the
// current tree, whichever its last measured cost per front node says is cheaper. A generate
// costs what the geometry costs, however stale the fronts; an update of stale fronts can
// cost more (sphere) or less (the falling spheres). Before a maintenance generate ran, the build frame's
// generate and ordering (timed alone) per front node made stand for it: a bound, since a
// maintenance generate's cost over a steady frame leaves out the preserve it replaces. A
// generate is tried once that bound is below the cost of an update after the first (the
// first update of a run is its dearest: against it the bound let the generate be tried on
// every scene); from then on each maintenance runs the one measured cheaper last, which
// re-measures it, so a choice that grew dear gives way; trying it where it loses costs one
// dear frame a run (docs/front-maintenance.md has the figures).
#include <algorithm>
#include <cstdint>
#include <limits>

#include "cdbench/exec/tuning.h"

namespace cdb {

// What a frame of a front pipeline ran, as FrontMaintenance prices it.
enum class FrameKind {
  steady,     // refit + preserve
  updated,    // the fronts updated (and nothing heavier ran with it)
  generated,  // the fronts generated on a refitted tree (a maintenance)
  built,      // the tree built and the fronts generated
  other,      // anything else (a restructure, a preserve on stale boxes): not priced
};

// A frame's measured cost (FrontMaintenance::observe).
struct FrameCost {
  FrameKind kind = FrameKind::other;
  double ms = 0.0;
  uint64_t front_nodes = 0;  // the fronts it started from
  // It ran its operations once (no buffer grew) and recorded no frame graph.
  bool once = true;
};

class FrontMaintenance {
 public:
  static constexpr uint32_t kAuto = 0;
  // kBuildPerUpdate: exec/tuning.h.

  // cycle: frames per fixed cycle, or kAuto.
  // regenerate: adaptive maintenances may generate instead of update.
  explicit FrontMaintenance(uint32_t cycle = kAuto, bool regenerate = false) : cycle_(cycle), regenerate_(regenerate) {}

  bool adaptive() const { return cycle_ == kAuto; }

  // Forget every measurement (a new run over the frames).
  void reset() { *this = FrontMaintenance(cycle_, regenerate_); }

  // Whether an adaptive maintenance due now generates new fronts instead of updating them.
  bool generate_due() const {
    if (!regenerates() || update_last_ < 0.0) return false;
    if (generate_last_ >= 0.0) return generate_last_ < update_last_;
    // Not tried yet: against an update after the first, the dearest of a run.
    return updates_once_ >= 2 && build_generate_ >= 0.0 && build_generate_ < update_last_;
  }

  // Whether maintenances may generate (adaptive, regenerate on).
  bool regenerates() const { return adaptive() && regenerate_; }

  // A build frame's generate and ordering per front node made (see generate_due).
  void observe_build_generate(double per_node_ms) { build_generate_ = per_node_ms; }

  // Whether the frame `frame` should update fronts of `front_nodes` nodes generated at
  // `generated` and last produced (generated, updated or restructured) at `produced`.
  bool update_due(uint64_t frame, uint64_t generated, uint64_t produced, uint64_t front_nodes) const {
    if (!adaptive()) return frame > generated && (frame - generated) % cycle_ == 0;
    if (frame <= produced) return false;
    return steady_ > 0 && rent_ms() >= price_ms(front_nodes);
  }

  // Whether the frame after `frame` may update, so that `frame`, if it preserves, should
  // probe: count what an update of its fronts would produce, for their buffers to be sized
  // before the update instead of growing inside it and running it again. Fixed cycle: the
  // frame before an update. Adaptive: where the rent paid and what the next steady frame is
  // expected to pay reach the price: the last frame's cost, plus its rise over the frame
  // before where it rose (exact where the rent grows linearly). A maintenance that comes due
  // unprobed all the same (a frame dearer than expected) waits a frame for its probe
  // (FramePlanner).
  bool update_near(uint64_t frame, uint64_t generated, uint64_t produced, uint64_t front_nodes) const {
    if (!adaptive()) return update_due(frame + 1, generated, produced, front_nodes);
    if (frame <= produced || steady_ == 0) return false;
    const double rise = steady_ > 1 ? std::max(0.0, steady_last_ - steady_before_) : 0.0;
    return rent_ms() + steady_last_ + rise - steady_min_ >= price_ms(front_nodes);
  }

  // The cheapest steady frame since the fronts were last produced (fresh fronts), in ms.
  double fresh_ms() const { return steady_min_; }

  // The rent paid since the fronts were last produced, in ms.
  double rent_ms() const { return steady_ > 0 ? steady_sum_ - double(steady_) * steady_min_ : 0.0; }

  bool priced() const { return price_per_node_ms_ >= 0.0; }

  // What an update of fresh fronts of `front_nodes` nodes costs over a steady frame, in ms:
  // measured, or before any update was, guessed from the build frame (0 before a steady
  // frame was measured).
  double price_ms(uint64_t front_nodes) const {
    if (generate_due() && generate_last_ >= 0.0) return generate_last_ * double(std::max<uint64_t>(front_nodes, 1));
    if (priced()) return price_per_node_ms_ * double(std::max<uint64_t>(front_nodes, 1));
    return steady_ > 0 ? std::max(0.0, build_ms_ - steady_min_) / kBuildPerUpdate : 0.0;
  }

  // A frame's measured cost. A steady frame that grew a buffer or recorded its graph paid a
  // one-off cost, not rent for stale fronts: it is left out (counted, such frames brought
  // updates frames early: docs/front-maintenance.md).
  void observe(const FrameCost& frame) {
    const double ms = frame.ms;
    const bool once = frame.once;
    if (frame.kind == FrameKind::built) build_ms_ = ms;
    if (frame.kind == FrameKind::steady) {
      if (!once) return;
      steady_sum_ += ms;
      steady_before_ = steady_last_;
      steady_last_ = ms;
      steady_min_ = std::min(steady_min_, ms);
      ++steady_;
      return;
    }
    const bool generated = frame.kind == FrameKind::generated;
    if (!(frame.kind == FrameKind::updated || generated) || steady_ == 0) return;
    // Over the cheapest steady frame before it: the cost of a steady frame on fresh fronts.
    const double per_node = std::max(0.0, ms - steady_min_) / double(std::max<uint64_t>(frame.front_nodes, 1));
    if (generated) {
      if (once) generate_last_ = per_node;
      return;
    }
    if (once) {
      update_last_ = per_node;
      ++updates_once_;
    }
    if (!once && clean_) return;
    price_per_node_ms_ = priced() && (clean_ || !once) ? std::min(price_per_node_ms_, per_node) : per_node;
    clean_ = clean_ || once;
  }

  // The fronts were produced this frame: the rent starts over.
  void produced() {
    steady_sum_ = 0.0;
    steady_last_ = steady_before_ = 0.0;
    steady_min_ = std::numeric_limits<double>::infinity();
    steady_ = 0;
  }

 private:
  uint32_t cycle_;
  bool regenerate_;
  double price_per_node_ms_ = -1.0;  // the cheapest measured update per front node
  double update_last_ = -1.0;        // the last update per front node that ran once
  double generate_last_ = -1.0;      // the last maintenance generate per front node that ran once
  double build_generate_ = -1.0;     // the last build frame's generate per front node made
  uint32_t updates_once_ = 0;        // updates measured (ran once)
  double build_ms_ = 0.0;            // the last frame that built the tree
  bool clean_ = false;               // that price comes from updates that ran once
  double steady_sum_ = 0.0;
  double steady_last_ = 0.0;    // the last steady frame counted
  double steady_before_ = 0.0;  // the one before it
  double steady_min_ = std::numeric_limits<double>::infinity();
  uint64_t steady_ = 0;
};

}  // namespace cdb
