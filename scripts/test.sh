#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite.
#   scripts/test.sh             Release build in build/, then the installed package (scripts/test_install.sh)
#   scripts/test.sh --sanitize  AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --with-browser
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build-asan
  # -O1 as the sanitizers' documentation advises, line tables only (-g1: stack traces keep file and
  # line): this build took 21.5 min at -O2 -g on the 2 cores, the larger part of the CI's time.
  bash scripts/build.sh "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" \
    -DPLANEMAP_SANITIZE=ON -DPLANEMAP_BUILD_BENCH=OFF
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  # The sanitized build runs every test but the longest rendered runs (2-4 min and more each there), whose
  # code paths shorter tests take: the walks but the default one tracked (refined: the map --refine
  # CLI test), the rendered tracking stretches (single wall, near a box, facing a shelf, a far
  # wall, a wall seen again after a turn), the rendered merge and the seeded consistency runs,
  # whose units have their own tests (silhouettes, merging, covariances); every closed-loop
  # approach run (the --trace CLI test runs the whole loop for 2 s); the report's browser test
  # (another approach run; the page is the same as the release build's); the real sequences' map,
  # refine and stride-20 runs
  # (Tracking.RealSequenceRunsEndToEnd and the fr3 pair take the same paths on real frames); and
  # the study on a Slurm cluster (its planemap code is the StudyShards tests', which run here).
  exclude='(TrackedWalk.*/(storeroom|office)|RefinedWalk)|Cli\.MapOfARealSequence|Cli/MapRefine\.OnARealSequence|Real/WideBaseline|Tracking\.(SingleWallStretch|NearABoxItsSilhouettes|FacingOnePlane|AStandingRobotDoesNotFollowAFarWall|AWallSeenAgain|ARoomCornerSeenNearBy)|MapMerge\.TwoHalves|Consistency\.BoxDimensionCovariances|Approach\.(FeedbackBeats|ASecondWithout|AnObjectMoved|ScenarioThreeEnds|ABoxNotMapped|PlanesMappedOnce|ABoxHidden|ARobotFacing|ACrateBefore)|Report\.ApproachPageInBrowser|Slurm\.StudyOnAJobArray'
else
  build_dir=build
  bash scripts/build.sh "$build_dir"
  exclude='^$'
fi
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" -E "$exclude"
# The installed package: find_package(planemap) from examples/, and the installed tool.
if [ "$build_dir" = build ]; then bash scripts/test_install.sh "$build_dir"; fi
