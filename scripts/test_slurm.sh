#!/usr/bin/env bash
# A study on a real Slurm (issue 59): a one-node cluster on this machine (munged, slurmctld and
# slurmd started here on localhost with their own key, sockets, ports and state in a temporary
# folder, stopped at the end whatever happens), a 4-shard study submitted by
# scripts/slurm/submit.sh as a job array and a collect job, waited for, and its files compared
# byte for byte with the same study run whole, without Slurm.
#   scripts/test_slurm.sh [BUILD_DIR | PLANEMAP_BINARY]     default: build
# Needs root (slurmd runs jobs as their users) and Debian's slurm-wlm and munge (scripts/setup.sh).
# Without them it is skipped (exit 77), unless PLANEMAP_REQUIRE_SLURM=1 (CI): then it fails.
# About a minute on 2 cores; ctest runs it as Slurm.StudyOnAJobArray.
set -euo pipefail
cd "$(dirname "$0")/.."
source_dir=$PWD
planemap=${1:-build}
[ -d "$planemap" ] && planemap=$planemap/apps/planemap
planemap=$(cd "$(dirname "$planemap")" && pwd)/$(basename "$planemap")
start=$SECONDS

skip() {
  if [ "${PLANEMAP_REQUIRE_SLURM:-0}" = 1 ]; then
    echo "test_slurm: $1 (PLANEMAP_REQUIRE_SLURM=1: a failure)" >&2
    exit 1
  fi
  echo "test_slurm: skipped: $1" >&2
  exit 77
}
fail() {
  echo "test_slurm: FAILED: $1" >&2
  exit 1
}
[ -x "$planemap" ] || fail "no planemap tool at $planemap"
for tool in munged slurmctld slurmd sbatch squeue sinfo scontrol scancel; do
  command -v "$tool" >/dev/null || skip "no $tool: install slurm-wlm and munge (scripts/setup.sh)"
done
[ "$(id -u)" = 0 ] || skip "slurmd must run as root"

dir=$(mktemp -d /tmp/planemap_slurm.XXXXXX)
chmod 755 "$dir"  # the job steps read the config and reach munged's socket
pids=()
jobs_submitted=()
cleanup() {
  local status=$?
  # This cluster's jobs first (a timeout leaves them running), then the daemons this script started.
  if [ ${#jobs_submitted[@]} -gt 0 ]; then SLURM_CONF=$dir/slurm.conf scancel --quiet "${jobs_submitted[@]}" 2>/dev/null || true; fi
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill "${pids[i]}" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  if [ $status != 0 ] && [ $status != 77 ]; then
    for log in "$dir"/slurmctld.log "$dir"/slurmd.log "$dir"/out/logs/*; do
      if [ -f "$log" ]; then echo "--- $log (last lines)"; tail -n 15 "$log"; fi
    done
  fi
  rm -rf "$dir"
  exit $status
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# A TCP port nobody listens on, from a range Slurm and most services leave alone.
free_port() {
  local port
  for _ in $(seq 50); do
    port=$((20000 + RANDOM % 20000))
    (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null || { echo "$port"; return; }
  done
  fail "no free TCP port for Slurm"
}

# 1. munged with a key of its own, on a socket of its own.
head -c 1024 /dev/urandom >"$dir/munge.key"
chmod 400 "$dir/munge.key"
munged --foreground --force --key-file="$dir/munge.key" --socket="$dir/munge.socket" --pid-file="$dir/munged.pid" \
  --log-file="$dir/munged.log" --seed-file="$dir/munged.seed" 2>>"$dir/munged.log" &
pids+=($!)
for _ in $(seq 50); do [ -S "$dir/munge.socket" ] && break; sleep 0.1; done
[ -S "$dir/munge.socket" ] || fail "munged did not start: $(tail -n 3 "$dir/munged.log")"

# 2. The cluster: this machine as its one node, every CPU it has, no cgroups (a container has
# none to give), no accounting database.
host=$(hostname -s)
ctld_port=$(free_port)
slurmd_port=$(free_port)
[ "$ctld_port" != "$slurmd_port" ] || slurmd_port=$((ctld_port + 1))
cpus=$(nproc)
memory_mb=$(($(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024))
mkdir -p "$dir/state" "$dir/spool"
cat >"$dir/slurm.conf" <<CONF
ClusterName=planemaptest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$dir/munge.socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
MailProg=/bin/true
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=600
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory_mb State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$dir/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" >>"$dir/slurmctld.log" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >>"$dir/slurmd.log" 2>&1 &
pids+=($!)
state=""
for _ in $(seq 60); do
  state=$(sinfo -h -N -o %t 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.5
done
[ "$state" = idle ] || fail "the node did not come up idle within 30 s (sinfo: '${state}')"
echo "test_slurm: one-node cluster up ($host, $cpus CPUs) after $((SECONDS - start)) s"

# 3. A small study: 8 runs of 3 frames (2 distances x 2 noise levels x 2 seeds), with the back end.
cat >"$dir/study.yaml" <<STUDY
name: slurm_test
frames: 3
seeds: 2
sweep:
  distance: [1.5, 2.0]
  noise: [1.0, 2.0]
  segmenter: [organized]
STUDY

# 4. Submitted as a user would, with the settings the script reads; one CPU per shard, so the
# 4 shards share the node's CPUs and queue for them.
ids=$(STUDY="$dir/study.yaml" OUT="$dir/out" PLANEMAP="$planemap" SHARDS=4 CPUS=1 TIME=00:10:00 MEM_PER_CPU=500M \
  bash "$source_dir/scripts/slurm/submit.sh" | tail -n 1)
read -r array collect <<<"$ids"
[[ "$array" =~ ^[0-9]+$ && "$collect" =~ ^[0-9]+$ ]] || fail "submit.sh printed no job ids: '$ids'"
jobs_submitted=("$array" "$collect")
echo "test_slurm: submitted array job $array (4 shards) and collect job $collect"

# 5. Meanwhile the same study run whole on this machine (one thread: the jobs have the others).
"$planemap" study "$dir/study.yaml" --out "$dir/whole" --threads 1 >"$dir/whole.log" 2>&1 || fail "the whole run: $(tail -n 3 "$dir/whole.log")"

# 6. Wait for both jobs to leave the queue (at most 5 minutes), then ask how they ended.
queued() { squeue -h -j "$array,$collect" -o %i 2>/dev/null; }
for _ in $(seq 300); do
  [ -z "$(queued)" ] && break
  sleep 1
done
[ -z "$(queued)" ] || fail "the jobs were still queued or running after 5 minutes: $(squeue -h -o '%i %T %R')"
echo "test_slurm: jobs done after $((SECONDS - start)) s"
# How each job (each array task, and the collect job) ended: "1_3 FAILED 3:0", ...
ended() {
  scontrol -o show job "$1" 2>/dev/null | awk '{
    delete f; for (i = 1; i <= NF; i++) { n = index($i, "="); if (n) f[substr($i, 1, n - 1)] = substr($i, n + 1) }
    print (f["ArrayTaskId"] != "" ? f["ArrayJobId"] "_" f["ArrayTaskId"] : f["JobId"]), f["JobState"], f["ExitCode"] }'
}
states="$(ended "$array" | tr '\n' ',') $(ended "$collect")"
[ "$(ended "$array" | grep -c ' COMPLETED ')" = 4 ] || fail "not every shard completed: $states"
ended "$collect" | grep -q ' COMPLETED ' || fail "the collect job did not complete: $states"
echo "test_slurm: $states"
for k in 1 2 3 4; do
  [ "$(($(wc -l <"$dir/out/shards/$k-of-4/runs.csv") - 1))" = 4 ] || fail "shard $k/4 holds no 2 runs (4 rows)"
done

# 7. The collected study is the whole one, byte for byte.
compared=0
for file in "$dir"/whole/*; do
  name=$(basename "$file")
  cmp -s "$file" "$dir/out/$name" || fail "$name of the collected study differs from the whole run's"
  compared=$((compared + 1))
done
[ "$compared" -ge 9 ] || fail "only $compared files in the whole run's folder"
[ "$(find "$dir/out" -maxdepth 1 -type f | wc -l)" = "$compared" ] || fail "the collected folder holds other files"
echo "test_slurm: passed: 4 shards on Slurm collected into the whole study's $compared files, byte for byte ($((SECONDS - start)) s)"
