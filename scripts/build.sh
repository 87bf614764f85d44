#!/usr/bin/env bash
# Configures and builds planemap. Usage: scripts/build.sh [BUILD_DIR [extra cmake arguments]]
# Default: build/ in Release.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build}
shift || true
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
