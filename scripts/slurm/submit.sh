#!/usr/bin/env bash
# Submits a planemap study to a Slurm cluster: its shards as a job array (study_array.sbatch, one
# task per shard) and the collect job (study_collect.sbatch), which Slurm starts once every task
# has succeeded. Set the variables below (or export them), then, from the folder the relative
# paths start in:
#   bash scripts/slurm/submit.sh
# It prints the two job ids. Watch them with `squeue -u $USER`; their output is in OUT/logs/.
# A shard that failed or ran out of time: submit it again (sbatch --array=K ..., or this script
# with the same settings: finished shards finish at once) and collect. docs/cluster.md has the sizes.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

# --- what a user sets ----------------------------------------------------------------------------
STUDY=${STUDY:-configs/studies/default.yaml}  # the study file
OUT=${OUT:-out/study_cluster}                 # the study folder, on a file system every node sees
PLANEMAP=${PLANEMAP:-build/apps/planemap}     # the planemap tool, as every node reaches it
SHARDS=${SHARDS:-4}                           # array tasks, one shard of the runs each
CPUS=${CPUS:-32}                              # CPUs per task: one run on each, side by side
TIME=${TIME:-02:00:00}                        # a shard's time limit
MEM_PER_CPU=${MEM_PER_CPU:-512M}              # memory per CPU (a run takes 20-40 MB beside the tool's 150 MB); empty: the cluster's default
PARTITION=${PARTITION:-}                      # empty: the cluster's default partition
REPORT=${REPORT:-}                            # the study as an HTML page, written by the collect job; empty: none
SBATCH_ARGS=${SBATCH_ARGS:-}                  # more sbatch options for both jobs, e.g. "--account=myproject"
# ---------------------------------------------------------------------------------------------------

# The jobs may start in another folder: absolute paths. A study file named configs/... that is
# not here is left as it is (planemap finds it in its own configs), and so is a tool on the PATH.
absolute() { case "$1" in /*) echo "$1" ;; *) if [ -e "$1" ]; then echo "$PWD/$1"; else echo "$1"; fi ;; esac; }
STUDY=$(absolute "$STUDY")
case "$OUT" in /*) ;; *) OUT="$PWD/$OUT" ;; esac
case "$PLANEMAP" in */*) PLANEMAP=$(absolute "$PLANEMAP") ;; esac
[ -n "$REPORT" ] && case "$REPORT" in /*) ;; *) REPORT="$PWD/$REPORT" ;; esac
command -v sbatch >/dev/null || { echo "submit.sh: no sbatch here: submit from a machine of the Slurm cluster" >&2; exit 1; }
command -v "$PLANEMAP" >/dev/null || { echo "submit.sh: PLANEMAP=$PLANEMAP is no program" >&2; exit 1; }
[[ "$SHARDS" =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: SHARDS=$SHARDS: a number of shards, 1 or more" >&2; exit 1; }
mkdir -p "$OUT/logs"  # Slurm writes no output into a folder that is not there
export STUDY OUT PLANEMAP SHARDS REPORT  # the jobs get the submitting shell's environment

common=(--parsable)
[ -n "$PARTITION" ] && common+=(--partition="$PARTITION")
[ -n "$MEM_PER_CPU" ] && common+=(--mem-per-cpu="$MEM_PER_CPU")
# shellcheck disable=SC2206  # SBATCH_ARGS is split into options on purpose
common+=($SBATCH_ARGS)
array=$(sbatch "${common[@]}" --array="1-$SHARDS" --cpus-per-task="$CPUS" --time="$TIME" \
  --output="$OUT/logs/shard-%a-of-$SHARDS.%A.out" "$here/study_array.sbatch")
array=${array%%;*}  # "id;cluster" on a federation
# afterok on an array job waits for every task; a task that fails cancels the collect job
# (--kill-on-invalid-dep) instead of leaving it pending for ever.
collect=$(sbatch "${common[@]}" --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$OUT/logs/collect.%j.out" "$here/study_collect.sbatch")
collect=${collect%%;*}
echo "submit.sh: $STUDY in $SHARDS shards of $CPUS CPUs: array job $array, then collect job $collect; into $OUT"
echo "$array $collect"
