#!/usr/bin/env bash
# Configures and builds planemap. Usage: scripts/build.sh [BUILD_DIR [extra cmake arguments]]
# Default: build/ in Release. PLANEMAP_TARGET=planemap builds only the tool.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build}
shift || true
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build_dir" -j "$(nproc)" --target "${PLANEMAP_TARGET:-all}"
