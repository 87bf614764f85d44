#!/usr/bin/env bash
# The installed package, as a user gets it: `cmake --install` into a temporary prefix, then
# examples/ built against it with find_package(planemap) and run on a real sequence, and the
# installed tool run from another folder (its configs/ from <prefix>/share/planemap).
#   scripts/test_install.sh [BUILD_DIR]      (default build/, already built)
# Without ../shared/data the runs are skipped, unless PLANEMAP_REQUIRE_SHARED_DATA=1 (CI).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >/dev/null
echo "test_install: installed into a temporary prefix: $(cd "$prefix" && find . -type f | wc -l) files"
cmake -S examples -B "$work/examples" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/examples" >/dev/null
echo "test_install: examples/ built against it (find_package(planemap))"

sequence=$(cd .. && pwd)/shared/data/icl_office_kt0
if [ ! -d "$sequence" ]; then
  [ "${PLANEMAP_REQUIRE_SHARED_DATA:-0}" = 1 ] && { echo "test_install: $sequence is missing" >&2; exit 1; }
  echo "test_install: $sequence is missing: the runs are skipped"
  exit 0
fi
frames=30
out=$("$work/examples/map_sequence" "$sequence" "$prefix/share/planemap/configs/cameras/icl_nuim.yaml" $frames)
poses=$(grep -cE '^[0-9]+ (tracked|degraded|lost) ' <<<"$out" || true)
if [ "$poses" != "$frames" ] || ! grep -q '^map: ' <<<"$out"; then
  echo "test_install: map_sequence printed $poses of $frames poses or no map line:" >&2
  echo "$out" >&2
  exit 1
fi
echo "test_install: map_sequence: $frames poses, $(grep '^map: ' <<<"$out")"
(cd "$work" && "$prefix/bin/planemap" map "$sequence" --camera configs/cameras/icl_nuim.yaml --max-frames 10 --out "$work/map" \
  >"$work/map.log" 2>&1) || { cat "$work/map.log" >&2; exit 1; }
[ -s "$work/map/map.json" ] || { echo "test_install: the installed planemap wrote no map.json" >&2; exit 1; }
echo "test_install: the installed planemap ran from another folder: $(grep '^frames' "$work/map.log")"
