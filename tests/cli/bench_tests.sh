#!/usr/bin/env bash
# The GPU machine's scripts (bench/) on small CPU results and on the committed H100 results:
# perf_targets.py's A/B tables, ab_phases.py on a printed log, steady_breakdown.py.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

export OMP_NUM_THREADS=1
res=$tmp/results
"$cdbench" run --device cpu --quiet --scene funnel --frames 0:6 --pipeline static,bvh --out "$res/funnel-{pipeline}.h5" \
  >"$tmp/run.out" 2>&1 || { cat "$tmp/run.out"; fail "cdbench run"; }

# The targets report's A/B table against itself: every speed-up is 1.00x, so the control
# range is 1.00x-1.00x, the control cell says so and the other cell lies inside it.
mkdir -p "$tmp/targets"
cp "$res/funnel-bvh.h5" "$tmp/targets/steady-funnel-bvh.h5"
cp "$res/funnel-static.h5" "$tmp/targets/steady-funnel-static.h5"
check "perf_targets control range" 0 "^Controls \(bvh: code shared by both binaries\): speed-ups 1\.00x–1\.00x over 1 cells" -- \
  "$python" "$root/bench/perf_targets.py" "$tmp/targets" --base "$tmp/targets" --controls bvh
has "perf_targets control cell" "$tmp/out" "^\| steady/funnel \| bvh \|.* \| control \|$"
has "perf_targets cell inside the control range" "$tmp/out" "^\| steady/funnel \| static \| .* \| 1\.00x \|.* \| no \|$"
# ... and per phase: the static pipeline's preserve against itself, and bvh's query as the control.
has "perf_targets phase control range" "$tmp/out" "Controls' phases \(bvh\): 1\.00x–1\.00x over [0-9]+ phases"
has "perf_targets phase row" "$tmp/out" "^\| steady/funnel \| static \| preserve \| [0-9.]+ \| [0-9.]+ \| 1\.00x \| no \|$"
has "perf_targets phase control row" "$tmp/out" "^\| steady/funnel \| bvh \| query \| [0-9.]+ \| [0-9.]+ \| 1\.00x \| control \|$"
# ab_phases.py on a log in device-targets.sh's printed format: one cell, two binaries.
cat >"$tmp/ab.log" <<'LOG'
=== cloth cloth-ball b --repeat 3 (/x/bin/cdbench)
pipeline: b on cuda
  per frame   mean 0.300  median 0.200  p95 0.500  min 0.100 ms (upload excluded)
  preserve    mean 0.120  median 0.100  p95 0.200 ms  (45 frames)
=== cloth cloth-ball b --repeat 3 (/x/base/cdbench-base)
pipeline: b on cuda
  per frame   mean 0.330  median 0.220  p95 0.500  min 0.100 ms (upload excluded)
  preserve    mean 0.150  median 0.110  p95 0.200 ms  (45 frames)
LOG
check "ab_phases phase speed-up" 0 "^cloth/cloth-ball +b +preserve +cdbench-base 0\.150/0\.110 \| cdbench 0\.120/0\.100 1\.25x$" -- \
  "$python" "$root/bench/ab_phases.py" "$tmp/ab.log" cdbench-base cdbench
has "ab_phases frame row" "$tmp/out" "^cloth/cloth-ball +b +per frame +cdbench-base 0\.330/0\.220 \| cdbench 0\.300/0\.200 1\.10x$"
# Cells of one scene with other generator settings stay apart (the scaling group's sizes).
cat >"$tmp/ab-sizes.log" <<'LOG'
=== scaling cloth-wave b --set res=72 --set frames=8 --repeat 2 (/x/bin/cdbench)
pipeline: b on cuda
  per frame   mean 0.100  median 0.100  p95 0.100  min 0.100 ms (upload excluded)
=== scaling cloth-wave b --set res=224 --set frames=8 --repeat 2 (/x/bin/cdbench)
pipeline: b on cuda
  per frame   mean 0.200  median 0.200  p95 0.200  min 0.200 ms (upload excluded)
LOG
check "ab_phases keeps sizes apart" 0 "^scaling/cloth-wave res=72 +b +per frame +cdbench 0\.100/0\.100$" -- \
  "$python" "$root/bench/ab_phases.py" "$tmp/ab-sizes.log" cdbench
has "ab_phases second size" "$tmp/out" "^scaling/cloth-wave res=224 +b +per frame +cdbench 0\.200/0\.200$"
check "ab_phases unknown binary" 1 "no cell run by cdbench-other" -- \
  "$python" "$root/bench/ab_phases.py" "$tmp/ab.log" cdbench-other cdbench
check "ab_phases missing log" 1 "nowhere.log: No such file or directory" -- \
  "$python" "$root/bench/ab_phases.py" "$tmp/nowhere.log" cdbench-base cdbench
# steady_breakdown.py: the committed H100 results have graph-replayed steady frames, one row
# a pipeline; CPU results launch plain and count too; a pipeline without fronts has none.
mkdir -p "$tmp/gpu"
tar -xJf "$root/results/2026-11-25-h100/h5.tar.xz" -C "$tmp/gpu"
check "steady_breakdown on GPU results" 0 "^\| targets \| steady-funnel-b \| [0-9]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \|$" -- \
  "$python" "$root/bench/steady_breakdown.py" "$tmp/gpu/targets"
# Runs made with --phase-timing off have a total and an upload, no phases.
has "steady_breakdown untimed run" "$tmp/out" "^\| targets \| untimed-funnel-b \| [0-9]+ \| [0-9.]+ \| — \| — \| — \| [0-9.]+ \|$"
# The funnel-size target is judged on the untimed runs, with four digits.
check "perf_targets judges the steady frame untimed" 0 \
  "^\| steady frame of a/b/c at funnel size ≤ 0\.050 \| 0\.[0-9]{4}–0\.[0-9]{4} \(median of the steady refit\+preserve frames, phases untimed\) \| (met|\*\*not met\*\*) \|$" -- \
  "$python" "$root/bench/perf_targets.py" "$tmp/gpu/targets"
check "steady_breakdown on plain CPU frames" 0 "^\| targets \| steady-funnel-static \| [0-9]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.-]+ \| [0-9.]+ \|$" -- \
  "$python" "$root/bench/steady_breakdown.py" "$tmp/targets"
mkdir -p "$tmp/no-fronts"
cp "$res/funnel-bvh.h5" "$tmp/no-fronts/"
check "steady_breakdown without steady frames" 1 "no steady refit\+preserve frames" -- \
  "$python" "$root/bench/steady_breakdown.py" "$tmp/no-fronts"
check "perf_targets unknown control" 1 "--controls: unknown pipeline\(s\) gird" -- \
  "$python" "$root/bench/perf_targets.py" "$tmp/targets" --base "$tmp/targets" --controls gird

# bar_report.py: the new binary's five pipelines and a base binary's c and b on one scene;
# the base is the same files, so base over new is 1.00x, as is the peak, and funnel has no
# peer to judge. On the CPU nothing builds ahead: none of the peak is the second tree's.
mkdir -p "$tmp/bar/new" "$tmp/bar/base"
"$cdbench" run --device cpu --quiet --scene funnel --set res=16 --frames 0:4 --repeat 2 --pipeline c,b,a,grid,hash \
  --out "$tmp/bar/new/funnel-{pipeline}.h5" >"$tmp/run.out" 2>&1 || { cat "$tmp/run.out"; fail "cdbench run (bar)"; }
cp "$tmp/bar/new/funnel-c.h5" "$tmp/bar/new/funnel-b.h5" "$tmp/bar/base/"
check "bar_report scene row" 0 "^\| funnel \| [0-9,]+ \| [0-9,]+ \| [0-9.]+ / [0-9.]+ / [0-9.]+ \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ \|( [0-9.]+ \|){4} [0-9]+ \| 0 \| [0-9.]+ \| [0-9.]+ \| 1\.00x \| [0-9]+ \|$" -- \
  "$python" "$root/bench/bar_report.py" "$tmp/bar" --base base
has "bar_report targets row" "$tmp/out" "^\| funnel \| [0-9.]+ \| — \| [abc] [0-9.]+ / (grid|hash) [0-9.]+ = [0-9.]+x \((met|not met)\) \| [0-9.]+ \| [0-9.]+ \((met|not met)\) \| 1\.00 \(met\) \|$"
# The base beside new, c and b: the same files, so base over new is 1.00 and the peaks equal.
has "bar_report base beside new" "$tmp/out" "^## base beside new$"
has "bar_report base beside new c row" "$tmp/out" "^\| funnel \| c \| ([0-9.]+) / ([0-9.]+) \| \1 / \2 \| 1\.00 \| ([0-9.]+) \| \3 \| ([0-9]+) \| \4 \|$"
# A run of c alone (no b, no cell method, no base): those columns are dashes, not nan.
mkdir -p "$tmp/bar-c/new"
cp "$tmp/bar/new/funnel-c.h5" "$tmp/bar-c/new/"
check "bar_report c alone" 0 "^\| funnel \| [0-9.]+ \| — \| — \| — \| [0-9.]+ \((met|not met)\) \|$" -- \
  "$python" "$root/bench/bar_report.py" "$tmp/bar-c"

# interleave.sh: one binary as A and as B, two rounds on a tiny funnel; every process
# replays the plan A recorded first, into its own labelled file, then compare pools each
# side's files as repeats.
ab=$tmp/interleave
check "interleave: A and B compared" 0 "^verdict: [a-zA-Z-]+( \(.*\))?: funnel\[res=8\] c cpu, B against A over 2 interleaved processes each.*; plan: replayed $ab/plan/plan\.h5$" -- \
  "$root/bench/interleave.sh" --a "$cdbench" --rounds 2 --scene funnel --device cpu --frames 0:6 "$ab" -- \
  --set res=8 --repeat 3 --warmup-ms 0
has "interleave: the compare table is printed" "$tmp/out" "^\| funnel\[res=8\] \| c \| cpu \| .* over repeats n=6 \| .* over repeats n=6 \|"
grep "^interleave: round" "$tmp/out" | tr '\n' ' ' >"$tmp/order"
has "interleave: A and B alternate process by process" "$tmp/order" \
  "^interleave: round 1 of 2: A interleave: round 1 of 2: B interleave: round 2 of 2: A interleave: round 2 of 2: B $"
has "interleave: the compare Markdown is kept with the files" "$ab/compare.md" "^\| funnel\[res=8\] \| c \| cpu \|"
check "interleave: every process replayed A's plan, labelled" 0 "^4 files: a a b b, replayed .*plan\.h5 \(pipeline c, pass 0\), plan_mixed 0$" -- \
  "$python" - "$ab" <<'PY'
import glob, sys
import h5py
files = sorted(glob.glob(sys.argv[1] + "/[ab]/run-*.h5"))
labels, sources, mixed = [], set(), 0
for path in files:
    with h5py.File(path, "r") as f:
        labels.append(f.attrs["label"])
        sources.add(f.attrs["plan_source"])
        mixed += int(f["summary"].attrs["plan_mixed_frames"])
print(f"{len(files)} files: {' '.join(labels)}, replayed {' / '.join(sorted(sources))}, plan_mixed {mixed}")
PY
check "interleave: the plan is the recording's" 0 "^0 build self=generate" -- cat "$ab/plan/plan.txt"
check "interleave --no-replay: each process plans its own" 0 "plan: each process planned its own$" -- \
  "$root/bench/interleave.sh" --a "$cdbench" --b "$cdbench" --b-args "--front-cycle 3" --rounds 1 --scene funnel \
  --device cpu --frames 0:6 --no-replay --compare-args "--metric median" "$tmp/free" -- --set res=8 --repeat 2 --warmup-ms 0
has "interleave --no-replay: compare flags B's other plan" "$tmp/free/compare.md" "PLANS DIFFER at frames"
check "interleave: a bad option is a usage error" 2 "unknown option --round" -- "$root/bench/interleave.sh" --round 2 "$tmp/x"

finish bench
