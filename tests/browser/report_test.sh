#!/usr/bin/env bash
# CTest's Report.ApproachPageInBrowser: the default approach run (seed 1) writes its report and
# map.json, and check_report.mjs opens the report in headless Chromium; then the same for a small
# study's report.
#   report_test.sh PLANEMAP_BINARY OUT_DIR
# Exit 77 (skipped) without node, /usr/bin/chromium or web/node_modules: scripts/setup.sh
# --with-browser installs them, and scripts/test.sh runs it so.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source_dir=$(cd "$here/../.." && pwd)
planemap=$1
out=$2
if ! command -v node >/dev/null || [ ! -x /usr/bin/chromium ] || [ ! -d "$source_dir/web/node_modules" ]; then
  echo "skipped: needs node, /usr/bin/chromium and web/node_modules (run scripts/setup.sh --with-browser)"
  exit 77
fi
mkdir -p "$out"
"$planemap" approach --scene "$source_dir/configs/scenes/default.yaml" --seed 1 \
  --report "$out/approach.html" --map "$out/map.json"
echo "report: $(stat -c %s "$out/approach.html") bytes"
node "$here/check_report.mjs" "$out/approach.html" "$out/map.json" "$out/approach.png"

# A study's page: a two-run study (1 frame each) with --report; the 3-D view is its first run's map.
cat > "$out/study.yaml" <<'EOF2'
name: browser
frames: 1
seeds: 1
sweep:
  distance: [1.5, 2.5]
EOF2
"$planemap" study "$out/study.yaml" --out "$out/study" --restart --report "$out/study.html"
node "$here/check_report.mjs" "$out/study.html" "$out/study/run0_map.json" "$out/study.png"
