#!/usr/bin/env bash
# cdbench sweep: expansion, one process per cell, resuming, failed cells, Slurm script, and
# report over a directory. Runs sweeps/ci-small.json (2 tiny scenes x 3 pipelines on the CPU).
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
count() {  # count NAME WANT PATTERN: lines of the last output matching PATTERN
  local n; n=$(grep -cE -- "$3" "$tmp/out")
  if [[ $n -ne $2 ]]; then
    fail "$1: $n lines match '$3' (want $2)"; sed 's/^/    /' "$tmp/out" | tail -20
  else
    echo "ok   $1"
  fi
}

sweep=$root/sweeps/ci-small.json
out=$tmp/results
check "dry run lists the cells" 0 "6 cells, 0 complete, 6 to run" -- "$cdbench" sweep "$sweep" --out "$out" --dry-run
count "dry run names every cell" 6 "^ +[0-9]+  (funnel|cloth-wave)\.frames=3\.res=[0-9]+_(bvh|b|sweep)_cpu  to run"
count "dry run shows the run lines" 6 "^ +cdbench run --scene .* --out $out/.*\.h5 --quiet"
[[ -e $out ]] && fail "dry run wrote $out"

check "sweep runs every cell" 0 "6 run, 6 complete, 0 failed" -- "$cdbench" sweep "$sweep" --out "$out"
n=$(ls "$out"/*.h5 | wc -l)
[[ $n -eq 6 ]] && echo "ok   six results files" || fail "$n results files (want 6)"
check "report over the directory, scenes by their labels" 0 "\| funnel\\[frames=3,res=24\\] \\| sweep \\| cpu" -- "$cdbench" report "$out"
count "report has six complete rows" 6 "\.h5 \| .* \| complete \|$"
check "second sweep skips complete cells" 0 "6 already complete, 0 to run" -- "$cdbench" sweep "$sweep" --out "$out"
count "each skip is said" 6 "^skip .*: results complete"

# Failing cells next to the complete ones: a scene whose frame 2 has a NaN (found before
# any frame runs) and a scene that does not exist; neither leaves a results file.
mkdir -p "$tmp/midway"
for f in 0 1 2 3; do
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 %d\nf 1 2 3\nf 1 2 4\n' "$f" >"$tmp/midway/frame_000$f.obj"
done
printf 'v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n' >"$tmp/midway/frame_0002.obj"
cat >"$tmp/failing.json" <<'JSON'
{"scenes": [{"scene": "funnel", "set": {"res": 24, "frames": 3}}, "midway/", "nowhere/"],
 "pipelines": ["bvh"], "devices": ["cpu"]}
JSON
check "failed cells make the sweep exit 1" 1 "3 cells, 1 already complete, 2 to run" -- "$cdbench" sweep "$tmp/failing.json" --out "$out"
count "the others are reported failed" 2 "^\[[12]/2\] (midway|nowhere)_bvh_cpu: FAILED, exit [12]: cdbench: error: "
check "failure recorded with its exit code" 0 '"exit_code": 2' -- cat "$out/nowhere_bvh_cpu.status.json"
check "sweep.log has the failure" 0 "failed midway_bvh_cpu exit 1: .*non-finite" -- cat "$out/sweep.log"
check "report shows the cell with a bad frame, exit 1" 1 "midway_bvh_cpu\.h5 \| midway \| bvh \| cpu \|.*\| failed, no results file: exit 1: .*frame 2, vertex 2: non-finite" -- "$cdbench" report "$out"
check "report shows the cell without a file" 1 "nowhere_bvh_cpu\.h5 \| nowhere \| bvh \| cpu \|.*\| failed, no results file: exit 2: .*nowhere" -- "$cdbench" report "$out"
count "report still has the six complete rows" 6 "\| complete \|$"
# The dry run opens every cell's scene as run would: the missing scene and the bad frame are
# refused there (the sweep itself ran them, so the other cells ran too).
check "dry run refuses the cells run would stop" 2 "cell nowhere_bvh_cpu: /scenes/2: unknown scene '$tmp/nowhere'" -- \
  "$cdbench" sweep "$tmp/failing.json" --out "$out" --dry-run
has "dry run refuses the cell with a bad frame" "$tmp/out" "midway_bvh_cpu  INVALID: /scenes/1: .*frame 2, vertex 2: non-finite"
mkdir -p "$tmp/nowhere" && cp "$tmp/midway/frame_0000.obj" "$tmp/midway/frame_0001.obj" "$tmp/nowhere/"
printf '{"scenes": ["nowhere/"], "pipelines": ["bvh"], "devices": ["cpu"]}' >"$tmp/found.json"
check "dry run says which cells failed" 0 "nowhere_bvh_cpu  to run again \(failed: exit 2" -- "$cdbench" sweep "$tmp/found.json" --out "$out" --dry-run

# Slurm: one array task per cell; the script itself runs a cell when given a task id.
check "slurm script written" 0 "6 array tasks" -- "$cdbench" sweep "$sweep" --out "$tmp/slurm" --slurm "$tmp/job.sh"
check "slurm script has the array" 0 "^#SBATCH --array=0-5$" -- cat "$tmp/job.sh"
count "slurm script has the run lines" 6 "cmd=\(.*cdbench run --scene .* --out $tmp/slurm/.*\.h5 --quiet\)"
check "slurm script is valid bash" 0 "^ran$" -- bash -c 'bash -n "$1" && echo ran' _ "$tmp/job.sh"
check "slurm task runs its cell" 0 "^ran$" -- bash -c 'SLURM_ARRAY_TASK_ID=4 bash "$1" && echo ran' _ "$tmp/job.sh"
check "slurm task leaves its status" 0 '"state": "complete", "exit_code": 0' -- cat "$tmp/slurm/cloth-wave.frames=3.res=12_b_cpu.status.json"
check "slurm script leaves out complete cells" 0 "5 array tasks \(1 cells already complete\)" -- "$cdbench" sweep "$sweep" --out "$tmp/slurm" --slurm "$tmp/job2.sh"
check "slurm script's defaults" 0 "^#SBATCH --time=1:00:00$" -- cat "$tmp/job.sh"
has "slurm script asks for 4 CPUs" "$tmp/job.sh" "^#SBATCH --cpus-per-task=4$"
has "slurm script runs in the output directory" "$tmp/job.sh" "^#SBATCH --chdir=$tmp/slurm$"
grep -q -- "--gres" "$tmp/job.sh" && fail "slurm script of CPU cells asks for a GPU" || echo "ok   no GPU for CPU cells"
[[ -d $tmp/slurm/logs ]] && echo "ok   slurm log directory exists before sbatch" || fail "no $tmp/slurm/logs"
check "report shows cells pending under the script" 0 "cloth-wave\.frames=3\.res=12_sweep_cpu\.h5 \| .* \| pending \(task 4 of $tmp/job2\.sh\) \|$" -- "$cdbench" report "$tmp/slurm"
check "a second script notes the pending cells" 0 "note: 5 of these cells were pending" -- "$cdbench" sweep "$sweep" --out "$tmp/slurm" --slurm "$tmp/job3.sh"
check "slurm options reach the script" 0 "66 array tasks" -- "$cdbench" sweep "$root/sweeps/paper-fig9.json" --out "$tmp/fig9" \
  --slurm "$tmp/fig9.sh" --time 2-0 --cpus-per-task 8 --partition gpu --account lab --gres gpu:h100:1 --throttle 3
has "slurm array throttle" "$tmp/fig9.sh" "^#SBATCH --array=0-65%3$"
has "slurm time limit" "$tmp/fig9.sh" "^#SBATCH --time=2-0$"
has "slurm CPUs" "$tmp/fig9.sh" "^#SBATCH --cpus-per-task=8$"
has "slurm partition" "$tmp/fig9.sh" "^#SBATCH --partition=gpu$"
has "slurm account" "$tmp/fig9.sh" "^#SBATCH --account=lab$"
has "slurm gres for CUDA cells" "$tmp/fig9.sh" "^#SBATCH --gres=gpu:h100:1$"
has "cells use the CPUs they asked for" "$tmp/fig9.sh" '^export OMP_NUM_THREADS=\$\{SLURM_CPUS_PER_TASK:-8\}$'
"$cdbench" sweep "$root/sweeps/paper-fig9.json" --out "$tmp/fig9" --slurm "$tmp/fig9.sh" --gres none >/dev/null
grep -q -- "--gres" "$tmp/fig9.sh" && fail "--gres none still asks for a GPU" || echo "ok   --gres none"
usage_error() {  # usage_error NAME PATTERN -- CMD...: a non-zero exit naming the problem
  local name=$1 pattern=$2; shift 3
  if "$@" >"$tmp/out" 2>&1 || ! grep -qE -- "$pattern" "$tmp/out"; then
    fail "$name: want an error matching '$pattern'"; sed 's/^/    /' "$tmp/out" | tail -5
  else
    echo "ok   $name"
  fi
}
usage_error "bad time limit refused" "not a Slurm time limit .*: 1h" -- "$cdbench" sweep "$sweep" --out "$tmp/x" --slurm "$tmp/x.sh" --time 1h
usage_error "slurm option without --slurm refused" "--time requires --slurm" -- "$cdbench" sweep "$sweep" --out "$tmp/x" --time 10
usage_error "partition with a space refused" "only letters" -- "$cdbench" sweep "$sweep" --out "$tmp/x" --slurm "$tmp/x.sh" --partition "a b"
[[ -e $tmp/x.sh ]] && fail "a refused option still wrote the script"
for i in 0 1 2 3 4; do SLURM_ARRAY_TASK_ID=$i bash "$tmp/job3.sh" >/dev/null 2>&1; done
check "no script tasks once every cell is complete" 0 "every cell of .* is complete in .*; nothing to submit" -- "$cdbench" sweep "$sweep" --out "$tmp/slurm" --slurm "$tmp/job4.sh"
check "the empty script says so when run" 0 "every cell complete" -- bash "$tmp/job4.sh"

# Option axes and the errors of a sweep file.
printf '{"scenes": ["funnel"], "pipelines": ["a"], "devices": ["cpu"], "options": {"front-cycle": [1, 8], "skip-adjacent": [false, true]}, "repeat": 2}' >"$tmp/axes.json"
check "option axes multiply" 0 "8 cells" -- "$cdbench" sweep "$tmp/axes.json" --out "$tmp/axes" --dry-run
check "axis values name the cell" 0 "funnel_a_cpu_front-cycle=8_skip-adjacent=true_r2  to run" -- "$cdbench" sweep "$tmp/axes.json" --out "$tmp/axes" --dry-run
check "axis values reach the run line" 0 "--front-cycle 8 --skip-adjacent --out" -- "$cdbench" sweep "$tmp/axes.json" --out "$tmp/axes" --dry-run
# An axis a pipeline ignores makes one cell there, not one per value: bvh has no fronts.
printf '{"scenes": ["funnel"], "pipelines": ["bvh", "c"], "devices": ["cpu"], "options": {"front-cycle": [1, 4], "skip-adjacent": [false, true]}}' >"$tmp/ignored.json"
check "cells its pipeline ignores an axis of are merged" 0 "ignored.json: 6 cells, 0 complete, 6 to run" -- "$cdbench" sweep "$tmp/ignored.json" --out "$tmp/ignored" --dry-run
count "bvh runs once per value it acts on" 2 "^ +[0-9]+  funnel_bvh_cpu_skip-adjacent=(false|true)  to run$"
count "c runs every value" 4 "^ +[0-9]+  funnel_c_cpu_front-cycle=[14]_skip-adjacent=(false|true)  to run$"
count "the ignored option is not on bvh's run line" 0 "--pipeline bvh .*--front-cycle"
has "the merge is said once" "$tmp/out" "^sweep .*ignored.json: 2 cells merged into others because their pipeline ignores the option: --front-cycle does not apply to bvh \(front pipelines only\)$"
printf '{"scenes": ["funnel"], "pipelines": ["bvh", "nope"]}' >"$tmp/bad1.json"
check "unknown pipeline names file and field" 2 "bad1.json: /pipelines/1: unknown pipeline 'nope'" -- "$cdbench" sweep "$tmp/bad1.json" --out "$tmp/x"
printf '{"scenes": ["funnel"], "pipelines": ["bvh"], "options": {"colour": 1}}' >"$tmp/bad2.json"
check "unknown option names file and field" 2 "bad2.json: /options/colour: not an option of cdbench run" -- "$cdbench" sweep "$tmp/bad2.json" --out "$tmp/x"
printf '{"scenes": ["funnel"], "pipelines": ["bvh"], "options": {"pipeline": "b"}}' >"$tmp/bad3.json"
check "sweep-owned option refused" 2 "bad3.json: /options/pipeline: set by the sweep itself" -- "$cdbench" sweep "$tmp/bad3.json" --out "$tmp/x"
printf '{"scenes": ["funnel", {"scene": "funnel"}], "pipelines": ["bvh"]}' >"$tmp/bad4.json"
check "duplicate cell names refused" 2 "bad4.json: cells 0 and 1 are both named 'funnel_bvh_cuda'" -- "$cdbench" sweep "$tmp/bad4.json" --out "$tmp/x"
printf '{"scenes": ["funnel"], "pipeline": ["bvh"]}' >"$tmp/bad5.json"
check "unknown key" 2 "bad5.json: /pipeline: unknown key" -- "$cdbench" sweep "$tmp/bad5.json" --out "$tmp/x"
printf '{"scenes": ["funnel"], "pipelines": ["bvh"], "options": {"help": true}}' >"$tmp/bad6.json"
check "help as a cell option refused" 2 "bad6.json: /options/help: prints run's help instead of running a cell" -- \
  "$cdbench" sweep "$tmp/bad6.json" --out "$tmp/x" --dry-run
# Cells counted from the axes before any is made: 10^6 and 10^9 are refused at once (the
# timeout only bounds a build that would expand them), 10,000 are accepted (refused later,
# by the unwritable --out, so none runs).
axis() {  # axis N: the JSON list 1..N
  seq -s, 1 "$1" | sed 's/^/[/; s/$/]/'
}
printf '{"scenes": ["funnel"], "pipelines": ["bvh"], "devices": ["cpu"], "options": {"rebuild-every": %s, "refit-every": %s}}' \
  "$(axis 1000)" "$(axis 1000)" >"$tmp/million.json"
check "a million cells refused" 2 "million.json: 1 scenes x 1 pipelines x 1 devices x 1000 /options/rebuild-every values x 1000 /options/refit-every values x 1 repeats make more than 10000 cells" -- \
  timeout 60 "$cdbench" sweep "$tmp/million.json" --out "$tmp/x" --dry-run
printf '{"scenes": ["funnel"], "pipelines": ["bvh"], "devices": ["cpu"], "options": {"rebuild-every": %s, "refit-every": %s, "warmup-ms": %s}}' \
  "$(axis 1000)" "$(axis 1000)" "$(axis 1000)" >"$tmp/billion.json"
check "a billion cells refused" 2 "billion.json: .* make more than 10000 cells, the most a sweep may have" -- \
  timeout 60 "$cdbench" sweep "$tmp/billion.json" --out "$tmp/x"
printf '{"scenes": ["funnel"], "pipelines": ["bvh"], "devices": ["cpu"], "options": {"rebuild-every": %s}, "repeat": 4294967297}' \
  "$(axis 2)" >"$tmp/repeats.json"
check "a repeat past 32 bits counted whole" 2 "repeats.json: .* x 4294967297 repeats make more than 10000 cells" -- \
  timeout 60 "$cdbench" sweep "$tmp/repeats.json" --out "$tmp/x" --dry-run
printf '{"scenes": ["funnel"], "pipelines": ["bvh"], "devices": ["cpu"], "options": {"rebuild-every": %s, "refit-every": %s}}' \
  "$(axis 100)" "$(axis 101)" >"$tmp/over.json"
check "10,100 cells refused" 2 "over.json: .* make more than 10000 cells" -- "$cdbench" sweep "$tmp/over.json" --out "$tmp/x" --dry-run
printf '{"scenes": ["funnel"], "pipelines": ["bvh"], "devices": ["cpu"], "options": {"rebuild-every": %s, "refit-every": %s}}' \
  "$(axis 100)" "$(axis 100)" >"$tmp/limit.json"
check "10,000 cells accepted" 2 "^cdbench: error: --out /proc/cdbench-sweep: cannot write in /proc" -- \
  timeout 60 "$cdbench" sweep "$tmp/limit.json" --out /proc/cdbench-sweep --dry-run

# A status file whose value has another type than the sweep writes: the file and key named.
cp -r "$out" "$tmp/badstatus"
sed -i 's/"state": "[a-z]*"/"state": 5/' "$tmp/badstatus/nowhere_bvh_cpu.status.json"
check "a status value of the wrong type names the file and key" 1 \
  "badstatus/nowhere_bvh_cpu.status.json: \"state\" is 5 \\(a number\\), not a string" -- "$cdbench" report "$tmp/badstatus"
check "and the sweep names them too" 1 "badstatus/nowhere_bvh_cpu.status.json: \"state\" is 5" -- \
  "$cdbench" sweep "$tmp/failing.json" --out "$tmp/badstatus" --dry-run

check "committed paper sweep expands" 0 "paper-fig9.json: 66 cells" -- "$cdbench" sweep "$root/sweeps/paper-fig9.json" --out "$tmp/fig9" --dry-run
# A dry run refuses what run would stop a cell for once it opens the scene, and an --out
# where nothing can be written; a cuda cell without a GPU is only a warning.
printf '{"scenes": ["no-such-scene", "/nonexistent/dir/", {"scene": "funnel", "set": {"res": 8}, "frames": "0:50"}, {"scene": "funnel", "set": {"res": 8}, "frames": "0:2", "label": "fine"}], "pipelines": ["bvh"], "devices": ["cpu"]}' >"$tmp/scenes.json"
check "dry run refuses an unknown scene" 2 "^cdbench: error: $tmp/scenes.json: cell no-such-scene_bvh_cpu: /scenes/0: unknown scene 'no-such-scene'" -- \
  "$cdbench" sweep "$tmp/scenes.json" --out "$tmp/sw" --dry-run
has "dry run refuses a missing scene directory" "$tmp/out" "cell dir_bvh_cpu: /scenes/1: unknown scene '/nonexistent/dir'"
has "dry run refuses frames past the scene's end" "$tmp/out" "cell funnel\.res=8_bvh_cpu: /scenes/2: --frames '0:50': the scene has only 20 frames"
has "dry run lists the valid cell" "$tmp/out" "^ +3  fine_bvh_cpu  to run$"
has "dry run counts the refused cells" "$tmp/out" "1 to run, 3 invalid"
check "dry run refuses an --out where nothing can be written" 2 "^cdbench: error: --out /proc/cdbench-sweep: cannot write in /proc" -- \
  "$cdbench" sweep "$sweep" --out /proc/cdbench-sweep --dry-run
check "sweep refuses it too" 2 "^cdbench: error: --out /proc/cdbench-sweep: cannot write in /proc" -- \
  "$cdbench" sweep "$sweep" --out /proc/cdbench-sweep
for file in "$root"/sweeps/*.json; do
  check "committed $(basename "$file") dry-runs here" 0 "cells, 0 complete" -- "$cdbench" sweep "$file" --out "$tmp/committed" --dry-run
  if grep -qE "_cuda(_[^ ]*)?  to run" "$tmp/out" && "$cdbench" --version | grep -qE "^cuda +none"; then
    has "  and warns of its cuda cells without a GPU" "$tmp/out" "^warning: .*cells run on cuda and this machine has no CUDA device"
  fi
done
check "run takes --set" 0 "frames 0:2" -- "$cdbench" run --device cpu --quiet --scene funnel --set res=12 --set frames=2

finish sweep
