#!/usr/bin/env bash
# Installs what planemap builds and tests with, if any is missing: Debian 12 packages, and the HTML
# reports' three.js (npm ci in web/). Runs as root (CI, a fresh machine) or through sudo.
#   scripts/setup.sh                 build dependencies, Node.js, web/node_modules
#   scripts/setup.sh --with-browser  and Chromium, for the report's browser test (scripts/test.sh)
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake ninja-build lld pkg-config
  clang-14 libclang-rt-14-dev   # the fuzz targets (libFuzzer): scripts/fuzz.sh
  libeigen3-dev libceres-dev libsuitesparse-dev libpcl-dev libopencv-dev
  libyaml-cpp-dev libcli11-dev libspdlog-dev nlohmann-json3-dev libboost-math-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  pybind11-dev python3-dev python3-numpy python3-pytest
  slurm-wlm munge   # a one-node Slurm cluster for scripts/test_slurm.sh (studies on a job array)
)
[ "${1:-}" = "--with-browser" ] && PACKAGES+=(chromium)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js and npm, from Debian only when the machine has none of its own.
command -v node >/dev/null && command -v npm >/dev/null || missing+=(nodejs npm)

SUDO=""
[ "$(id -u)" = 0 ] || SUDO=sudo
if ((${#missing[@]} > 0)); then
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# three.js (and the browser test's driver) at the versions web/package-lock.json pins.
if [ ! -d web/node_modules ]; then
  echo "setup: npm ci in web/"
  (cd web && npm ci --no-audit --no-fund --loglevel=error)
fi
