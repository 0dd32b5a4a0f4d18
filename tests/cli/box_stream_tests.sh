#!/usr/bin/env bash
# Bring your own data (docs/usage.md "Your own data"): box streams written by NumPy and by
# printf are verified and run like any scene, their bad frames and the features that need
# triangles are refused, and the worked example (an OBJ cloth sequence and an OBJ collider
# sequence as parts with declared queries) runs as the documentation's steps say.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

# 300 boxes drifting over 4 frames, in the three formats; the .npy frames alternate the
# (N, 6) and (N, 2, 3) shapes. Coordinates on a 1/32 grid, so boxes also touch exactly.
"$python" - "$tmp" <<'PY'
import sys, numpy as np
out = sys.argv[1]
rng = np.random.default_rng(7)
lo = rng.integers(0, 64, size=(300, 3)) / 32.0
size = rng.integers(0, 5, size=(300, 3)) / 32.0
step = rng.integers(-1, 2, size=(300, 3)) / 32.0
import os
for d in ("f32", "f64", "npy"):
    os.makedirs(f"{out}/{d}", exist_ok=True)
for k in range(4):
    boxes = np.hstack([lo + k * step, lo + k * step + size])  # (N, 6): min.xyz max.xyz
    boxes.astype("<f4").tofile(f"{out}/f32/frame_{k}.boxes")
    boxes.astype("<f8").tofile(f"{out}/f64/frame_{k}.boxes64")
    arr = boxes.astype("<f4")
    np.save(f"{out}/npy/frame_{k}.npy", arr if k % 2 else arr.reshape(-1, 2, 3))
PY
for d in f32 f64 npy; do
  check "$d box stream verifies" 0 "all pipelines match the oracle" -- \
    "$cdbench" verify --device cpu --scene "$tmp/$d"
  has "$d: verify names 300 primitives" "$tmp/out" "verify: scene $d \(300 triangles\)"
done
check "box stream runs" 0 "box stream .*300 boxes \(boxes\), 4 frames" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/f32" --pipeline bvh
check "box stream in scenes info" 0 "^boxes +300 " -- "$cdbench" scenes info "$tmp/npy"
has "scenes info says box stream" "$tmp/out" "box stream .*300 boxes \(npy\), 4 frames"
check "box stream results written" 0 "pairs +mean" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/f32" --pipeline static --out "$tmp/boxes.h5"
check "results say box stream" 0 "^box stream .*f32: 300 boxes \(boxes\), 4 frames$" -- \
  "$python" -c "import h5py, sys; print(h5py.File(sys.argv[1], 'r').attrs['scene_description'])" "$tmp/boxes.h5"
check "run --check is refused on boxes" 2 "has 300 boxes \(a box stream\), and --check counts contacts of triangles" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/f32" --check every

# printf: two float32 boxes (24 bytes each) that touch at x = 1, one pair.
mkdir -p "$tmp/printf"
printf '\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x80\x3f\x00\x00\x80\x3f\x00\x00\x80\x3f' >"$tmp/printf/f0.boxes"
printf '\x00\x00\x80\x3f\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x40\x00\x00\x80\x3f\x00\x00\x80\x3f' >>"$tmp/printf/f0.boxes"
check "printf boxes that touch are a pair" 0 "all pipelines match the oracle" -- \
  "$cdbench" verify --device cpu --scene "$tmp/printf"
check "printf boxes run" 0 "pairs +1 " -- "$cdbench" run --device cpu --scene "$tmp/printf" --pipeline brute

# Bad frames exit 1 naming the file, frame and box.
mkdir -p "$tmp/bad"
cp "$tmp/f32/frame_0.boxes" "$tmp/bad/frame_0.boxes"
"$python" -c "
import numpy as np, sys
b = np.fromfile('$tmp/f32/frame_1.boxes', '<f4').reshape(-1, 6)
b[17, 4] = np.nan
b.tofile('$tmp/bad/frame_1.boxes')"
check "NaN box refused" 1 "bad/frame_1.boxes: frame 1, box 17: max.y is nan" -- \
  "$cdbench" verify --device cpu --scene "$tmp/bad"
head -c 100 "$tmp/f32/frame_1.boxes" >"$tmp/bad/frame_1.boxes"
check "truncated frame refused" 1 "frame_1.boxes: frame 1: 100 bytes is not a whole number of boxes" -- \
  "$cdbench" run --device cpu --scene "$tmp/bad"
cp "$tmp/f32/frame_1.boxes" "$tmp/bad/frame_1.boxes"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$tmp/bad/frame_2.obj"
check "box and mesh frames in one directory refused" 1 "mixes box frames .* and mesh frames \(frame_2.obj\)" -- \
  "$cdbench" scenes info "$tmp/bad"

# Boxes at float's limit: every pipeline exact, with and without a margin that keeps them
# within float range; a margin that takes a box past +-FLT_MAX is refused (exit 2), naming
# the option and the frame, before the pipelines run it. Frame 1 moves box 0 to FLT_MAX.
mkdir -p "$tmp/limit"
"$python" - "$tmp/limit" <<'PY'
import sys, numpy as np
big = float(np.finfo(np.float32).max)
c = 0.9 * big
boxes = np.array([[c - 1e36 * k] * 3 + [c - 1e36 * k + 1e37] * 3 for k in range(3)] +
                 [[-c - 1e37 + 1e36 * k] * 3 + [-c + 1e36 * k] * 3 for k in range(3)])
boxes.astype("<f4").tofile(f"{sys.argv[1]}/frame_0.boxes")
boxes[0, 3:] = big
boxes.astype("<f4").tofile(f"{sys.argv[1]}/frame_1.boxes")
PY
check "boxes at float's limit verify" 0 "all pipelines match the oracle" -- \
  "$cdbench" verify --device cpu --scene "$tmp/limit"
check "a margin within float range verifies there" 0 "all pipelines match the oracle" -- \
  "$cdbench" verify --device cpu --scene "$tmp/limit" --box-margin 1e36 --frames 0
check "verify: a margin past float range refused" 2 \
  "^cdbench: error: frame 1: --box-margin 1e\+36 takes a box past float range: vertex 1's x is 3.40282e\+38" -- \
  "$cdbench" verify --device cpu --scene "$tmp/limit" --box-margin 1e36 --frames 0:2
check "run: a margin past float range refused" 2 "^cdbench: error: frame 0: --box-margin 1e\+38 takes a box past float range" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/limit" --pipeline grid --box-margin 1e38

# The worked example of docs/usage.md, step by step.
ex=$tmp/my-scene
check "example: cloth frames" 0 "wrote 12 frames" -- \
  "$cdbench" scenes generate cloth-wave --set res=24 --set frames=12 --out "$ex/cloth"
check "example: collider frames" 0 "wrote 12 frames" -- \
  "$cdbench" scenes generate "$root/scenes/examples/collider.json" --out "$ex/collider"
cp "$root/scenes/examples/cloth-and-collider.json" "$ex/"
check "example: scenes info" 0 "query +inter cloth - collider" -- "$cdbench" scenes info "$ex/cloth-and-collider.json"
has "example: the collider is a part" "$tmp/out" "object +collider +faces 1058\.\.1138"
check "example verifies" 0 "all pipelines match the oracle" -- \
  "$cdbench" verify --device cpu --scene "$ex/cloth-and-collider.json"
check "example runs with --check" 0 "check +12 frames against the oracle: recall min 1\.0+," -- \
  "$cdbench" run --device cpu --scene "$ex/cloth-and-collider.json" --check every --pipeline bvh --quiet

# Its declared queries: each frame's pairs by kind (self within the cloth, inter between
# cloth and ball, which meet from frame 6), self + inter = pairs every frame, in the file,
# its summary, report and run --json.
check "example: pairs by query in the summary" 0 "^  pairs +mean [0-9]+ per frame \\(self [0-9]+, inter [0-9]+\\)" -- \
  "$cdbench" run --device cpu --scene "$ex/cloth-and-collider.json" --pipeline c,grid --quiet --warmup-ms 0 \
    --out "$tmp/queries-{pipeline}.h5"
for p in c grid; do
  check "example: $p's self + inter = pairs every frame" 0 "^12 frames: self \\+ inter = pairs, inter > 0$" -- \
    "$python" - "$tmp/queries-$p.h5" <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    fr, s = f["frames"], f["summary"].attrs
    self_, inter, pairs = fr["pairs_self"][()], fr["pairs_inter"][()], fr["pairs"][()]
    assert (self_ + inter == pairs).all(), (self_, inter, pairs)
    w = int(s["warmup"])
    assert np.isclose(s["pairs_self_mean"], self_[w:].mean()) and np.isclose(s["pairs_inter_mean"], inter[w:].mean())
    print(f"{len(pairs)} frames: self + inter = pairs, inter {'> 0' if inter.sum() > 0 else '= 0'}")
PY
done
check "example: results format documented with queries" 0 "^0 differences" -- \
  "$python" "$root/tests/cli/results_format_check.py" "$root/docs/results-format.md" "$tmp/queries-c.h5"
check "example: report shows pairs by query" 0 "\\| pairs \\| pairs_self \\| pairs_inter \\|" -- \
  "$cdbench" report "$tmp/queries-c.h5"
"$cdbench" run --device cpu --scene "$ex/cloth-and-collider.json" --pipeline bvh --quiet --warmup-ms 0 --frames 5:8 \
  --json >"$tmp/queries.json" 2>/dev/null
check "example: run --json gives pairs by query" 0 "^self [0-9.]+ \\+ inter [0-9.]+ = pairs$" -- \
  "$python" -c "
import json, sys
r = json.load(open(sys.argv[1]))['runs'][0]
q = r['pairs_by_query']
assert q['self_mean'] + q['inter_mean'] == r['pairs_mean'], (q, r['pairs_mean'])
print(f\"self {q['self_mean']} + inter {q['inter_mean']} = pairs\")" "$tmp/queries.json"
check "run --json without declared queries: pairs_by_query null" 0 '"pairs_by_query": null' -- \
  "$cdbench" run --device cpu --scene "$ex/cloth/" --pipeline bvh --quiet --warmup-ms 0 --frames 0:2 --json

finish "box stream"
