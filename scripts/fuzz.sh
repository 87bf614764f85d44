#!/usr/bin/env bash
# Builds the libFuzzer targets of the file readers (fuzz/; clang, ASan + UBSan) in build-fuzz/ and
# runs each one; docs/fuzzing.md says what each drives and what they have run.
#   scripts/fuzz.sh SECONDS            every target for SECONDS
#   scripts/fuzz.sh --runs N           every target for N inputs
#   options before those: --jobs J    J targets at a time (default 1: one core)
#                         --only A,B  only these targets, in this order (names: fuzz/CMakeLists.txt)
# PLANEMAP_FUZZ_BUILD=DIR builds and runs in DIR instead of build-fuzz/ (a second corpus).
# Exits non-zero when a target crashed (a sanitizer report, an uncaught exception, an error message
# that does not name the file), hung (over 10 s on one input), leaked, or went over 2 GB on one
# input; the input is in build-fuzz/findings/<target>/, the log in build-fuzz/logs/<target>.log.
# The corpus of each target grows in build-fuzz/corpus/<target>/, seeded on every run
# (fuzz/make_seeds.py: configs/, ../shared/data, fuzz/seeds/).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=1
only=""
mode=""
while (($# > 0)); do
  case "$1" in
    --jobs) jobs=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    --runs) mode="-runs=$2"; shift 2 ;;
    *) mode="-max_total_time=$1"; shift ;;
  esac
done
[ -n "$mode" ] || { echo "usage: scripts/fuzz.sh [--jobs J] [--only A,B] SECONDS | --runs N" >&2; exit 2; }

bash scripts/setup.sh
build=${PLANEMAP_FUZZ_BUILD:-build-fuzz}  # another folder for a second, separate corpus
build_start=$SECONDS
# -O1 as libFuzzer's documentation advises; line tables only (-g1): reports keep file and line.
CC=clang-14 CXX=clang++-14 cmake -S . -B "$build" -G Ninja -DPLANEMAP_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" -DPLANEMAP_BUILD_PYTHON=OFF -DPLANEMAP_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)"
echo "fuzz: build took $((SECONDS - build_start)) s"

read -r -a targets < <(tr ";" " " <"$build/fuzz_targets.txt") || true
if [ -n "$only" ]; then IFS=, read -r -a targets <<<"$only"; fi
rm -rf "$build/seeds" "$build/results"
/usr/bin/python3 fuzz/make_seeds.py "$build/seeds" ../shared/data
mkdir -p "$build/logs" "$build/results"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:symbolize=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0

# One target: its corpus, the seeds, the limits; one result line "target inputs exec/s cov seconds result".
run_target() {
  local t=$1 log=$build/logs/$1.log corpus=$build/corpus/$1 start=$SECONDS status=0
  mkdir -p "$corpus" "$build/findings/$t"
  "$build/fuzz/fuzz_$t" "$mode" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 -print_final_stats=1 \
    -close_fd_mask=1 -artifact_prefix="$build/findings/$t/" "$corpus" "$build/seeds/$t" >"$log" 2>&1 || status=$?
  local result=ok
  if ((status != 0)); then
    result=crash
    grep -q "ERROR: libFuzzer: timeout" "$log" && result=hang
    grep -q "ERROR: LeakSanitizer" "$log" && result=leak
    grep -qE "ERROR: libFuzzer: (out-of-memory|malloc limit)" "$log" && result=out-of-memory
  fi
  local inputs execs cov
  inputs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  [ -n "$inputs" ] || inputs=$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#')
  execs=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  cov=$(grep -oE ' cov: [0-9]+' "$log" | tail -1 | tr -dc '0-9')
  echo "$t ${inputs:-0} ${execs:--} ${cov:--} $((SECONDS - start)) $result" >"$build/results/$t"
  echo "fuzz: $t: $result (${inputs:-0} inputs in $((SECONDS - start)) s)"
}

for t in "${targets[@]}"; do
  while (($(jobs -rp | wc -l) >= jobs)); do wait -n || true; done
  run_target "$t" &
done
wait

failed=0
{
  echo "target inputs exec/s cov seconds result"
  for t in "${targets[@]}"; do
    cat "$build/results/$t"
  done
} | column -t
for t in "${targets[@]}"; do grep -q " ok$" "$build/results/$t" || failed=1; done
if ((failed)); then
  echo "fuzz: FAILED: the findings are in $build/findings/, the logs in $build/logs/" >&2
  exit 1
fi
