#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite.
#   scripts/test.sh             Release build in build/
#   scripts/test.sh --sanitize  AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --with-browser
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build-asan
  bash scripts/build.sh "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPLANEMAP_SANITIZE=ON -DPLANEMAP_BUILD_BENCH=OFF
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  # The sanitized build runs every test but the longest rendered walks (3-4 min each there), whose
  # code paths the default walk, the single-wall walk and the rendered merge already take, and all
  # but one closed-loop approach run (the dropped-frames run takes the whole loop's paths), nor the
  # report's browser test (another approach run; the page is the same as the release build's).
  exclude='(TrackedWalk|RefinedWalk).*/(storeroom|office)|Approach\.(FeedbackBeats|AnObjectMoved|ScenarioThreeEnds|ABoxNotMapped|PlanesMappedOnce|ABoxHidden|ARobotFacing)|Report\.ApproachPageInBrowser'
else
  build_dir=build
  bash scripts/build.sh "$build_dir"
  exclude='^$'
fi
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" -E "$exclude"
