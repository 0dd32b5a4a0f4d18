#pragma once
// Every constant that only trades speed, in one place, as CUB's tuning headers keep theirs:
// values that change no result, only how fast it comes. Each line says what measured it;
// the figures are in docs/design.md "Constants and their measurements". All were measured
// on sm_90 (H100 and H200); other architectures run the same values until measured.
#include <cstddef>
#include <cstdint>

namespace cdb {

// --- Launch shapes (CUDA executor) ---
// Threads of a staged kernel's block (for_each_staged). Measured: 128 (half-size stages)
// and 512 against 256 on update and preserve (H100).
inline constexpr uint32_t kStagedThreads = 256;
// Threads of a plain launch's block (for_each_n). Not measured apart: a common choice.
inline constexpr uint32_t kForEachThreads = 256;
// A functor's kernels (for_each_n, for_each_staged) may ask for F::kMinBlocksPerSm resident
// blocks (their __launch_bounds__): the compiler then holds each thread's registers to what
// that many blocks leave it, so that more warps hide the latency of a traversal's loads.
// 0: no bound (every functor that does not say).
template <class F>
constexpr uint32_t min_blocks_per_sm() {
  if constexpr (requires { F::kMinBlocksPerSm; })
    return F::kMinBlocksPerSm;
  else
    return 0;
}
// Preserve's blocks per SM under its bound (PreserveFrontFn, --preserve-bound): 8 holds it
// to 32 registers (from 40, some spilled), 64 resident warps an SM instead of 48; 7 gives
// the same 32. --preserve-bound auto: bounded while the fronts fill this many waves of
// resident threads. Measured: H200, 1.03-1.05x from 5 waves up, 0.88x at 2.5 (docs/design.md).
inline constexpr uint32_t kPreserveMinBlocks = 8;
inline constexpr uint64_t kPreserveBoundedWaves = 4;
// --preserve-two-nodes auto: two front nodes a preserve thread (PreserveTwoNodesFn) while
// the fronts fill this many waves of resident threads, where each lane traverses alone
// (kWarpSharingWaves). Measured (H200): the cloths of 522K, 1M and 10M triangles (45, 89
// and 890 waves) 0.95x, 0.92x and 0.90x the time a frame; the garment (17 waves, shared in
// warps) 1.15x.
inline constexpr uint64_t kPreserveTwoNodesWaves = 32;
// Threads of the one-block kernels (in_one_block): the hardware's limit, not a measurement.
inline constexpr uint32_t kOneBlockThreads = 1024;
// The reduction's block size and most partials. Not measured: a common choice.
inline constexpr uint32_t kReduceThreads = 256;
inline constexpr uint32_t kReduceBlocks = 512;
// exclusive_scan_pair: arrays up to this long scan in one block each, longer ones by device
// scans. Measured: Nsight Compute on count logs of 9K and 32K values (H100).
inline constexpr size_t kPairScanBlockMax = size_t(1) << 14;
// The one-block scan's tile: threads and values per thread. Measured: the same study,
// against 16 values a thread with warp scans.
inline constexpr uint32_t kPairScanThreads = 1024, kPairScanItems = 4;

// --- Front traversals ---
// Spread launches (front/warp_traversal.h): the most waves of resident threads a spread
// launch may fill, per operation. Measured: one against four waves for generate (32K and
// 48K leaves), update (sphere, funnel, falling spheres) and preserve (H100).
inline constexpr uint64_t kSpreadWavesGenerate = 1;
inline constexpr uint64_t kSpreadWavesPreserve = 1;
inline constexpr uint64_t kSpreadWavesUpdate = 4;
// --preserve-warp/--update-warp auto: warp sharing while the fronts fit in this many waves
// of resident threads. Measured: warp-shared preserve on funnel and cloth-ball against the
// 1M and 10M cloths (H100).
inline constexpr uint64_t kWarpSharingWaves = 32;
// Preserve stages its pairs per block while a block of front nodes yields at least this
// many pairs. Measured: pairs per block on the cloths and n-body, staged against direct
// appends (H100).
inline constexpr uint64_t kStagedPairsPerBlock = 32;
// Slots a count every block adds to is spread over (blockIdx % kStopSlots). Not measured
// apart: probing frames cost what replayed frames did on cloth-ball (H100).
inline constexpr uint32_t kStopSlots = 16;

// --- Refit ---
// Most leaves a refit tile holds (one block; its shared memory stays under the static
// limit, 1024 would not). Measured: 256 against 512 on four scenes (H100).
inline constexpr uint32_t kRefitTile = 512;
// Default of --refit-top-leaves: the largest tree whose top refits in one block. Measured:
// one block against hand-over between blocks, by tree size (docs/results.md).
inline constexpr uint32_t kRefitTopMaxLeaves = 1u << 15;
// Spanning nodes the one-block top refit keeps in shared memory. Measured: 384 against
// 1536 slots on three scenes, within noise (H100).
inline constexpr uint32_t kRefitTopSharedSlots = 1536;

// --- Front maintenance (pipeline/front_maintenance.h) ---
// Before any update was measured, a build frame's first pass, its cost over a steady frame
// divided by this, is an update's price. Measured (H200): 4 over the first pass ran
// 0.95-1.06x of 8 over the build frame counted with its re-run and growth (about twice its
// first pass), the rule before; 8 over the first pass 0.86-1.04x (docs/front-maintenance.md).
inline constexpr double kBuildPerUpdate = 4.0;
// A maintenance rebuilds where the probe counts an update would make fronts of more than
// this many times what a rebuild would (pipeline/tree_maintenance.h). Measured: updates grow
// the fronts per pair 1.05-1.9x on the cloths, funnel, crumple and cloth-ball, 2-3x on the
// garment and the falling spheres (H200); 1.5 rebuilt the funnel and crumple, 2.5 missed
// the garment's first maintenance.
// With rebuilds built ahead, whose frames do not wait for them, 1 and 1.4 ran within noise
// of 2 on six scenes (H200, docs/front-maintenance.md "Rebuilds built ahead").
inline constexpr double kRebuildGrowth = 2.0;
// ... and where that growth, less one, came at more than this much a frame since the build.
// Measured by host replays of H200 plans at the probes that crossed kRebuildGrowth.
inline constexpr double kRebuildRate = 0.08;

// --- Front buffers (pipeline/front_query.h) ---
// Spare over a probe's update bound: the fronts' buffers grow to bound + bound / this when
// they hold less. It covers the motion from the probed frame to the update's. Measured: on
// the falling spheres (fixed cycles 10, 20, 30; host executor) an update made at most 4.4%
// more than the bound of the frame before it. A quarter would hold the 522K cloth's
// internal fronts 1.2M nodes (19 MiB) larger.
inline constexpr size_t kProbeSpareDiv = 8;
// Spare over a produced front that did not fit, when its buffers grow: the run again fits
// exactly, the spare is for the fronts that the next frames produce before a probe sizes
// them (generates after a rebuild, restructures). Not measured apart: the probe's spare.
inline constexpr size_t kRegrowSpareDiv = 8;
// Spare over what a build ahead's fronts are expected to hold (FrontPipeline::
// build_expected, FrontQuery::reserve_ahead): they are generated on a new tree frames
// later, while contact may grow. On
// the flag (host executor, every maintenance built ahead) an eighth let one adoption in
// five outgrow its fronts (126K internal nodes generated against 97K held when it was
// launched) and generate them again in its frame; half held all five.
inline constexpr size_t kAheadSpareDiv = 2;

// --- Baselines ---
// Cell entries per box before the first frame's count (grid and hash); a short guess
// re-runs frame 0 only. Not measured: a box covers 1 to 8 cells of its level.
inline constexpr size_t kEntriesPerBoxEstimate = 8;

// --- Host executor ---
// Below this many elements a host scan runs on one thread. Not measured: where the second
// pass over the chunks costs more than it saves.
inline constexpr size_t kParallelScanMin = size_t(1) << 15;
// Chunks of the host scan, sort and reduction; a fixed count keeps results independent of
// the thread count. Not measured.
inline constexpr size_t kScanChunks = 64;
inline constexpr size_t kReduceChunks = 64;
inline constexpr size_t kSortChunks = 64;
// The host radix sort's digit and the keys a chunk takes at least. Not measured.
inline constexpr int kSortDigitBits = 11;
inline constexpr size_t kSortChunkKeys = size_t(1) << 14;

}  // namespace cdb
