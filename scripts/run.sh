#!/usr/bin/env bash
# Quick start: install what is missing, build in Release, and run the main job on the built-in
# default scene: the simulated humanoid walks, closed loop, to the pre-grasp pose in front of the
# box of the paper's Fig. 2 layout (scenario 3: path feedback, then object approach).
# Extra arguments go to `planemap approach` (try --help; --table --seeds 20 gives Table 1).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
PLANEMAP_TARGET=planemap bash scripts/build.sh build
./build/apps/planemap approach "$@"
