#!/usr/bin/env bash
# `sweep --slurm` on a real Slurm: a one-node cluster of Debian's slurmctld, slurmd and munge,
# started as this test's own processes (key, sockets, state, spool and logs under its
# temporary directory; non-default ports), runs the script of a small CPU sweep with sbatch.
# Every good cell completes, a cell with a missing scene is recorded as failed, `report`
# reads the directory, and a second script after one result is removed holds exactly the
# cells not complete. When the packages cannot be installed or the daemons cannot start,
# the test fails with their logs; it does not skip.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

if ! bash "$root/scripts/install-deps.sh" --slurm; then
  echo "FAIL cannot install slurmctld, slurmd and munge (scripts/install-deps.sh --slurm; needs root or sudo)"
  exit 1
fi

cluster=$tmp/cluster
mkdir -p "$cluster"/{munge,state,spool,log}
# munged refuses a socket in a directory others cannot enter.
chmod 755 "$tmp" "$cluster" "$cluster/munge"
export SLURM_CONF=$cluster/slurm.conf
started=()  # pid files of the daemons started, stopped in reverse order on exit

stop_cluster() {
  local i pidfile pid
  for ((i = ${#started[@]} - 1; i >= 0; i--)); do
    pidfile=${started[i]}
    pid=$(cat "$pidfile" 2>/dev/null) || continue
    kill "$pid" 2>/dev/null || continue
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$pid" 2>/dev/null && kill -KILL "$pid"
  done
}
trap 'stop_cluster; rm -rf "$tmp"' EXIT

# Fails the whole test: the rest needs a running cluster.
cluster_broken() {
  echo "FAIL $1"
  for log in "$cluster"/munge/munged.log "$cluster"/log/*.log; do
    [[ -f $log ]] && { echo "---- $log"; tail -30 "$log"; }
  done
  exit 1
}

# Two free TCP ports for slurmctld and slurmd, so a site's own Slurm on 6817/6818 is left alone.
read -r ctld_port slurmd_port < <(/usr/bin/python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*(x.getsockname()[1] for x in s))')

mungekey --create --keyfile="$cluster/munge/munge.key" || cluster_broken "mungekey could not create a key"
munged --key-file="$cluster/munge/munge.key" --socket="$cluster/munge/socket" \
  --pid-file="$cluster/munge/munged.pid" --log-file="$cluster/munge/munged.log" \
  --seed-file="$cluster/munge/munged.seed" || cluster_broken "munged did not start"
started+=("$cluster/munge/munged.pid")

host=$(hostname -s)
# The node as slurmd sees this machine (CPUs, sockets, cores, memory), without a GPU.
node=$(slurmd -C | head -1)
[[ $node == NodeName=$host\ * ]] || cluster_broken "slurmd -C printed '$node', not a NodeName=$host line"
cat >"$SLURM_CONF" <<CONF
ClusterName=cdbench-test
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$(id -un)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$cluster/munge/socket
CredType=cred/munge
StateSaveLocation=$cluster/state
SlurmdSpoolDir=$cluster/spool
SlurmctldPidFile=$cluster/slurmctld.pid
SlurmdPidFile=$cluster/slurmd.pid
SlurmctldLogFile=$cluster/log/slurmctld.log
SlurmdLogFile=$cluster/log/slurmd.log
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
ReturnToService=2
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=cdbtest Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF

slurmctld -f "$SLURM_CONF" || cluster_broken "slurmctld did not start"
started+=("$cluster/slurmctld.pid")
slurmd -f "$SLURM_CONF" -N "$host" || cluster_broken "slurmd did not start"
started+=("$cluster/slurmd.pid")
state=
for _ in $(seq 60); do
  state=$(sinfo -h -n "$host" -o %t 2>/dev/null)
  [[ $state == idle ]] && break
  sleep 0.5
done
[[ $state == idle ]] || cluster_broken "node $host is '$state' after 30 s, not idle"
echo "ok   one-node cluster up: $node"

# wait_for_job ID: until squeue no longer lists it (at most two minutes).
wait_for_job() {
  local left
  for _ in $(seq 240); do
    left=$(squeue -h -j "$1" 2>/dev/null)
    [[ -z $left ]] && return 0
    sleep 0.5
  done
  cluster_broken "job $1 still queued after two minutes: $(squeue)"
}

# Three cells that run in seconds on the CPU, and one whose scene does not exist.
cat >"$tmp/small.json" <<'JSON'
{"scenes": [{"scene": "funnel", "set": {"res": 24, "frames": 3}}, "nowhere/"],
 "pipelines": ["bvh", "b", "sweep"], "devices": ["cpu"]}
JSON
out=$tmp/results
check "script written" 0 "wrote .*: 6 array tasks \(0 cells already complete\)" -- \
  "$cdbench" sweep "$tmp/small.json" --out "$out" --slurm "$tmp/jobs/one.sbatch" \
  --time 5 --cpus-per-task 1 --partition cdbtest --throttle 2
[[ -d $out/logs ]] && echo "ok   log directory exists before sbatch" || fail "no $out/logs after writing the script"
check "report shows the pending cells" 0 "funnel\.frames=3\.res=24_b_cpu\.h5 \| funnel.* \| pending \(task 1 of $tmp/jobs/one.sbatch\) \|$" -- \
  "$cdbench" report "$out"

job=$(sbatch --parsable "$tmp/jobs/one.sbatch") || cluster_broken "sbatch refused the script"
echo "ok   submitted array job $job"
wait_for_job "$job"
n=$(ls "$out"/logs/slurm-"${job}"_*.out 2>/dev/null | wc -l)
[[ $n -eq 6 ]] && echo "ok   six array tasks ran" || fail "$n Slurm output files for job $job (want 6)"
for p in bvh b sweep; do
  has "$p cell complete" "$out/funnel.frames=3.res=24_${p}_cpu.status.json" "\"state\": \"complete\""
  has "$p cell ran under Slurm" "$out/funnel.frames=3.res=24_${p}_cpu.status.json" "\"job\": \"slurm job ${job}_[0-9]\""
done
has "missing scene recorded failed" "$out/nowhere_b_cpu.status.json" '"state": "failed", "exit_code": 2'
check "report reads the directory, exit 1 for the failed cells" 1 "funnel\.frames=3\.res=24_sweep_cpu\.h5 \| funnel.* \| sweep \| cpu.* \| complete \|$" -- \
  "$cdbench" report "$out"
n=$(grep -cE "\| complete \|$" "$tmp/out")
[[ $n -eq 3 ]] && echo "ok   report has three complete cells" || fail "report has $n complete cells (want 3)"
n=$(grep -cE "nowhere_(bvh|b|sweep)_cpu\.h5 .*\| failed, no results file: exit 2: " "$tmp/out")
[[ $n -eq 3 ]] && echo "ok   report has three failed cells" || fail "report has $n failed cells (want 3)"

# Resubmission: the b cell's results are gone, so it and the failed cells are the array.
rm "$out/funnel.frames=3.res=24_b_cpu.h5"
check "second script holds the incomplete cells" 0 "wrote .*: 4 array tasks \(2 cells already complete\)" -- \
  "$cdbench" sweep "$tmp/small.json" --out "$out" --slurm "$tmp/jobs/two.sbatch" --time 5 --cpus-per-task 1
cells=$(grep -oE "^  [0-9]+\) cell=.*" "$tmp/jobs/two.sbatch" | sed 's/.*cell=//' | LC_ALL=C sort | tr '\n' ' ')
want="funnel.frames=3.res=24_b_cpu nowhere_b_cpu nowhere_bvh_cpu nowhere_sweep_cpu "
[[ $cells == "$want" ]] && echo "ok   second array: the removed cell and the failed ones" || fail "second array holds '$cells' (want '$want')"
has "second array is four tasks" "$tmp/jobs/two.sbatch" "^#SBATCH --array=0-3$"
job2=$(sbatch --parsable "$tmp/jobs/two.sbatch") || cluster_broken "sbatch refused the second script"
wait_for_job "$job2"
has "removed cell complete again" "$out/funnel.frames=3.res=24_b_cpu.status.json" "\"state\": \"complete\".*\"job\": \"slurm job ${job2}_"
has "complete cells not run again" "$out/funnel.frames=3.res=24_bvh_cpu.status.json" "\"job\": \"slurm job ${job}_"
check "report after resubmission: exit 1 for the failed cells left" 1 "funnel\.frames=3\.res=24_b_cpu\.h5 \| funnel.* \| complete \|$" -- "$cdbench" report "$out"
n=$(grep -cE "\| complete \|$" "$tmp/out")
[[ $n -eq 3 ]] && echo "ok   three complete cells after resubmission" || fail "report has $n complete cells (want 3)"

finish slurm
