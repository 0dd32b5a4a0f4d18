#!/usr/bin/env bash
# run --check's contacts: --contact-distance raises them monotonically, swept boxes find
# interval contacts that discrete boxes miss (a discrete run finds none), the fields reach the
# results file, and bad values are refused.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

# Contacts between triangles sharing no vertex on the default scene (funnel), two frames, with
# boxes as fat as the distance so that the pairs within it are reported.
previous=-1
for distance in 0 0.001 0.003 0.01; do
  check "contacts within $distance" 0 "contacts +[0-9]+ of [0-9]+ checked pairs" -- \
    "$cdbench" run --device cpu --quiet --frames 0:2 --pipeline static --check every --skip-adjacent \
    --box-margin "$distance" --contact-distance "$distance"
  contacts=$(sed -nE 's/^  contacts +([0-9]+) of .*/\1/p' "$tmp/out")
  if [[ -n $contacts && $contacts -gt $previous ]]; then
    echo "ok   contacts rise with the distance: $contacts within $distance"
  else
    fail "contacts within $distance: '$contacts', not above $previous"
  fi
  previous=${contacts:-$previous}
done
has "a distance is printed as the float it is" "$tmp/out" "lie within 0\\.00999999978:"

# A fast soup: 3000 triangles jumping about their own size between frames.
soup=(--scene random-100k --set triangles=3000 --set jitter=1 --device cpu --quiet --pipeline static --check every)
missed() { sed -nE 's/^  interval +([0-9]+) contacts missed.*/\1/p' "$tmp/out"; }
check "swept boxes find contacts discrete boxes miss" 0 "interval +[1-9][0-9]* contacts missed by discrete boxes" -- \
  "$cdbench" run "${soup[@]}" --boxes swept --out "$tmp/swept.h5"
eight=$(missed)
check "discrete boxes miss none they report" 0 "interval +0 contacts missed by discrete boxes" -- \
  "$cdbench" run "${soup[@]}"
# One substep samples the two frames only, a subset of the 9 times of 8 substeps.
check "one substep: the two frames" 0 "within 0 at one of 2 sampled times" -- \
  "$cdbench" run "${soup[@]}" --boxes swept --contact-substeps 1
one=$(missed)
if [[ -n $one && -n $eight && $one -le $eight ]]; then
  echo "ok   fewer samples find no more: $one with 1 substep, $eight with 8"
else
  fail "fewer samples: '$one' with 1 substep, '$eight' with 8"
fi
check "per-frame column and settings in the results file" 0 "^ok$" -- "$python" - "$tmp/swept.h5" <<'PY'
import json, sys
import h5py
with h5py.File(sys.argv[1], "r") as f:
    missed = f["frames/discrete_missed_contacts"][:]
    assert missed.sum() == f["summary"].attrs["discrete_missed_contacts"] > 0, missed
    assert missed[0] == 0, missed  # the first frame has no interval before it
    assert f.attrs["contact_distance"] == 0 and f.attrs["contact_substeps"] == 8
    resolved = json.loads(f.attrs["params_json"])["resolved"]
    assert resolved["contact_distance"] == 0 and resolved["contact_substeps"] == 8, resolved
print("ok")
PY

check "negative distance" 2 "--contact-distance -1: expected a finite distance >= 0" -- \
  "$cdbench" run --device cpu --quiet --frames 0:1 --check every --contact-distance -1
check "NaN distance" 2 "--contact-distance nan: expected a finite distance" -- \
  "$cdbench" run --device cpu --quiet --frames 0:1 --check every --contact-distance nan
check "distance beyond float" 2 "--contact-distance 1e\\+39: expected a finite distance" -- \
  "$cdbench" run --device cpu --quiet --frames 0:1 --check every --contact-distance 1e39
check "zero substeps" 2 "--contact-substeps 0: expected at least 1" -- \
  "$cdbench" run --device cpu --quiet --frames 0:1 --check every --contact-substeps 0
check "contact options need --check" 2 "need --check" -- \
  "$cdbench" run --device cpu --quiet --frames 0:1 --contact-distance 0.1
finish contact
