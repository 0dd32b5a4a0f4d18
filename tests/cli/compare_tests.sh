#!/usr/bin/env bash
# cdbench compare, report's commit/label columns and stable CSV, run --label/--json, the
# scripts' schema and baseline matching: small funnel runs on the CPU.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

scene=(--device cpu --scene funnel --set res=16 --frames 0:6 --quiet)
run() {  # run OUT ARGS...: one run into OUT, its output kept in $tmp/run.out
  local out=$1; shift
  "$cdbench" run "${scene[@]}" --out "$out" "$@" >"$tmp/run.out" 2>&1 || { fail "run $*"; sed 's/^/    /' "$tmp/run.out"; }
}
run "$tmp/a.h5" --label before
run "$tmp/b.h5" --label after
run "$tmp/skip.h5" --skip-adjacent
run "$tmp/margin.h5" --box-margin 0.5
run "$tmp/cold-start.h5" --warmup-ms 1
run "$tmp/c3.h5" --repeat 3
run "$tmp/c5.h5" --repeat 5
run "$tmp/brute3.h5" --repeat 3 --pipeline brute
# Fronts updated every 2nd and every 3rd frame: one identity, other plans.
run "$tmp/cycle2.h5" --pipeline b --front-cycle 2
run "$tmp/cycle3.h5" --pipeline b --front-cycle 3

# Same configuration twice. Whether two runs' times differ is the machine's doing, not
# compare's (on a shared machine one-pass runs differed by 60%), so the verdict is checked
# on one run against a copy of itself; the verdicts themselves are unit-tested
# (compare_statistics).
cp "$tmp/a.h5" "$tmp/a-copy.h5"
check "same configuration: no regression" 0 "^\| funnel\[res=16\] \| c \| cpu \|" -- \
  "$cdbench" compare "$tmp/a.h5" "$tmp/a-copy.h5" --threshold 50 --fail-on-regression
if grep -q "REGRESSION" "$tmp/out"; then fail "same configuration flagged a regression"; else echo "ok   no regression row"; fi
check "two runs of one configuration compared" 0 "^\| funnel\[res=16\] \| c \| cpu \|" -- \
  "$cdbench" compare "$tmp/a.h5" "$tmp/b.h5"
has "same configuration: the pairs agree" "$tmp/out" "\| same \(6 frames\) \|"
has "one pass: the interval is over frames" "$tmp/out" "over frames n=5"
has "the labels and commits are named" "$tmp/out" "\[before\] \(commit [0-9a-f]+.*\[after\] \(commit"

# A mismatch in an option that changes the pair set is refused, naming it and both values.
check "mismatch refused" 2 "--skip-adjacent: 'false' in A, 'true' in B" -- "$cdbench" compare "$tmp/a.h5" "$tmp/skip.h5"
has "mismatch suggests --allow-mismatch" "$tmp/out" "--allow-mismatch"
check "another warm-up is another measurement" 2 "--warmup-ms: '0(\.0)?' in A, '1(\.0)?' in B" -- "$cdbench" compare "$tmp/a.h5" "$tmp/cold-start.h5"
check "allow-mismatch compares, flagged" 0 "\*\*MISMATCH: --box-margin: '0(\.0)?' in A, '0\.5' in B\*\*" -- \
  "$cdbench" compare "$tmp/a.h5" "$tmp/margin.h5" --allow-mismatch
has "fatter boxes: other pairs" "$tmp/out" "\*\*DIFFER in [1-9][0-9]* of 6 frames\*\*"

# Runs of one side only are rows of their own, alike from either side, and do not stop the
# comparison: A holds a and skip, B a copy of a and margin.
mkdir -p "$tmp/sideA" "$tmp/sideB"
cp "$tmp/a.h5" "$tmp/skip.h5" "$tmp/sideA/"
cp "$tmp/a-copy.h5" "$tmp/margin.h5" "$tmp/sideB/"
check "a run of A only is a row" 0 "\| — \| — \|  \| only in A \| — \| nearest B [^|]*a-copy\.h5: --skip-adjacent: 'true' in A, 'false' in B( \||;)" -- \
  "$cdbench" compare "$tmp/sideA" "$tmp/sideB"
has "a run of B only is a row" "$tmp/out" "^\| funnel\[res=16\] \| c \| cpu \| — \| — \| [0-9.]+ \| \[[0-9.]+, [0-9.]+\] over frames n=5 \|  \| only in B \| — \| nearest A [^|]*sideA/a\.h5: --box-margin: '0(\.0)?' in A, '0\.5' in B( \||;)"
has "the matching runs are compared" "$tmp/out" "^\| funnel\[res=16\] \| c \| cpu \| [0-9.]+ \| .* \| same \(6 frames\) \|"
has "each one-sided run is named on stderr" "$tmp/out" "B run [^ ]*margin\.h5 matches no run of A, listed as only in B"
check "the other way round, the other side" 0 "\| only in A \| — \| nearest B [^|]*sideA/a\.h5: --box-margin: '0\.5' in A, '0(\.0)?' in B( \||;)" -- \
  "$cdbench" compare "$tmp/sideB" "$tmp/sideA"
has "and A's former run is B's now" "$tmp/out" "\| only in B \| — \| nearest A [^|]*a-copy\.h5: --skip-adjacent: 'false' in A, 'true' in B( \||;)"
# Two runs of B of one identity, other tuning knobs: the one of A's configuration pairs, the
# other is B's only, said so.
mkdir -p "$tmp/tuned"
cp "$tmp/cycle2.h5" "$tmp/tuned/cycle2-copy.h5"
cp "$tmp/cycle3.h5" "$tmp/tuned/"
check "another tuning of the same identity is B's only" 0 "\| only in B \| — \| nearest A [^|]*cycle2\.h5 pairs with another run of this identity \(other tuning options\)" -- \
  "$cdbench" compare "$tmp/cycle2.h5" "$tmp/tuned"
check "one-sided rows in CSV: verdict, no value of the other side" 0 "^only in A,,;only in B,,$" -- \
  "$python" -c "import csv, subprocess, sys; rows = list(csv.DictReader(subprocess.run([sys.argv[1], 'compare', sys.argv[2], sys.argv[3], '--csv'], capture_output=True, text=True).stdout.splitlines())); print(';'.join(','.join((r['verdict'], r['b_ms'] if r['verdict'] == 'only in A' else r['a_ms'], r['pair_frames'])) for r in rows if r['verdict'].startswith('only')))" "$cdbench" "$tmp/sideA" "$tmp/sideB"
check "one-sided rows in JSON: no files of the other side" 0 "^\[\] \[\]$" -- \
  "$python" -c "import json, subprocess, sys; rows = json.loads(subprocess.run([sys.argv[1], 'compare', sys.argv[2], sys.argv[3], '--json'], capture_output=True, text=True).stdout)['rows']; print(*[r['files_b'] if r['verdict'] == 'only in A' else r['files_a'] for r in rows if r['verdict'].startswith('only')])" "$cdbench" "$tmp/sideA" "$tmp/sideB"

# Two pipelines, allowed as a mismatch: the same pairs, and brute force (2-3x slower here)
# never an improvement. Whether it is a regression depends on the machine's noise.
check "other pipeline compared, flagged" 0 "\| (REGRESSION|within-noise|inconclusive) \| same \(6 frames\) \| \*\*MISMATCH: pipeline: 'c' in A, 'brute' in B\*\*" -- \
  "$cdbench" compare "$tmp/c3.h5" "$tmp/brute3.h5" --allow-mismatch
has "the interval is over the passes" "$tmp/out" "over passes n=3"

# A known regression, independent of the machine: a --repeat 5 run whose passes agree
# within 1% (set so), in good conditions (set so: this machine's load is not the point),
# against a copy with every pass 50% slower.
$python - "$tmp/c5.h5" "$tmp/slow.h5" "$tmp/base.h5" <<'PY'
import shutil, sys
import h5py
src, slow, base = sys.argv[1:]
for path, factor in ((base, 1.0), (slow, 1.5)):
    shutil.copy(src, path)
    with h5py.File(path, "r+") as f:
        frames = f["frames/t_total_ms"][()]
        passes = f["passes/t_total_ms"]
        for p in range(passes.shape[1]):
            passes[:, p] = frames * factor * (1 + 0.002 * p)
        f["frames/t_total_ms"][...] = passes[()].mean(axis=1)
        f["frames/t_total_noise"][...] = 0.01
        f.attrs["noise_warning"] = ""  # the copied run's warning and conditions no longer apply
        f.attrs["conditions"] = "good"
        f.attrs["conditions_notes"] = ""
PY
check "a 50% slow-down is a regression" 1 "\| \+50\.0% \| REGRESSION \| same \(6 frames\) \|" -- \
  "$cdbench" compare "$tmp/base.h5" "$tmp/slow.h5" --fail-on-regression
has "the regression is named on stderr" "$tmp/out" "regression beyond 5\.0% and the noise"
check "without --fail-on-regression it exits 0" 0 "REGRESSION" -- "$cdbench" compare "$tmp/base.h5" "$tmp/slow.h5"
check "above the threshold it is no regression" 0 "\| unchanged \|" -- \
  "$cdbench" compare "$tmp/base.h5" "$tmp/slow.h5" --threshold 60 --fail-on-regression
check "and the other way an improvement" 0 "\| -33\.3% \| improvement \|" -- \
  "$cdbench" compare "$tmp/slow.h5" "$tmp/base.h5" --fail-on-regression
# Poor conditions recorded: whatever the times, no verdict, and --fail-on-regression passes.
$python - "$tmp/base.h5" "$tmp/busy.h5" <<'PY'
import shutil, sys
import h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    f.attrs["conditions"] = "poor"
    f.attrs["conditions_notes"] = "host busy before the run (90%)"
PY
check "a busy host recorded: inconclusive, not a regression" 0 \
  "\| \+50\.0% \| inconclusive \| same \(6 frames\) \| poor conditions \(A: host busy before the run \(90%\)\) \|$" -- \
  "$cdbench" compare "$tmp/busy.h5" "$tmp/slow.h5" --fail-on-regression
check "report shows the poor conditions" 0 "busy\.h5 \|.*\| poor conditions: host busy before the run \(90%\) \| complete \|$" -- \
  "$cdbench" report "$tmp/busy.h5"
# GPU conditions as NVML would have recorded them on a card whose clock fell during the
# frames: report shows the readings and the poor conditions, compare gives no verdict.
$python - "$tmp/base.h5" "$tmp/gpu-slowed.h5" <<'PY'
import shutil, sys
import h5py
shutil.copy(sys.argv[1], sys.argv[2])
why = "GPU SM clock changed during the measured frames (1980 to 1500 MHz)"
with h5py.File(sys.argv[2], "r+") as f:
    f.attrs["gpu_source"] = "nvml"
    f.attrs["gpu_name"] = "NVIDIA H200"
    for name, before, after in (("sm_clock_mhz", 1980.0, 1500.0), ("temperature_c", 45.0, 61.5)):
        f.attrs[f"gpu_{name}_before"] = before
        f.attrs[f"gpu_{name}_after"] = after
    f.attrs["gpu_throttle_reasons_after"] = "none"
    f.attrs["gpu_warning"] = why
    f.attrs["conditions"] = "poor"
    f.attrs["conditions_notes"] = why
PY
check "report shows the GPU's readings and its poor conditions" 0 \
  "gpu-slowed\.h5 \|.*\| SM 1980 to 1500 MHz, 45 to 62 C \| poor conditions: GPU SM clock changed during the measured frames \(1980 to 1500 MHz\) \| complete \|$" -- \
  "$cdbench" report "$tmp/gpu-slowed.h5"
check "report CSV has the GPU's readings" 0 "^1980,1500,45,61\.5,none,GPU SM clock changed" -- \
  "$python" -c "import csv, sys; r = next(csv.DictReader(open(sys.argv[1]))); print(','.join(r[k] for k in ('gpu_sm_clock_mhz_before', 'gpu_sm_clock_mhz_after', 'gpu_temperature_c_before', 'gpu_temperature_c_after', 'gpu_throttle_reasons_after', 'gpu_warning')))" \
  <("$cdbench" report --csv "$tmp/gpu-slowed.h5")
check "a GPU whose clock changed: inconclusive" 0 "\| inconclusive \| same \(6 frames\) \| poor conditions \(B: GPU SM clock changed" -- \
  "$cdbench" compare "$tmp/base.h5" "$tmp/gpu-slowed.h5" --fail-on-regression
# Three passes against three cannot reach p < 0.05 even fully separated (p = 0.1).
$python - "$tmp/c3.h5" "$tmp/three.h5" "$tmp/three-slow.h5" <<'PY'
import shutil, sys
import h5py
src, fast, slow = sys.argv[1:]
for path, factor in ((fast, 1.0), (slow, 2.0)):
    shutil.copy(src, path)
    with h5py.File(path, "r+") as f:
        passes = f["passes/t_total_ms"]
        for p in range(passes.shape[1]):
            passes[:, p] = factor * (1 + 0.01 * p)
        f.attrs["noise_warning"] = ""
        f.attrs["conditions"] = "good"
PY
check "three passes each: too few to decide" 0 "\| inconclusive \|.*too few samples \(3 and 3\)" -- \
  "$cdbench" compare "$tmp/three.h5" "$tmp/three-slow.h5" --fail-on-regression
# A file of schema 4 keeps only the passes' means: not tested over passes.
$python - "$tmp/base.h5" "$tmp/schema4.h5" <<'PY'
import shutil, sys
import h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    del f["passes"]
    f.attrs["schema_version"] = 4
    for name in ("conditions", "conditions_notes", "host_busy_before", "host_busy_after", "host_warning"):
        del f.attrs[name]
PY
check "a schema 4 file still compares, inconclusive" 0 "\| inconclusive \|.*passes not kept" -- \
  "$cdbench" compare "$tmp/schema4.h5" "$tmp/slow.h5" --fail-on-regression
check "report reads the schema 4 file" 0 "schema4\.h5 \|.*\| 5 \(means only\) \|" -- "$cdbench" report "$tmp/schema4.h5"
# Other plans: the runs pair (--front-cycle is a tuning knob), flagged with the frames.
check "other plans are flagged with their frames" 0 "\*\*PLANS DIFFER at frames [0-9][-0-9,]*\*\*" -- \
  "$cdbench" compare "$tmp/cycle2.h5" "$tmp/cycle3.h5"
# The same two files with their conditions marked good, so that the plans alone decide:
# one process a side is too few; four copies a side are tested over the processes.
mkdir -p "$tmp/plans-a" "$tmp/plans-b"
$python - "$tmp/cycle2.h5" "$tmp/cycle3.h5" "$tmp/plans-a" "$tmp/plans-b" <<'PY'
import shutil, sys
import h5py
for src, side in ((sys.argv[1], sys.argv[3]), (sys.argv[2], sys.argv[4])):
    for k in range(1, 5):
        dst = f"{side}/r{k}.h5"
        shutil.copy(src, dst)
        with h5py.File(dst, "r+") as f:
            f.attrs["noise_warning"] = ""
            f.attrs["conditions"] = "good"
            f.attrs["conditions_notes"] = ""
PY
check "other plans in one process a side: inconclusive, processes too few" 0 "\\| inconclusive \\|.*plans differ at frames [0-9][-0-9,]*, and 1 and 1 processes are too few to test" -- \
  "$cdbench" compare "$tmp/plans-a/r1.h5" "$tmp/plans-b/r1.h5"
"$cdbench" compare "$tmp/plans-a" "$tmp/plans-b" --csv >"$tmp/plans4.csv" 2>/dev/null
check "other plans, 4 processes a side: tested over the processes" 0 "^(REGRESSION|improvement|within-noise|unchanged) " -- \
  "$python" -c "import csv, sys; r = next(csv.DictReader(open(sys.argv[1]))); print(r['verdict'], r['p_value'], r['why'])" "$tmp/plans4.csv"
"$cdbench" compare "$tmp/cycle2.h5" "$tmp/cycle3.h5" --csv >"$tmp/plans.csv" 2>/dev/null
check "the CSV names the frames" 0 "^[1-9][-0-9,]*$" -- \
  "$python" -c "import csv, sys; print(next(csv.DictReader(open(sys.argv[1])))['plan_differ'])" "$tmp/plans.csv"
check "one plan: no flag" 0 "^$" -- \
  "$python" -c "import csv, sys, subprocess; print(next(csv.DictReader(subprocess.run([sys.argv[1], 'compare', sys.argv[2], sys.argv[2], '--csv'], capture_output=True, text=True).stdout.splitlines()))['plan_differ'])" "$cdbench" "$tmp/cycle2.h5"
# The stored noise warning and content hash, set in copies: compare flags the noisy run and
# refuses other frames under the same scene name.
$python - "$tmp/base.h5" "$tmp/noisy.h5" "$tmp/otherinput.h5" <<'PY'
import shutil, sys
import h5py
src, noisy, other = sys.argv[1:]
shutil.copy(src, noisy)
with h5py.File(noisy, "r+") as f:
    f.attrs["noise_warning"] = "noisy run: the passes' times differ by 31.0%"
shutil.copy(src, other)
with h5py.File(other, "r+") as f:
    f.attrs["input_hash"] = "0123456789abcdef"
PY
check "a noisy run is flagged" 0 "\| poor conditions \(B: noise warning\) \|$" -- "$cdbench" compare "$tmp/base.h5" "$tmp/noisy.h5"
check "report marks the noisy run" 0 "noisy\.h5 \|.*\| noisy \| complete \|$" -- "$cdbench" report "$tmp/base.h5" "$tmp/noisy.h5"
check "other input frames refused" 2 "input_hash: [0-9a-f]{16} in A, 0123456789abcdef in B" -- \
  "$cdbench" compare "$tmp/base.h5" "$tmp/otherinput.h5"
# Times that are NaN (a damaged or hand-made file) decide nothing: inconclusive, not
# unchanged (the timeout bounds a build whose test loops on them).
$python - "$tmp/base.h5" "$tmp/nan.h5" <<'PY'
import shutil, sys
import h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    f["frames/t_total_ms"][...] = float("nan")
    f["passes/t_total_ms"][...] = float("nan")
PY
check "NaN times are inconclusive" 0 "\| inconclusive \| same \(6 frames\) \| .*times that are not finite \(NaN or infinite\): 0 of [0-9]+ samples of A, ([0-9]+) of \1 of B" -- \
  timeout 60 "$cdbench" compare "$tmp/base.h5" "$tmp/nan.h5"
# Runs of other scenes: their hashes differ because the scenes do, not "same scene name".
"$cdbench" run --device cpu --scene cloth-wave --set res=8 --frames 0:6 --quiet --out "$tmp/wave.h5" >/dev/null 2>&1 || fail "run cloth-wave"
check "other scenes: the hashes differ as the scenes do" 0 "input_hash: [0-9a-f]{16} in A, [0-9a-f]{16} in B \(the scenes differ\)" -- \
  "$cdbench" compare "$tmp/a.h5" "$tmp/wave.h5" --allow-mismatch
grep -q "same scene name" "$tmp/out" && fail "other scenes called the same scene name" || echo "ok   other scenes not called one name"
check "median metric" 0 "^median per-frame ms" -- "$cdbench" compare "$tmp/a.h5" "$tmp/b.h5" --metric median
check "unknown metric is a usage error" 2 "--metric" -- "$cdbench" compare "$tmp/a.h5" "$tmp/b.h5" --metric max

# Repeats: two files of one configuration in a directory are one run's repeats.
mkdir -p "$tmp/repeats"
cp "$tmp/a.h5" "$tmp/repeats/cell_r1.h5"
cp "$tmp/b.h5" "$tmp/repeats/cell_r2.h5"
"$cdbench" run "${scene[@]}" --out "$tmp/repeats/cell_r1.h5" --label r --overwrite >/dev/null 2>&1
"$cdbench" run "${scene[@]}" --out "$tmp/repeats/cell_r2.h5" --label r --overwrite >/dev/null 2>&1
check "directory repeats combine" 0 "over repeats n=2 \|.*over repeats n=2 \|" -- \
  "$cdbench" compare "$tmp/repeats" "$tmp/repeats"
# A label names a file, it does not tell runs apart: two labels of one configuration pool.
mkdir -p "$tmp/labelled"
cp "$tmp/a.h5" "$tmp/b.h5" "$tmp/labelled/"
check "files of other labels pool as repeats" 0 "over repeats n=2 \|.*over repeats n=2 \|" -- \
  "$cdbench" compare "$tmp/labelled" "$tmp/labelled"
has "each pooled file is named with its label" "$tmp/out" "a\.h5 \[before\] [^ ]*b\.h5 \[after\] \(commit"
check "the CSV lists both labels" 0 "^before, after$" -- \
  "$python" -c "import csv, sys, subprocess; print(next(csv.DictReader(subprocess.run([sys.argv[1], 'compare', sys.argv[2], sys.argv[2], '--csv'], capture_output=True, text=True).stdout.splitlines()))['label_a'])" "$cdbench" "$tmp/labelled"

# Stable machine-readable output: the same CSV header whatever the inputs.
"$cdbench" compare "$tmp/a.h5" "$tmp/b.h5" --csv >"$tmp/csv1" 2>/dev/null
"$cdbench" compare "$tmp/base.h5" "$tmp/slow.h5" --csv >"$tmp/csv2" 2>/dev/null
"$cdbench" compare "$tmp/c3.h5" "$tmp/brute3.h5" --csv --allow-mismatch >"$tmp/csv3" 2>/dev/null
if [[ "$(head -1 "$tmp/csv1")" == "$(head -1 "$tmp/csv2")" && "$(head -1 "$tmp/csv1")" == "$(head -1 "$tmp/csv3")" ]] && grep -q "^scene,pipeline,device,label_a" "$tmp/csv1"; then
  echo "ok   compare CSV header is stable"
else
  fail "compare CSV headers differ: $(head -1 "$tmp/csv1") / $(head -1 "$tmp/csv2")"
fi
has "CSV row of the regression" "$tmp/csv2" ",(50(\.0*[0-9]*)?|49\.9+[0-9]*),REGRESSION,0\.007936507936507936,,,6,0,([0-9a-f]{16}),\3,,"
# Full precision: every number of the CSV row is the very double of compare --json (which
# writes doubles that read back exactly), the exact test's p = 2 / C(10, 5) among them.
"$cdbench" compare "$tmp/base.h5" "$tmp/slow.h5" --json >"$tmp/json2" 2>/dev/null
check "compare CSV has every double exactly" 0 "^exact: [1-9][0-9]* numbers$" -- "$python" - "$tmp/csv2" "$tmp/json2" <<'PY'
import csv, json, sys
row = next(csv.DictReader(open(sys.argv[1])))
expected = json.load(open(sys.argv[2]))["rows"][0]
numbers = [k for k, v in expected.items() if isinstance(v, float)]
bad = [k for k in numbers if float(row[k]) != expected[k]]
bad += [] if float(row["p_value"]) == 2 / 252 else ["p_value is not 2 / C(10, 5)"]
bad += [] if abs(float(row["change_pct"]) - 50) < 1e-9 else ["change_pct is not 50%"]
print("differ: " + ", ".join(bad) if bad else f"exact: {len(numbers)} numbers")
PY
# 5 frames' median: ranks below the first frame bound it only by zero, as no time is negative.
check "an interval unbounded below starts at 0" 0 "^funnel\[res=16\],c,cpu,before,before,median,[0-9.e-]+,0,(inf|[0-9.e-]+),5,frames," -- \
  "$cdbench" compare "$tmp/a.h5" "$tmp/a-copy.h5" --metric median --csv
check "an unbounded interval end is inf in CSV" 0 "^funnel\[res=16\],c,cpu,before,before,p95,[0-9.e-]+,[0-9.e-]+,inf,5,frames," -- \
  "$cdbench" compare "$tmp/a.h5" "$tmp/a-copy.h5" --metric p95 --csv
has "CSV row of the mismatch" "$tmp/csv3" ",6,0,([0-9a-f]{16}),\1,\"pipeline: 'c' in A, 'brute' in B\","
check "JSON parses" 0 '"verdict": "REGRESSION"' -- \
  bash -c "'$cdbench' compare '$tmp/base.h5' '$tmp/slow.h5' --json 2>/dev/null | $python -m json.tool"
# Each side's content hash as its files recorded it, and each side's files as a list.
check "JSON has both hashes and the files as lists" 0 "^hashes [0-9a-f]{16} [0-9a-f]{16}; files \['[^']*base\.h5'\] \['[^']*slow\.h5'\]$" -- \
  "$python" -c "import json, sys; r = json.load(open(sys.argv[1]))['rows'][0]; print('hashes', r['input_hash_a'], r['input_hash_b'] + ';', 'files', r['files_a'], r['files_b'])" "$tmp/json2"
"$cdbench" compare "$tmp/base.h5" "$tmp/otherinput.h5" --allow-mismatch --json >"$tmp/json-other" 2>/dev/null
check "JSON of other inputs names both hashes" 0 "^[0-9a-f]{16} 0123456789abcdef$" -- \
  "$python" -c "import json, sys; r = json.load(open(sys.argv[1]))['rows'][0]; print(r['input_hash_a'], r['input_hash_b'])" "$tmp/json-other"
check "JSON of repeats lists every file" 0 "^2 2$" -- \
  "$python" -c "import json, subprocess, sys; r = json.loads(subprocess.run([sys.argv[1], 'compare', sys.argv[2], sys.argv[2], '--json'], capture_output=True, text=True).stdout)['rows'][0]; print(len(r['files_a']), len(r['files_b']))" "$cdbench" "$tmp/labelled"
# --overwrite says where the output may go, as --out does: a run written over an earlier
# file is a repeat of one written afresh, not another configuration.
mkdir -p "$tmp/rewritten"
run "$tmp/rewritten/fresh.h5"
cp "$tmp/rewritten/fresh.h5" "$tmp/rewritten/again.h5"
run "$tmp/rewritten/again.h5" --overwrite
check "a run written with --overwrite is a repeat" 0 "^1 row of 2 and 2 files$" -- \
  "$python" -c "import json, subprocess, sys; rows = json.loads(subprocess.run([sys.argv[1], 'compare', sys.argv[2], sys.argv[2], '--json'], capture_output=True, text=True).stdout)['rows']; print(len(rows), 'row of', len(rows[0]['files_a']), 'and', len(rows[0]['files_b']), 'files')" "$cdbench" "$tmp/rewritten"
# Labels and commits are lists too, a label with a space one item; the side a one-sided
# row has no run of has empty lists.
cp "$tmp/a.h5" "$tmp/labelled/spaced.h5"
mkdir -p "$tmp/labelled-and-skip" && cp "$tmp/a.h5" "$tmp/skip.h5" "$tmp/labelled-and-skip/"
"$python" -c "import h5py, sys; h5py.File(sys.argv[1], 'r+').attrs['label'] = 'after fix'" "$tmp/labelled/spaced.h5"
check "JSON has the labels and commits as lists" 0 "^\['before', 'after', 'after fix'\] \['[0-9a-f]{12}(-dirty)?'\] \[\] \[\]$" -- \
  "$python" -c "import json, subprocess, sys; rows = json.loads(subprocess.run([sys.argv[1], 'compare', sys.argv[2], sys.argv[3], '--json'], capture_output=True, text=True).stdout)['rows']; r = rows[0]; o = [x for x in rows if x['verdict'] == 'only in B'][0]; print(r['label_a'], r['commit_a'], o['label_a'], o['commit_a'])" "$cdbench" "$tmp/labelled" "$tmp/labelled-and-skip"

# report: the commit column, the label, the same CSV columns for any set of files.
check "report has the commit column" 0 "\| label \| commit \| input \| (warning \| )?status \|" -- "$cdbench" report "$tmp/a.h5" "$tmp/skip.h5"
has "report shows the label and commit" "$tmp/out" "a\.h5 \|.*\| before \| [0-9a-f]{12}(-dirty)? \| [0-9a-f]{8} \| ( \| |noisy \| |poor conditions: [^|]* \| )?complete \|"
"$cdbench" report --csv "$tmp/a.h5" >"$tmp/rcsv1"
run "$tmp/checked.h5" --check every --pipeline b
"$cdbench" report --csv "$tmp/a.h5" "$tmp/checked.h5" "$tmp/margin.h5" >"$tmp/rcsv2"
if [[ "$(head -1 "$tmp/rcsv1")" == "$(head -1 "$tmp/rcsv2")" ]]; then echo "ok   report CSV header is stable"; else
  fail "report CSV headers differ:"; head -1 "$tmp/rcsv1" "$tmp/rcsv2" | sed 's/^/    /'; fi
cols1=$(head -1 "$tmp/rcsv1" | tr ',' '\n' | wc -l)
bad=$($python -c "import csv,sys; print(sum(len(r) != $cols1 for r in csv.reader(open('$tmp/rcsv2'))))")
[[ $bad == 0 ]] && echo "ok   every report CSV row has $cols1 cells" || fail "$bad report CSV rows of another width"
has "report CSV carries the label and commit" "$tmp/rcsv1" "a\.h5,funnel\[res=16\],c,cpu: [^,]*,before,[0-9a-f]{12}"
# Full precision: every statistic reads back as the very double /summary holds.
check "report CSV has the summary's doubles exactly" 0 "^exact$" -- "$python" - "$tmp/rcsv1" "$tmp/a.h5" <<'PY'
import csv, sys
import h5py
row = next(csv.DictReader(open(sys.argv[1])))
s = h5py.File(sys.argv[2], "r")["summary"].attrs
pairs = {"mean_ms": "t_total_ms_mean", "median_ms": "t_total_ms_median", "p95_ms": "t_total_ms_p95",
         "min_ms": "t_total_ms_min", "first_frame_ms": "first_frame_ms", "frames_measured": "measured_frames"}
bad = [k for k, a in pairs.items() if float(row[k]) != float(s[a])]
print("differ: " + ", ".join(bad) if bad else "exact")
PY
# report --json: one object per file, the CSV's columns as keys in their order, every
# number the very double of the CSV cell, the options an object.
"$cdbench" report --csv "$tmp/a.h5" "$tmp/c3.h5" >"$tmp/rcsv3"
"$cdbench" report --json "$tmp/a.h5" "$tmp/c3.h5" >"$tmp/rjson3"
check "report --json has the CSV's statistics exactly" 0 "^2 runs, [1-9][0-9]* numbers exact, options an object$" -- "$python" - "$tmp/rcsv3" "$tmp/rjson3" <<'PY'
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
out = json.load(open(sys.argv[2]))
runs = out["runs"]
bad = [] if out["command"] == "report" and len(runs) == len(rows) else ["not one object per file"]
numbers = 0
for row, run in zip(rows, runs):
    keys = ["options" if k == "options_json" else k for k in row]
    bad += [] if list(run) == keys else [f"keys {list(run)} vs {keys}"]
    for k, cell in row.items():
        v = run["options" if k == "options_json" else k]
        if k == "options_json":
            bad += [] if v == json.loads(cell) and isinstance(v, dict) else ["options"]
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            numbers += 1
            bad += [] if float(cell) == v else [f"{k}: {cell} vs {v}"]
        elif v is None:
            bad += [] if cell in ("", "inf", "-inf", "nan") else [f"{k}: {cell} vs null"]
        else:
            bad += [] if cell == v else [f"{k}: {cell!r} vs {v!r}"]
print("differ: " + "; ".join(bad) if bad else f"{len(runs)} runs, {numbers} numbers exact, options an object")
PY
check "report --json and --csv are refused together" 2 "excludes" -- "$cdbench" report --json --csv "$tmp/a.h5"
# read_results --csv is CSV alone: csv.DictReader reads every frame of every file.
"$python" "$root/scripts/read_results.py" --csv "$tmp/a.h5" "$tmp/c5.h5" >"$tmp/frames.csv"
check "read_results --csv is pure CSV" 0 "^12 rows, exact$" -- "$python" - "$tmp/frames.csv" "$tmp/a.h5" <<'PY'
import csv, sys
import h5py
rows = list(csv.DictReader(open(sys.argv[1])))
times = h5py.File(sys.argv[2], "r")["frames/t_total_ms"][()]
mine = [float(r["t_total_ms"]) for r in rows if r["file"] == sys.argv[2]]
print(f"{len(rows)} rows, " + ("exact" if mine == list(times) else f"differ: {mine} vs {list(times)}"))
PY

# run --json: stdout is the JSON alone, the human lines on stderr.
"$cdbench" run "${scene[@]}" --label json-run --json >"$tmp/json.out" 2>"$tmp/json.err"
check "run --json parses" 0 '"label": "json-run"' -- "$python" -m json.tool "$tmp/json.out"
has "run --json has the mean" "$tmp/out" '"mean_ms": [0-9.e-]+'
has "run --json has the input hash" "$tmp/out" '"input_hash": "[0-9a-f]{16}"'
has "run --json: the summary went to stderr" "$tmp/json.err" "^summary: 5 frames measured"
has "run --json: one pass has no noise" "$tmp/json.out" '"noise_pct": null'
# One unit for the noise (percent) and two names for the frames (run, measured) in run
# --json, report --json and report --csv alike.
"$cdbench" run "${scene[@]}" --repeat 3 --json --out "$tmp/units.h5" >"$tmp/units.json" 2>/dev/null
"$cdbench" report --json "$tmp/units.h5" >"$tmp/units-report.json"
"$cdbench" report --csv "$tmp/units.h5" >"$tmp/units.csv"
check "run --json and report agree on noise_pct and the frames" 0 "^percent 6 run 5 measured$" -- "$python" - \
  "$tmp/units.json" "$tmp/units-report.json" "$tmp/units.csv" "$tmp/units.h5" <<'PY'
import csv, json, sys
import h5py
run = json.load(open(sys.argv[1]))["runs"][0]
report = json.load(open(sys.argv[2]))["runs"][0]
row = next(csv.DictReader(open(sys.argv[3])))
fraction = float(h5py.File(sys.argv[4], "r")["summary"].attrs["noise_median"])
bad = [k for k in ("noise", "frames", "measured_frames") if k in run or k in report or k in row]
pct = {run["noise_pct"], report["noise_pct"], float(row["noise_pct"])}
if len(pct) != 1 or abs(pct.pop() - 100 * fraction) > 1e-9 * max(1.0, 100 * fraction):
    bad.append(f"noise_pct {run['noise_pct']}, {report['noise_pct']}, {row['noise_pct']} against 100 x {fraction}")
counts = {(run["frames_run"], run["frames_measured"]), (report["frames_run"], report["frames_measured"]),
          (int(row["frames_run"]), int(row["frames_measured"]))}
if len(counts) != 1:
    bad.append(f"frame counts differ: {counts}")
print("differ: " + "; ".join(bad) if bad else f"percent {run['frames_run']} run {run['frames_measured']} measured")
PY

# Scripts: no schema warning on files of this build; the baseline matches the identity.
check "read_results knows this schema" 0 "^label: before$" -- "$python" "$root/scripts/read_results.py" --summary "$tmp/a.h5"
if grep -q "newer than" "$tmp/out"; then fail "read_results warns about the schema"; else echo "ok   no schema warning"; fi
has "read_results shows the input hash" "$tmp/out" "^input_hash: [0-9a-f]{16}$"
# The scripts match runs as compare does: another warm-up is another identity, another
# label is not.
check "the scripts' identity agrees with compare's" 0 "^warm-up: --warmup-ms: 0(\.0)? vs 1(\.0)?; label: none$" -- \
  "$python" -c "import sys; sys.path.insert(0, sys.argv[1]); import cdb_results as c; a, cold, b = (c.Run(p) for p in sys.argv[2:]); print('warm-up: ' + '; '.join(c.identity_differences(a, cold)) + '; label: ' + ('; '.join(c.identity_differences(a, b)) or 'none'))" \
  "$root/scripts" "$tmp/a.h5" "$tmp/cold-start.h5" "$tmp/b.h5"
# The scripts take the identity options a file records (params_json's identity_options),
# not a copy of their own: with --warmup-ms struck from both files' lists, the two warm-ups
# are one identity; a file without the list (written before it) falls back to the list of
# those builds, --warmup-ms in it.
check "the scripts read a file's own identity options" 0 "^own list: none; without: --warmup-ms: 0(\.0)? vs 1(\.0)?$" -- \
  "$python" - "$root/scripts" "$tmp/a.h5" "$tmp/cold-start.h5" "$tmp/ids" <<'PY'
import json, os, shutil, sys
import h5py
sys.path.insert(0, sys.argv[1])
import cdb_results as c
os.makedirs(sys.argv[4], exist_ok=True)
def edited(path, name, edit):
    out = os.path.join(sys.argv[4], name)
    shutil.copy(path, out)
    with h5py.File(out, "r+") as f:
        params = json.loads(c.text(f.attrs["params_json"]))
        edit(params)
        f.attrs["params_json"] = json.dumps(params)
    return c.Run(out)
strike = lambda p: p["identity_options"].remove("warmup-ms")
drop = lambda p: p.pop("identity_options")
own = c.identity_differences(edited(sys.argv[2], "a.h5", strike), edited(sys.argv[3], "cold.h5", strike))
without = c.identity_differences(edited(sys.argv[2], "a-old.h5", drop), edited(sys.argv[3], "cold-old.h5", drop))
print("own list: " + ("; ".join(own) or "none") + "; without: " + ("; ".join(without) or "none"))
PY
mkdir -p "$tmp/tp"
run "$tmp/tp/grid-skip.h5" --pipeline grid --skip-adjacent
run "$tmp/tp/c.h5" --pipeline c
check "table_pipelines: no baseline of another identity" 0 "No \`grid\` run of the same identity as \`$tmp/tp/c.h5\`" -- \
  "$python" "$root/scripts/table_pipelines.py" --baseline grid "$tmp/tp"
has "table_pipelines: c has no speed-up" "$tmp/out" "^\| \*?\*?c \[--skip-adjacent false\]\*?\*? \|.*\| — \|$"
run "$tmp/tp/grid.h5" --pipeline grid
check "table_pipelines: the matching baseline is named" 0 "Speed-up \[--skip-adjacent false\] against \`$tmp/tp/grid.h5\`" -- \
  "$python" "$root/scripts/table_pipelines.py" --baseline grid "$tmp/tp"

finish compare
