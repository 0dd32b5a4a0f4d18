#!/usr/bin/env bash
# picture: the PNG decodes (tests/cli/png_pixels.py) at the size asked, its contact colour
# is where the frame has pairs and nowhere when it has none, every view draws the scene,
# and a frame past the end, a directory or an unwritable --out are refused.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

pixels() {  # pixels NAME FILE SIZE: the picture decodes at SIZE x SIZE; sets drawn, contact
  local out
  if ! out=$("$python" "$root/tests/cli/png_pixels.py" "$2" 2>&1); then fail "$1: $out"; return; fi
  read -r width height drawn contact < <(sed -E 's/[a-z]+=//g' <<<"$out")
  if [[ $width == "$3" && $height == "$3" ]]; then echo "ok   $1: decodes, ${width}x$height"; else fail "$1: $out"; fi
}

check "funnel frame 10" 0 "marked +[1-9][0-9]* triangles \(red-orange\) in [1-9][0-9]* pairs of pipeline sweep" -- \
  "$cdbench" picture --scene funnel --frame 10 --skip-adjacent --size 96 --out "$tmp/funnel.png"
has "the picture's path and size printed" "$tmp/out" "^picture: $tmp/funnel.png, 96x96 pixels, view iso"
has "the triangle count printed" "$tmp/out" "funnel frame 10 \(of 20\), 8674 triangles"
has "the time printed" "$tmp/out" "^  time +[0-9.]+ s"
pixels "funnel picture" "$tmp/funnel.png" 96
if ((drawn > 1000 && contact > 0)); then echo "ok   pairs: $contact of $drawn drawn pixels in the contact colour"
else fail "pairs: $contact of $drawn drawn pixels in the contact colour"; fi

pairs_contact=$contact
# --mark contacts: of the same pairs, those of triangles that touch and share no vertex
# (the cloth on the ball and the funnel): some, and fewer than the pairs mark.
check "funnel frame 10, contacts" 0 "marked +[1-9][0-9]* triangles \(red-orange\) in [1-9][0-9]* contacts within 0 \(sharing no vertex\) of [1-9][0-9]* pairs" -- \
  "$cdbench" picture --scene funnel --frame 10 --mark contacts --size 96 --out "$tmp/contacts.png"
pixels "contacts picture" "$tmp/contacts.png" 96
if ((contact > 0 && contact < pairs_contact)); then echo "ok   contacts: $contact pixels in the contact colour, pairs $pairs_contact"
else fail "contacts: $contact pixels in the contact colour, pairs $pairs_contact"; fi
check "--mark neither pairs nor contacts" 2 "--mark" -- "$cdbench" picture --mark touching --out "$tmp/x.png"
check "a negative contact distance" 2 "--contact-distance" -- "$cdbench" picture --mark contacts --contact-distance -1 --out "$tmp/x.png"

# 20 small triangles far apart: no pairs, so no pixel in the contact colour.
check "a frame without pairs" 0 "marked +0 triangles \(red-orange\) in 0 pairs" -- \
  "$cdbench" picture --scene random-100k --set triangles=20 --set size=0.03 --skip-adjacent --size 64 \
  --out "$tmp/apart.png"
pixels "picture without pairs" "$tmp/apart.png" 64
if ((drawn > 0 && contact == 0)); then echo "ok   no pairs: $drawn pixels drawn, none in the contact colour"
else fail "no pairs: $contact of $drawn drawn pixels in the contact colour"; fi

# Swept boxes span frame 0 to 1 of a fast soup: more pairs than frame 1's discrete boxes.
soup=(--scene random-100k --set triangles=3000 --set jitter=1 --set frames=2 --frame 1 --size 32)
pairs_of() { sed -nE 's/.* in ([0-9]+) pairs .*/\1/p' "$tmp/out"; }
check "discrete boxes" 0 "pairs of pipeline sweep" -- "$cdbench" picture "${soup[@]}" --out "$tmp/discrete.png"
discrete=$(pairs_of)
check "swept boxes" 0 "pairs of pipeline sweep" -- "$cdbench" picture "${soup[@]}" --boxes swept --out "$tmp/swept.png"
swept=$(pairs_of)
if [[ -n $discrete && -n $swept && $swept -gt $discrete ]]; then echo "ok   swept boxes: $swept pairs, discrete $discrete"
else fail "swept boxes: '$swept' pairs, discrete '$discrete'"; fi

for view in x y z; do
  check "view $view" 0 "view $view" -- "$cdbench" picture --view "$view" --size 32 --pipeline hash --out "$tmp/$view.png"
  pixels "view $view" "$tmp/$view.png" 32
  ((drawn > 0)) && echo "ok   view $view draws the scene" || fail "view $view: nothing drawn"
done

check "a frame past the end" 2 "--frame 20: scene funnel has 20 frames \(0 to 19\)" -- \
  "$cdbench" picture --frame 20 --out "$tmp/late.png"
[[ ! -e $tmp/late.png ]] && echo "ok   nothing written for a frame past the end" || fail "late.png written"
check "--out a directory" 2 "--out $tmp: names a directory" -- "$cdbench" picture --out "$tmp"
check "--out empty" 2 "--out: expected a name" -- "$cdbench" picture --out ""
check "--out where nothing can be written" 1 "--out /proc/cdbench.png: cannot write in directory /proc" -- \
  "$cdbench" picture --out /proc/cdbench.png
touch "$tmp/plainfile"
check "--out under a file" 1 "--out $tmp/plainfile/f.png: cannot create directory" -- \
  "$cdbench" picture --out "$tmp/plainfile/f.png"
check "--size too small" 2 "--size" -- "$cdbench" picture --size 4
check "an unknown view" 2 "--view" -- "$cdbench" picture --view top
COLUMNS=100 "$cdbench" picture --help >"$tmp/help.txt" 2>&1
[[ $(awk 'length > 100' "$tmp/help.txt" | wc -l) -eq 0 ]] && echo "ok   picture --help fits 100 columns" ||
  fail "picture --help: lines over 100 columns"
finish picture
