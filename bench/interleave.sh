#!/usr/bin/env bash
# A fair A/B of two binaries, or of one binary under two option sets: their processes run
# interleaved (A B A B ..., one round each), so a drift of the machine (clocks, heat, other
# load) falls on both sides alike; every process replays one front plan, recorded once by A
# before the rounds, so both sides do the same work at every frame (docs/usage.md "Plans");
# then `cdbench compare` sets B's files against A's, pooled as repeats (docs/usage.md
# "Comparing runs").
#
#   bench/interleave.sh [options] OUTDIR [-- RUN_ARGS...]
#   bench/interleave.sh --a old/cdbench --b build/app/cdbench --scene crumple --device cuda out/ab
#   bench/interleave.sh --b-args "--cuda-graph on" --scene funnel --device cpu out/graph -- --repeat 5
#
# Options (RUN_ARGS after -- go to every run of both sides):
#   --a BIN, --b BIN           the binaries (A: $CDBENCH or build/app/cdbench; B: A's)
#   --a-args ARGS, --b-args ARGS   options of one side only, as one word (split on blanks)
#   --label-a L, --label-b L   the runs' labels (a, b)
#   --rounds N                 processes per side (5)
#   --scene S, --pipeline P, --device D, --frames F   the run's (funnel, c, cdbench's default, all)
#   --no-replay                every process plans its own fronts (the plans then may differ,
#                              and compare flags the frames where they do)
#   --compare-args ARGS        options of compare (e.g. "--metric median --threshold 2")
#
# Files: OUTDIR/plan/plan.h5 (A's run whose plan every process replays), OUTDIR/a/run-K.h5
# and OUTDIR/b/run-K.h5 (round K), OUTDIR/logs/, and compare's Markdown in
# OUTDIR/compare.md, also printed with a verdict line per row. Compare runs with B's
# binary, usually the newer, which reads both sides' files. Exit: 0 when every run and the
# compare ran, 1 when one failed, 2 on bad arguments.
set -euo pipefail

usage() {
  sed -n '/^#   bench\/interleave.sh \[options\]/,/^#   --compare-args/p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

a_bin=${CDBENCH:-build/app/cdbench} b_bin="" a_args="" b_args="" label_a=a label_b=b rounds=5
scene=funnel pipeline=c device="" frames="" replay=1 compare_args="" outdir=""
while [[ $# -gt 0 ]]; do
  case $1 in
    --a | --b | --a-args | --b-args | --label-a | --label-b | --rounds | --scene | --pipeline | --device | --frames | \
      --compare-args)
      [[ $# -ge 2 ]] || { echo "bench/interleave.sh: $1 needs a value" >&2; exit 2; }
      case $1 in
        --a) a_bin=$2 ;; --b) b_bin=$2 ;; --a-args) a_args=$2 ;; --b-args) b_args=$2 ;;
        --label-a) label_a=$2 ;; --label-b) label_b=$2 ;; --rounds) rounds=$2 ;; --scene) scene=$2 ;;
        --pipeline) pipeline=$2 ;; --device) device=$2 ;; --frames) frames=$2 ;; --compare-args) compare_args=$2 ;;
      esac
      shift 2 ;;
    --no-replay) replay=0; shift ;;
    -h | --help) usage ;;
    --) shift; break ;;
    -*) echo "bench/interleave.sh: unknown option $1" >&2; usage ;;
    *) [[ -z $outdir ]] || { echo "bench/interleave.sh: one OUTDIR, not $outdir and $1" >&2; exit 2; }
       outdir=${1%/}; shift ;;
  esac
done
run_args=("$@")
b_bin=${b_bin:-$a_bin}
[[ -n $outdir ]] || { echo "bench/interleave.sh: OUTDIR missing" >&2; usage; }
[[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "bench/interleave.sh: --rounds $rounds: expected a whole number >= 1" >&2; exit 2; }
[[ $pipeline != *,* ]] || { echo "bench/interleave.sh: --pipeline $pipeline: one pipeline (one plan to replay)" >&2; exit 2; }
[[ $label_a != "$label_b" ]] || { echo "bench/interleave.sh: --label-a and --label-b are both '$label_a'" >&2; exit 2; }
for bin in "$a_bin" "$b_bin"; do
  [[ -x $bin ]] || { echo "bench/interleave.sh: no cdbench at $bin (--a, --b or CDBENCH)" >&2; exit 2; }
done
read -ra side_a <<<"$a_args"
read -ra side_b <<<"$b_args"
read -ra compare_extra <<<"$compare_args"
common=(--scene "$scene" --pipeline "$pipeline" --quiet --overwrite)
[[ -z $device ]] || common+=(--device "$device")
[[ -z $frames ]] || common+=(--frames "$frames")
mkdir -p "$outdir/a" "$outdir/b" "$outdir/logs"

# run BIN OUT LOG ARGS...: one process, its output in LOG; a failure ends the A/B.
run() {
  local bin=$1 out=$2 log=$3; shift 3
  "$bin" run "${common[@]}" --out "$out" "$@" "${run_args[@]}" >"$log" 2>&1 ||
    { echo "bench/interleave.sh: $bin run failed (log $log):" >&2; tail -5 "$log" >&2; exit 1; }
}

# The plan: recorded once, by A, before the rounds. A pipeline without fronts has none, and
# its processes run the same operations anyway.
plan=()
if [[ $replay == 1 ]]; then
  echo "interleave: recording A's plan ($outdir/plan/plan.h5)" >&2
  mkdir -p "$outdir/plan"
  run "$a_bin" "$outdir/plan/plan.h5" "$outdir/logs/plan.log" --label "$label_a-plan" "${side_a[@]}"
  if "$a_bin" report --plan "$outdir/plan/plan.h5" >"$outdir/plan/plan.txt" 2>"$outdir/logs/plan-report.log"; then
    plan=(--front-cycle "$outdir/plan/plan.h5")
  else
    echo "interleave: pipeline $pipeline has no front plan; its processes run without one" >&2
    rm -f "$outdir/plan/plan.txt"
  fi
fi

for k in $(seq "$rounds"); do
  echo "interleave: round $k of $rounds: A" >&2
  run "$a_bin" "$outdir/a/run-$k.h5" "$outdir/logs/a-$k.log" --label "$label_a" "${plan[@]}" "${side_a[@]}"
  echo "interleave: round $k of $rounds: B" >&2
  run "$b_bin" "$outdir/b/run-$k.h5" "$outdir/logs/b-$k.log" --label "$label_b" "${plan[@]}" "${side_b[@]}"
done

"$b_bin" compare "$outdir/a" "$outdir/b" "${compare_extra[@]}" >"$outdir/compare.md" 2>"$outdir/logs/compare.log" ||
  { echo "bench/interleave.sh: compare failed (log $outdir/logs/compare.log):" >&2; cat "$outdir/logs/compare.log" >&2; exit 1; }
"$b_bin" compare "$outdir/a" "$outdir/b" "${compare_extra[@]}" --json >"$outdir/logs/compare.json" 2>/dev/null
cat "$outdir/compare.md"
echo
/usr/bin/python3 - "$outdir/logs/compare.json" "$rounds" "${plan[*]:+replayed $outdir/plan/plan.h5}" <<'PY'
import json, sys
path, rounds, plan = sys.argv[1], sys.argv[2], sys.argv[3] or "each process planned its own"
for r in json.load(open(path))["rows"]:
    change = "" if r["change_pct"] is None else f", change {r['change_pct']:+.2f}%"
    p = "" if r["p_value"] is None else f", p = {r['p_value']:.3g}"
    why = f" ({r['why']})" if r["why"] else ""
    print(f"verdict: {r['verdict']}{why}: {r['scene']} {r['pipeline']} {r['device']}, B against A over "
          f"{rounds} interleaved processes each{change}{p}; plan: {plan}")
PY
echo "interleave: files in $outdir/a and $outdir/b, compare's table in $outdir/compare.md" >&2
