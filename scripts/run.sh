#!/usr/bin/env bash
# Quick start: install what is missing, build in Release, and run the main job on the built-in
# default scene. Until the approach demo exists this renders the default scene (the paper's
# Fig. 2 layout) along the default walk toward the box, with sensor noise, into out/default_walk/.
# Extra arguments go to `planemap render` (try --help).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
PLANEMAP_TARGET=planemap bash scripts/build.sh build
./build/apps/planemap render --out out/default_walk "$@"
