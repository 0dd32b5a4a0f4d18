#!/usr/bin/env bash
# Results files never overwrite finished work nor claim more than they hold; bad OBJ frames
# and reused output directories are refused. Exit codes as docs/usage.md gives them.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

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

check "--overwrite says it replaces an earlier run's partial file" 0 \
  "^warning: $d/r.h5.incomplete, the partial file an earlier run left, will be replaced by this run's$" -- \
  "$cdbench" run "${small[@]}" --out "$d/r.h5" --overwrite

# --- two runs onto one file: the second refused, the first's file (and an older one) intact ---
# writer_busy FILE [OPTIONS...]: a run writing FILE, stopped once a second run onto it was
# refused; the first's file reads as incomplete (SIGTERM), the second changed nothing.
writer_busy() {
  local f=$1; shift
  "$cdbench" run "${endless[@]}" --out "$f" "$@" >"$tmp/first.out" 2>&1 &
  local pid=$!
  for _ in $(seq 600); do grep -q "^frame  *2 " "$tmp/first.out" && break; sleep 0.1; done
  check "second run onto $(basename "$f") $* refused" 2 "^cdbench: error: $f is being written by another cdbench run \(pid $pid\)" -- \
    "$cdbench" run "${small[@]}" --pipeline bvh --out "$f" "$@"
  kill -TERM "$pid"
  wait "$pid"
}
writer_busy "$d/busy.h5"
[[ $(report_status "$d/busy.h5") == incomplete*SIGTERM* ]] && echo "ok   the first run's file is intact" || fail "first run's file: $(report_status "$d/busy.h5")"
[[ -e $d/busy.h5.lock ]] && fail "lock file left after the run" || echo "ok   no lock file left"
before=$(md5sum <"$d/r.h5")
writer_busy "$d/r.h5" --overwrite
[[ $(md5sum <"$d/r.h5") == "$before" ]] && echo "ok   the older complete file unchanged by both" || fail "older file changed: $(report_status "$d/r.h5")"
[[ $(report_status "$d/r.h5.incomplete") == incomplete*SIGTERM* ]] && echo "ok   the first run's staged file is intact" || fail "staged file: $(report_status "$d/r.h5.incomplete")"
rm -f "$d/r.h5.incomplete"
# A lock file a killed run left behind holds nobody back.
echo 99999999 >"$d/stale.h5.lock"
check "a stale lock file is taken over" 0 "^results: $d/stale.h5 \(4 frames\)" -- "$cdbench" run "${small[@]}" --out "$d/stale.h5"

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

# --- every signal that asks a program to stop: as SIGTERM, the frames run kept ---
for sig in HUP QUIT USR1 USR2 ALRM XCPU; do
  f=$d/stop-$sig.h5
  "$cdbench" run "${endless[@]}" --out "$f" >"$tmp/stop.out" 2>&1 &
  pid=$!
  for _ in $(seq 600); do grep -q "^frame  *2 " "$tmp/stop.out" && break; sleep 0.1; done
  kill -"$sig" "$pid"
  wait "$pid"; rc=$?
  want=$((128 + $(kill -l "$sig")))
  state=$(report_status "$f")
  if [[ $rc -eq $want ]] && grep -q "^cdbench: interrupted by SIG$sig after [1-9][0-9]* of 1000000 frames" "$tmp/stop.out" &&
     [[ $state == *"incomplete"*"SIG$sig after "[1-9]* ]]; then
    echo "ok   SIG$sig: $rc, frames kept"
  else
    fail "SIG$sig: rc=$rc (want $want), $state"; grep -v "^frame" "$tmp/stop.out" | tail -3
  fi
done
# Before the scene is loaded: at once, said.
"$cdbench" run "${endless[@]}" --out "$d/early.h5" >"$tmp/early.out" 2>&1 &
pid=$!
for _ in $(seq 1000); do catches_sigterm "$pid" && break; sleep 0.005; done
kill -HUP "$pid"
wait "$pid"; rc=$?
if [[ $rc -eq 129 ]] && grep -q "interrupted by SIGHUP" "$tmp/early.out"; then echo "ok   SIGHUP at the start: 129, said"
else fail "SIGHUP at the start: rc=$rc"; tail -3 "$tmp/early.out"; fi

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

# A short run whose file the disk (or the limit) cuts off at its end, at several sizes: exit
# 1, and the file left is one report reads as incomplete, or none, said so.
end_full() {  # end_full NAME DIR [ULIMIT_KB]
  local name=$1 dir=$2 limit=${3:-} f=$2/end.h5
  rm -f "$f"
  if [[ -n $limit ]]; then
    (ulimit -f "$limit"; exec "$cdbench" run --device cpu --quiet --scene funnel --set res=16 --frames 0:10 --out "$f") >"$tmp/end.out" 2>&1
  else
    "$cdbench" run --device cpu --quiet --scene funnel --set res=16 --frames 0:10 --out "$f" >"$tmp/end.out" 2>&1
  fi
  local rc=$? state="no file"
  [[ -e $f ]] && state=$(report_status "$f")
  if [[ $rc -eq 1 ]] && grep -q "writing results to $f failed" "$tmp/end.out" &&
     { { [[ $state == incomplete* ]] && grep -q "results (incomplete.*): $f$" "$tmp/end.out"; } ||
       { [[ $state == "no file" ]] && ! grep -q "results (incomplete" "$tmp/end.out"; }; }; then
    echo "ok   $name: $state"
  else
    fail "$name: rc=$rc, $state"; sed 's/^/    /' "$tmp/end.out" | grep -v "^    frame" | tail -6
  fi
}
for size in 64k 100k 150k; do
  if mount -t tmpfs -o size=$size tmpfs "$tmp/tiny" 2>"$tmp/mount.err"; then
    end_full "run's end on a full disk ($size tmpfs)" "$tmp/tiny"
    umount "$tmp/tiny"
  else
    skip "run's end on a full disk ($size tmpfs)" "cannot mount a tmpfs here: $(head -1 "$tmp/mount.err")"
  fi
done
for kb in 20 40 60 100 150; do end_full "run's end past ulimit -f $kb" "$tmp/limited" "$kb"; done
# The other commands that write files: a clear error, exit 1 rather than killed by SIGXFSZ,
# and no cut-off file left to be read as a shorter frame.
(ulimit -f 20; exec "$cdbench" scenes generate funnel --set res=16 --set frames=3 --out "$tmp/limited/gen") >"$tmp/gen.out" 2>&1
rc=$?
if [[ $rc -eq 1 ]] && grep -q "gen/frame_0000.obj: write failed: File too large (the partial frame removed)" "$tmp/gen.out" &&
   [[ ! -e $tmp/limited/gen/frame_0000.obj ]]; then echo "ok   scenes generate past ulimit -f: exit 1, nothing cut off left"
else fail "scenes generate past ulimit -f: rc=$rc"; tail -3 "$tmp/gen.out"; fi
(ulimit -f 4; exec "$cdbench" verify --device cpu --scene funnel --set res=16 --frames 0:3 --write-pairs "$tmp/limited/pairs") >"$tmp/wp.out" 2>&1
rc=$?
if [[ $rc -eq 1 ]] && grep -q "pairs/frame_0000.txt: write failed: File too large (the partial file removed)" "$tmp/wp.out" &&
   [[ ! -e $tmp/limited/pairs/frame_0000.txt ]]; then echo "ok   verify --write-pairs past ulimit -f: exit 1, nothing cut off left"
else fail "verify --write-pairs past ulimit -f: rc=$rc"; tail -3 "$tmp/wp.out"; fi

# --- stdout the system refuses: the command fails, said on stderr ---
for command in "report --csv $d/r.h5" "report $d/r.h5" "report --plan $d/r.h5" "compare --json $d/r.h5 $d/r.h5" \
               "scenes info funnel" "scenes list" "run ${small[*]} --json" "--version"; do
  # shellcheck disable=SC2086
  "$cdbench" $command >/dev/full 2>"$tmp/full-stdout.err"; rc=$?
  if [[ $rc -eq 1 ]] && grep -q "^cdbench: error: writing to standard output failed.*: what it printed is incomplete$" "$tmp/full-stdout.err"; then
    echo "ok   $command >/dev/full: exit 1, said"
  else
    fail "$command >/dev/full: rc=$rc"; tail -2 "$tmp/full-stdout.err"
  fi
done
check "a usage error keeps exit 2 on /dev/full" 2 "unknown pipeline" -- bash -c '"$1" run --device cpu --pipeline nope >/dev/full' _ "$cdbench"

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
  "$cdbench" scenes generate funnel --set res=4 --set frames=3 --out "$tmp/gen" --overwrite
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

# --- cached frames: a cache file changed since it was written is simulated again ---
export CDBENCH_CACHE=$tmp/cache
unset CDBENCH_FRAME_CACHE
cached=(--device cpu --quiet --scene cloth-wave --set res=8 --set frames=3 --pipeline bvh)
check "first run fills the frame cache" 0 "^  pairs +mean" -- "$cdbench" run "${cached[@]}"
first_pairs=$(grep "^  pairs" "$tmp/out")
frame_file=$(find "$tmp/cache" -name frame_1.f64 | head -1)
if [[ -z $frame_file ]]; then
  fail "no cached frame_1.f64 under $tmp/cache"
else
  # Other finite numbers in place of the first vertex's x: whole, finite, and wrong.
  /usr/bin/python3 -c 'import struct,sys; f=open(sys.argv[1],"r+b"); f.seek(24); f.write(struct.pack("<d", 12345.5))' "$frame_file"
  check "a changed cache file is detected" 0 "cached frame .*frame_1\.f64 does not match its checksum .*; simulating the frame again" -- \
    "$cdbench" run "${cached[@]}"
  [[ $(grep "^  pairs" "$tmp/out") == "$first_pairs" ]] && echo "ok   the regenerated frame gives the first run's pairs" ||
    fail "pairs after regeneration: $(grep "^  pairs" "$tmp/out") (first run: $first_pairs)"
  check "the rewritten file is trusted again" 0 "^  pairs" -- "$cdbench" run "${cached[@]}"
  grep -q "cached frame" "$tmp/out" && fail "the regenerated cache file was refused again" || echo "ok   no note once rewritten"
fi
unset CDBENCH_CACHE

# --- OBJ frames: every frame checked before the first is timed, the line and field named ---
obj_seq() {  # obj_seq DIR Z1: three frames, frame 1's last vertex at z = Z1
  mkdir -p "$1"
  for f in 0 1 2; do
    printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 %s\nf 1 2 3\nf 1 2 4\n' "$([[ $f == 1 ]] && echo "$2" || echo 1)" >"$1/frame_000$f.obj"
  done
}
obj_seq "$tmp/far" 1e39
check "1e39 in frame 1 named by file, frame, line and field" 1 \
  "far/frame_0001.obj: frame 1, vertex 3: position beyond float range \(0 0 1e\+39\) on line 4 \(z is 1e\+39, float holds magnitudes up to 3.40282e\+38\): .*scale the frames down" -- \
  "$cdbench" run --device cpu --scene "$tmp/far"
if grep -qE "^frame " "$tmp/out"; then fail "a frame was timed before the bad frame was found"; else echo "ok   found before any frame was timed"; fi
obj_seq "$tmp/far308" 1e308
check "1e308 printed compactly" 1 "z is 1e\+308" -- "$cdbench" run --device cpu --quiet --scene "$tmp/far308"
grep -qE "[0-9]{40}" "$tmp/out" && fail "a number of 40 or more digits in the message" || echo "ok   no 309-digit number"
obj_seq "$tmp/garbage" 0.3xyz
check "trailing garbage on a vertex refused" 1 "garbage/frame_0001.obj: frame 1, line 4: '0.3xyz' is not a number" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/garbage"
obj_seq "$tmp/dangling" 1
ln -s frame_0009.obj "$tmp/dangling/frame_0003.obj"
check "dangling frame link refused" 1 "dangling/frame_0003.obj: this frame is a link that leads nowhere \(it leads to frame_0009.obj, which does not exist\)" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/dangling"
rm "$tmp/dangling/frame_0003.obj"
ln -s frame_0003.obj "$tmp/dangling/frame_0003.obj"
check "looping frame link refused" 1 "dangling/frame_0003.obj: this frame is a link that leads nowhere" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/dangling"
mkdir -p "$tmp/danglingbox"
printf '\0\0\0\0\0\0\0\0\0\0\0\0\0\0\200\77\0\0\200\77\0\0\200\77' >"$tmp/danglingbox/f0.boxes"
ln -s gone.boxes "$tmp/danglingbox/f1.boxes"
check "dangling box frame link refused" 1 "danglingbox/f1.boxes: this frame is a link that leads nowhere" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/danglingbox"

mkdir -p "$tmp/farboxes"
/usr/bin/python3 -c '
import struct, sys
for k in range(2):
    v = [0, 0, 0, 1, 1, 1, 0.5, 0.5, 0.5, 1.5, 1.5, 1.5]
    if k == 1: v[3] = 1e39
    open(sys.argv[1] + "/f%d.boxes64" % k, "wb").write(struct.pack("<12d", *v))' "$tmp/farboxes"
check "a box beyond float range found before any frame" 1 "farboxes/f1.boxes64: frame 1, box 0: max.x is 1e\+39, beyond float range" -- \
  "$cdbench" run --device cpu --scene "$tmp/farboxes"
if grep -qE "^frame " "$tmp/out"; then fail "a box frame was timed before the bad one was found"; else echo "ok   no box frame timed first"; fi

# --- descriptors and options quietly accepted before ---
printf '{"generator": "cloth-wave", "generator": "funnel", "params": {"res": 8, "frames": 3}}' >"$tmp/dupkey.json"
check "duplicate descriptor key refused" 1 "dupkey.json: key \"generator\" appears twice in the object at /" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/dupkey.json"
printf '{"generator": "cloth-wave", "params": {"res": 8, "res": 9, "frames": 3}}' >"$tmp/dupkey2.json"
check "duplicate nested key names its path" 1 "key \"res\" appears twice in the object at /params" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/dupkey2.json"
printf '{"generator": "cloth-wave", "params": {"res": 1e400}}' >"$tmp/overflow.json"
check "a number past double range in words" 1 "overflow.json: malformed JSON: .*beyond the range of a double" -- \
  "$cdbench" run --device cpu --quiet --scene "$tmp/overflow.json"
if raw_library_text "$tmp/out" || grep -q "json.exception" "$tmp/out"; then fail "raw library text"; else echo "ok   no raw library text"; fi
check "--max-noise nan refused" 2 "--max-noise: expected a finite number >= 0, not 'nan'" -- \
  "$cdbench" run "${small[@]}" --max-noise nan

# --- library text translated, the input named ---
check "a name that is not UTF-8" 1 "not valid UTF-8 .*rename it with UTF-8 characters" -- \
  "$cdbench" run "${small[@]}" --out "$d/bad-$(printf '\xff').h5"
ln -s loop-b "$tmp/loop-a"
ln -s loop-a "$tmp/loop-b"
check "a scene link loop" 1 "loop-a: its symbolic links form a loop" -- "$cdbench" run --device cpu --quiet --scene "$tmp/loop-a"
long=$(printf 'x%.0s' $(seq 300))
check "a 300-character file name" 1 "$long\.h5: the name is too long for the file system" -- "$cdbench" run "${small[@]}" --out "$d/$long.h5"
echo "not a directory" >"$tmp/sweep-out-file"
printf '{"scenes": [{"scene": "funnel", "set": {"res": 8, "frames": 3}}], "pipelines": ["bvh"], "devices": ["cpu"]}' >"$tmp/one.json"
check "sweep --out onto a file" 2 "--out $tmp/sweep-out-file: not a directory" -- "$cdbench" sweep "$tmp/one.json" --out "$tmp/sweep-out-file"
if grep -q "filesystem error" "$tmp/out"; then fail "raw filesystem text"; else echo "ok   no raw filesystem text"; fi

# --- sweep --dry-run checks each cell's options as its run will ---
printf '{"scenes": [{"scene": "funnel", "set": {"res": 8, "frames": 3}, "frames": "5:2"}], "pipelines": ["bvh"], "devices": ["cpu"]}' >"$tmp/bad-frames.json"
check "dry run refuses --frames 5:2" 2 "INVALID: --frames '5:2': empty range" -- "$cdbench" sweep "$tmp/bad-frames.json" --out "$tmp/sw" --dry-run
printf '{"scenes": [{"scene": "funnel", "set": {"res": 8, "frames": 3}}], "pipelines": ["bvh"], "devices": ["cpu"], "options": {"box-margin": [-1, 0]}}' >"$tmp/bad-margin.json"
check "dry run refuses --box-margin -1" 2 "box-margin=-1  INVALID: --box-margin: expected a finite number >= 0, not '-1'" -- \
  "$cdbench" sweep "$tmp/bad-margin.json" --out "$tmp/sw" --dry-run
has "the valid cell is still listed to run" "$tmp/out" "box-margin=0  to run$"
has "the count says which are invalid" "$tmp/out" "2 cells, 0 complete, 1 to run, 1 invalid"
check "a sweep with an invalid cell runs nothing" 2 "cell .*box-margin=-1: --box-margin: expected a finite number >= 0, not '-1'" -- \
  "$cdbench" sweep "$tmp/bad-margin.json" --out "$tmp/sw"
[[ -e $tmp/sw ]] && fail "the refused sweep made its output directory" || echo "ok   nothing written for the refused sweep"
# A cell's FAILED reason is its error, not CLI11's pointer to --help.
mkdir -p "$tmp/cells"
printf '{"cell": "c1", "scene": "funnel", "pipeline": "c", "device": "cpu", "state": "failed", "exit_code": 2, "log_tail": "--warmup: bad value\\nRun with --help for more information.\\n"}' >"$tmp/cells/c1.status.json"
check "report shows the cell's own error" 1 "c1\.h5 .*failed, no results file: exit 2: --warmup: bad value \|$" -- "$cdbench" report "$tmp/cells"

# --- a reader stopped (Ctrl-Z, SIGSTOP) longer than the damaged-file guard's budget ---
# The guard counts CPU time: the stopped seconds do not make a good file "damaged".
mkdir -p "$tmp/many"
for i in $(seq 1000); do cp "$d/r.h5" "$tmp/many/r$i.h5"; done
"$cdbench" report --csv "$tmp/many" >"$tmp/many.out" 2>&1 &
pid=$!
sleep 0.3
kill -STOP "$pid"
sleep 11
kill -CONT "$pid"
wait "$pid"; rc=$?
if [[ $rc -eq 0 ]] && ! grep -q "damaged" "$tmp/many.out" && [[ $(grep -c ",complete$" "$tmp/many.out") -eq 1000 ]]; then
  echo "ok   report stopped for 11 s reads every file"
else
  fail "report stopped for 11 s: rc=$rc"; grep -m3 -v ",complete$" "$tmp/many.out"
fi

# --- report: exit codes, and a link loop beside valid files ---
mkdir -p "$tmp/empty-results"
check "report on an empty directory" 1 "no results files \(.h5\) or sweep cells under $tmp/empty-results" -- "$cdbench" report "$tmp/empty-results"
check "report on a path that is not there" 2 "$tmp/nothing-here: no such file or directory" -- "$cdbench" report "$tmp/nothing-here"
mkdir -p "$tmp/looped"
cp "$d/r.h5" "$tmp/looped/r.h5"
ln -s self "$tmp/looped/self"
check "report beside a link loop reports the valid file" 1 "^\| $tmp/looped/r.h5 \| funnel\[res=16\] .*\| complete \|$" -- "$cdbench" report "$tmp/looped"
has "and names the entry skipped and why" "$tmp/out" "cdbench: report: skipped $tmp/looped/self: its symbolic links form a loop"

# --- results files cut short or damaged: named, said so, and what to do; not HDF5's text ---
mkdir -p "$tmp/cut"
head -c 100 "$tmp/looped/r.h5" >"$tmp/cut/r100.h5"
head -c 20000 "$tmp/looped/r.h5" >"$tmp/cut/r20000.h5"
damaged="the results file is truncated or damaged and cannot be read \\(HDF5: .*\\); write it again"
for f in r100 r20000; do
  check "report on a file cut to ${f#r} bytes" 1 "\\| unreadable: $tmp/cut/$f.h5: $damaged" -- "$cdbench" report "$tmp/cut/$f.h5"
  check "compare on a file cut to ${f#r} bytes" 1 "^cdbench: error: $tmp/cut/$f.h5: $damaged" -- \
    "$cdbench" compare "$tmp/cut/$f.h5" "$tmp/looped/r.h5"
  check "--front-cycle on a file cut to ${f#r} bytes" 2 "^cdbench: error: --front-cycle: $tmp/cut/$f.h5: $damaged" -- \
    "$cdbench" run --device cpu --quiet --scene funnel --set res=16 --frames 0:2 --front-cycle "$tmp/cut/$f.h5"
done

[[ $skipped -ne 0 ]] && echo "$skipped check(s) skipped (reasons above)"
finish reliability
