#!/usr/bin/env bash
# Installs the Debian 12 packages planemap builds with, if any is missing. Runs as root (CI, a
# fresh machine) or through sudo.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build lld pkg-config
  libeigen3-dev libceres-dev libsuitesparse-dev libpcl-dev libopencv-dev
  libyaml-cpp-dev libcli11-dev libspdlog-dev nlohmann-json3-dev libboost-math-dev
  libgtest-dev libgmock-dev libbenchmark-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi

SUDO=""
[ "$(id -u)" = 0 ] || SUDO=sudo
echo "setup: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
