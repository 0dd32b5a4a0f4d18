#!/usr/bin/env bash
# A/A test of `cdbench compare`: the same run command twice, labelled a and b, N times, each
# pair compared; how often compare calls the same build a regression or an improvement is
# its false-positive rate on this machine (docs/usage.md "Comparing runs"). Not a timed
# test: it measures the machine as much as compare.
#
#   bench/aa.sh N OUTDIR RUN_ARGS...
#   bench/aa.sh 20 /tmp/aa --device cpu --scene funnel --set res=16 --frames 0:9 --repeat 5
#
# CDBENCH: the binary (default build/app/cdbench). Files: OUTDIR/K/{a,b}/run.h5, compare's
# JSON of pair K in OUTDIR/K/compare.json; the tally on stdout.
set -euo pipefail
if [[ $# -lt 3 || ! $1 =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: bench/aa.sh N OUTDIR RUN_ARGS...  (N: pairs of runs, at least 1)" >&2
  exit 2
fi
n=$1 outdir=${2%/}
shift 2
cdbench=${CDBENCH:-build/app/cdbench}
python=/usr/bin/python3
[[ -x $cdbench ]] || { echo "bench/aa.sh: no cdbench at $cdbench (set CDBENCH)" >&2; exit 2; }
for k in $(seq "$n"); do
  for side in a b; do
    "$cdbench" run "$@" --quiet --label "$side" --out "$outdir/$k/$side/run.h5" --overwrite >"$outdir.run.log" 2>&1 ||
      { echo "bench/aa.sh: pair $k run $side failed:" >&2; tail -5 "$outdir.run.log" >&2; exit 1; }
  done
  "$cdbench" compare "$outdir/$k/a" "$outdir/$k/b" --json >"$outdir/$k/compare.json"
  echo "pair $k of $n compared" >&2
done
"$python" - "$outdir" "$n" "$*" <<'PY'
import collections, json, os, sys
outdir, n, command = sys.argv[1], int(sys.argv[2]), sys.argv[3]
verdicts, poor, changes = collections.Counter(), 0, []
for k in range(1, n + 1):
    rows = json.load(open(os.path.join(outdir, str(k), "compare.json")))["rows"]
    for r in rows:
        verdicts[r["verdict"]] += 1
        poor += bool(r["poor_conditions"])
        if r["change_pct"] is not None:
            changes.append(abs(r["change_pct"]))
total = sum(verdicts.values())
print(f"A/A: {n} pairs of `cdbench run {command}`, {total} rows compared")
print()
print("| verdict | rows | share |")
print("| --- | ---: | ---: |")
for v in ("REGRESSION", "improvement", "within-noise", "unchanged", "inconclusive"):
    print(f"| {v} | {verdicts[v]} | {100.0 * verdicts[v] / total:.0f}% |")
called = verdicts["REGRESSION"] + verdicts["improvement"]
print()
print(f"false positives (REGRESSION or improvement): {called} of {total} ({100.0 * called / total:.0f}%); "
      f"rows with poor conditions recorded: {poor}; median |change| {sorted(changes)[len(changes) // 2]:.1f}%"
      if changes else f"false positives: {called} of {total}")
PY
