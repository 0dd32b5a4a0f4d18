#!/usr/bin/env bash
# Results files never overwrite finished work nor claim more than they hold; bad OBJ frames
# and reused output directories are refused. Exit codes as docs/usage.md gives them.
set -u
cdbench=$1
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$root/tests/cli/harness.sh"

d=$tmp/res
mkdir -p "$d"
small=(--device cpu --quiet --scene funnel --set res=16 --frames 0:4)
# A run far too long to finish: stopped by a signal or a failed write, never by its end.
printf '{"generator": "cloth-wave", "params": {"res": 16, "frames": 1000000}}' >"$tmp/endless.json"
endless=(--device cpu --scene "$tmp/endless.json")
skipped=0
skip() {  # skip NAME REASON: a check that cannot run here, said rather than passed
  echo "skip $1: $2"
  skipped=$((skipped + 1))
}
# report_status FILE: the status column report gives FILE ("complete", "incomplete ...").
report_status() { "$cdbench" report --csv "$1" 2>&1 | tail -1 | awk -F, '{print $NF}'; }
# A line of stderr that the HDF5 library or std::filesystem wrote, not cdbench.
raw_library_text() { grep -qE "HDF5-DIAG|H5[A-Z][a-z_]+\(\)|filesystem error|slist|errno = " "$1"; }

# --- an existing file is kept unless --overwrite ---
check "first run writes a complete file" 0 "^results: $d/r.h5 \(4 frames\)" -- "$cdbench" run "${small[@]}" --out "$d/r.h5"
before=$(md5sum <"$d/r.h5")
check "existing results file refused" 2 "--out $d/r.h5: the file exists; pass --overwrite" -- \
  "$cdbench" run "${small[@]}" --out "$d/r.h5"
if grep -qE "^(scene|pipeline|frame|copy bandwidth)" "$tmp/out"; then fail "work began before the refusal"; else echo "ok   refused before any work"; fi
[[ $(md5sum <"$d/r.h5") == "$before" ]] && echo "ok   refused file unchanged" || fail "refused file changed"
check "--overwrite replaces it" 0 "^results: $d/r.h5 \(4 frames\)" -- "$cdbench" run "${small[@]}" --out "$d/r.h5" --overwrite
[[ -e $d/r.h5.incomplete ]] && fail "staged file left after a complete run" || echo "ok   no staged file left after a complete run"
[[ $(report_status "$d/r.h5") == complete ]] && echo "ok   replaced file is complete" || fail "replaced file: $(report_status "$d/r.h5")"
check "--overwrite needs --out" 2 "overwrite" -- "$cdbench" run "${small[@]}" --overwrite

echo "keep me" >"$d/precious.txt"
check "non-results file refused" 2 "--out $d/precious.txt: the file exists" -- "$cdbench" run "${small[@]}" --out "$d/precious.txt"
[[ $(cat "$d/precious.txt") == "keep me" ]] && echo "ok   precious.txt untouched" || fail "precious.txt changed"

# --- a complete file survives a later run that fails or is stopped ---
before=$(md5sum <"$d/r.h5")
mkdir -p "$tmp/nanseq"
for f in 0 1 2; do printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 %s\nf 1 2 3\nf 1 2 4\n' "$([[ $f == 2 ]] && echo nan || echo $f)" >"$tmp/nanseq/frame_000$f.obj"; done
check "failing run with --overwrite fails" 1 "frame_0002.obj" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/nanseq" --out "$d/r.h5" --overwrite
[[ $(md5sum <"$d/r.h5") == "$before" ]] && echo "ok   complete file unchanged by the failing run" || fail "complete file changed by a failing run"
"$cdbench" run "${endless[@]}" --out "$d/r.h5" --overwrite >"$tmp/killed.out" 2>&1 &
pid=$!
for _ in $(seq 600); do grep -q "^frame  *2 " "$tmp/killed.out" && break; sleep 0.1; done
kill -TERM "$pid"
wait "$pid"; rc=$?
[[ $rc -eq 143 ]] && echo "ok   stopped run exits 143" || fail "stopped run: rc=$rc (want 143)"
has "stopped run names its partial file" "$tmp/killed.out" "results \(incomplete\): $d/r.h5.incomplete"
has "stopped run says the old file was kept" "$tmp/killed.out" "$d/r.h5 left as it was"
[[ $(report_status "$d/r.h5") == complete ]] && echo "ok   report still reads the file as complete" || fail "after the stopped run: $(report_status "$d/r.h5")"
[[ $(md5sum <"$d/r.h5") == "$before" ]] && echo "ok   complete file unchanged by the stopped run" || fail "complete file changed by the stopped run"
case $(report_status "$d/r.h5.incomplete") in
  incomplete*SIGTERM*) echo "ok   the stopped run's own file reads as incomplete" ;;
  *) fail "staged file: $(report_status "$d/r.h5.incomplete")" ;;
esac

# --- {pipeline}: one file per pipeline, every placeholder replaced ---
check "two pipelines onto one file refused" 2 "pipelines c and c would both write $d/dup-c.h5" -- \
  "$cdbench" run "${small[@]}" --pipeline c,c --out "$d/dup-{pipeline}.h5"
[[ -e $d/dup-c.h5 ]] && fail "a file was written for the refused duplicates" || echo "ok   nothing written for the duplicates"
check "every {pipeline} replaced" 0 "^results: $d/pat-bvh-bvh.h5 \(4 frames\)" -- \
  "$cdbench" run "${small[@]}" --pipeline c,bvh --out "$d/pat-{pipeline}-{pipeline}.h5"
has "first pipeline's name replaced twice" "$tmp/out" "^results: $d/pat-c-c.h5 \(4 frames\)"
ls "$d" | grep -q "{pipeline}" && fail "a file name kept {pipeline}" || echo "ok   no file name keeps {pipeline}"

# --- SIGTERM right after the start: no file, or one report reads as incomplete ---
# Counted from when the process catches SIGTERM (its SigCgt mask in /proc): a signal before
# main() runs gets the system's default action, which no program can answer with a message.
catches_sigterm() {
  local mask
  mask=$(awk '/^SigCgt:/ {print $2}' "/proc/$1/status" 2>/dev/null)
  [[ -n $mask ]] && (((16#$mask >> 14) & 1))
}
for delay in 0 0.02 0.05 0.1 0.2 0.3 0.5 0.8; do
  f=$d/sig-$delay.h5
  "$cdbench" run "${endless[@]}" --quiet --out "$f" >"$tmp/sig.out" 2>&1 &
  pid=$!
  for _ in $(seq 1000); do catches_sigterm "$pid" && break; sleep 0.005; done
  sleep "$delay"
  kill -TERM "$pid"
  wait "$pid"; rc=$?
  if [[ -e $f ]]; then state=$(report_status "$f"); else state="no file"; fi
  if [[ $rc -eq 143 ]] && grep -q "interrupted by SIGTERM" "$tmp/sig.out" &&
     [[ $state == "no file" || $state == incomplete*SIGTERM* ]]; then
    echo "ok   SIGTERM after ${delay}s: 143, $state"
  else
    fail "SIGTERM after ${delay}s: rc=$rc, $state"; sed 's/^/    /' "$tmp/sig.out" | tail -5
  fi
done

# --- a write that fails on the system's side ---
# disk_full NAME DIR [ULIMIT_KB]: a run whose results outgrow DIR (or the file size limit):
# exit 1 (no crash), the system's reason in a clear sentence, no raw library text, and a
# file that report reads as incomplete, or none.
disk_full() {
  local name=$1 dir=$2 limit=${3:-}
  local f=$dir/full.h5
  if [[ -n $limit ]]; then
    (ulimit -f "$limit"; exec "$cdbench" run "${endless[@]}" --quiet --save-pairs --out "$f") >"$tmp/full.out" 2>&1
  else
    "$cdbench" run "${endless[@]}" --quiet --save-pairs --out "$f" >"$tmp/full.out" 2>&1
  fi
  local rc=$?
  if [[ $rc -eq 1 ]] && grep -qE "^cdbench: (error: )?writing results to $f failed: (no space left on device|file too large)$" "$tmp/full.out"; then
    echo "ok   $name: exit 1, $(grep -m1 -oE '(no space left on device|file too large)' "$tmp/full.out")"
  else
    fail "$name: rc=$rc (want 1 and 'writing results to $f failed: ...')"; sed 's/^/    /' "$tmp/full.out" | tail -8
  fi
  if raw_library_text "$tmp/full.out"; then fail "$name: raw library text"; grep -m3 -E "HDF5|H5|slist|errno" "$tmp/full.out"; else echo "ok   $name: no raw library text"; fi
  local state="no file"
  [[ -e $f ]] && state=$(report_status "$f")
  case $state in
    "no file" | incomplete*) echo "ok   $name: $state" ;;
    *) fail "$name: the file left: $state" ;;
  esac
}
mkdir -p "$tmp/tiny"
if mount -t tmpfs -o size=200k tmpfs "$tmp/tiny" 2>"$tmp/mount.err"; then
  disk_full "full disk (200k tmpfs)" "$tmp/tiny"
  umount "$tmp/tiny"
else
  skip "full disk (200k tmpfs)" "cannot mount a tmpfs here: $(head -1 "$tmp/mount.err")"
fi
mkdir -p "$tmp/limited"
disk_full "file size limit (ulimit -f 200)" "$tmp/limited" 200

# --- OBJ frames whose faces change ---
"$cdbench" scenes generate funnel --set res=4 --set frames=3 --out "$tmp/faces" >/dev/null 2>&1
first_face=$(grep -m1 "^f " "$tmp/faces/frame_0002.obj")
sed -i '0,/^f .*/s//f 1 1 1/' "$tmp/faces/frame_0002.obj"
check "changed faces refused" 1 "frame_0002.obj: frame 2: face 1 has vertices 1 1 1, frame 0's face 1 has ${first_face#f }" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/faces"
if grep -qE "^frame " "$tmp/out"; then fail "frames ran before the changed faces were found"; else echo "ok   found before any frame ran"; fi

# --- scenes generate into a directory used before ---
check "generate 6 frames" 0 "wrote 6 frames" -- "$cdbench" scenes generate funnel --set res=4 --set frames=6 --out "$tmp/gen"
check "generate 3 frames over them" 0 "removed 3 frames left there by an earlier generation" -- \
  "$cdbench" scenes generate funnel --set res=4 --set frames=3 --out "$tmp/gen"
listing=$(ls "$tmp/gen" | tr '\n' ' ')
[[ $listing == "frame_0000.obj frame_0001.obj frame_0002.obj " ]] && echo "ok   only the new frames remain" || fail "left: $listing"
check "the directory reads as 3 frames" 0 "frames 0:3" -- "$cdbench" run --device cpu --quiet --scene "$tmp/gen"
echo "notes" >"$tmp/gen/notes.txt"
check "directory holding other files refused" 2 "--out $tmp/gen: holds notes.txt, which \`scenes generate\` did not write" -- \
  "$cdbench" scenes generate funnel --set res=4 --set frames=2 --out "$tmp/gen"
[[ -e $tmp/gen/frame_0002.obj ]] && echo "ok   refused directory untouched" || fail "refused directory changed"

check "--out /dev/null refused before any work" 2 "^cdbench: error: --out /dev/null: not a regular file" -- \
  "$cdbench" run --device cpu --quiet --frames 0:3 --out /dev/null --overwrite
check "--out in /proc names the reason" 1 "--out /proc/r.h5: cannot write in directory /proc: (the file system does not take new files here|Permission denied|Read-only file system)" -- \
  "$cdbench" run --device cpu --quiet --frames 0:3 --out /proc/r.h5

[[ $skipped -ne 0 ]] && echo "$skipped check(s) skipped (reasons above)"
finish reliability
