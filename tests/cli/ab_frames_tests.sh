#!/usr/bin/env bash
# scripts/ab_frames.py: frame k of A against frame k of B on a small CPU run and a copy of it
# whose passes are twice as slow and whose plan differs at one frame.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

export OMP_NUM_THREADS=1
"$cdbench" run --device cpu --quiet --scene funnel --set res=8 --frames 0:6 --pipeline b --front-cycle 2 --repeat 3 \
  --warmup-ms 0 --out "$tmp/a.h5" >"$tmp/run.out" 2>&1 || { cat "$tmp/run.out"; fail "cdbench run"; }
cp "$tmp/a.h5" "$tmp/a2.h5"
# B: every pass twice as slow; pass 1 preserved at frame 4, where the recorded plan updates.
"$python" - "$tmp/a.h5" "$tmp/b.h5" <<'PY'
import shutil, sys
import h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    passes = f["passes/t_total_ms"]
    passes[...] = passes[()] * 2
    p = f["plans"]
    rows = [i for i in range(len(p["pass"])) if p["pass"][i] == 1 and p["frame"][i] == 4]
    assert rows and p["self"][rows[0]] == b"update", "the recorded plan updates at frame 4"
    p["self"][rows[0]] = b"preserve"
PY

ab=("$python" "$root/scripts/ab_frames.py")
check "one row per frame, B / A of the medians" 0 "^\| 1 \| [0-9.]+ \| [0-9.]+ \| 2\.000 \|  \|  \|$" -- \
  "${ab[@]}" --a "$tmp/a.h5" "$tmp/a2.h5" --b "$tmp/b.h5" --plot "$tmp/ab.png"
has "the first frame is the warm-up" "$tmp/out" "^\| 0 \(warm-up\) \| [0-9.]+ \| [0-9.]+ \| 2\.000 \|"
has "the frame whose plans differ names both" "$tmp/out" \
  "^\| 4 \| [0-9.]+ \| [0-9.]+ \| 2\.000 \| refit self=update( inspect)? \| refit self=preserve( probe)? \| refit self=update( inspect)? \|$"
has "the files of each side are named" "$tmp/out" "^- A: \`$tmp/a\.h5\`, \`$tmp/a2\.h5\`$"
if [[ $(head -c 4 "$tmp/ab.png" | od -An -c | tr -d ' ') == "211PNG" ]]; then echo "ok   --plot writes a PNG"; else fail "no PNG at $tmp/ab.png"; fi
# CSV: the medians at full precision, pooled over both A files (6 passes) against B's 3.
"${ab[@]}" --a "$tmp/a.h5" "$tmp/a2.h5" --b "$tmp/b.h5" --csv >"$tmp/ab.csv"
check "CSV: medians over the pooled passes, exactly" 0 "^6 rows exact$" -- "$python" - "$tmp/ab.csv" "$tmp/a.h5" <<'PY'
import csv, sys
import h5py, numpy as np
rows = list(csv.DictReader(open(sys.argv[1])))
passes = h5py.File(sys.argv[2], "r")["passes/t_total_ms"][()]
bad = [r["frame"] for k, r in enumerate(rows)
       if float(r["a_median_ms"]) != float(np.median(np.concatenate([passes[k], passes[k]])))
       or float(r["b_median_ms"]) != 2 * float(np.median(passes[k])) or float(r["ratio"]) != 2.0
       or (r["a_n"], r["b_n"]) != ("6", "3") or bool(r["plan_a"]) != (r["frame"] == "4")]
print(f"{len(rows)} rows " + ("exact" if not bad else "differ at frames " + ",".join(bad)))
PY
check "another scene is refused" 1 "A is scene funnel\[res=8\], B funnel\[res=16\]" -- bash -c "
  '$cdbench' run --device cpu --quiet --scene funnel --set res=16 --frames 0:3 --warmup-ms 0 --out '$tmp/other.h5' >/dev/null 2>&1
  '$python' '$root/scripts/ab_frames.py' --a '$tmp/a.h5' --b '$tmp/other.h5'"

finish ab_frames
