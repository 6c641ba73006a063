#!/usr/bin/env bash
# End-to-end: the real GCS window (GLFW + OpenGL 3.3 on Mesa llvmpipe) under Xvfb, talking to a
# simulated vehicle with its onboard tracker. The script takes off, ticks signals into two plots,
# draws a survey, picks a target on the video and saves two screenshots seconds apart;
# check_screenshot verifies they show every panel with live data and writes one picture per
# panel (panel_*.png) for the user guide.
# Usage: gcs_window.sh BIN_DIR SCRIPT OUT_DIR
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/../integration/scaled_timeout.sh"
bin=$1 script=$2 out=$3
mkdir -p "$out"
rm -f "$out"/gcs_*.png "$out/layout.ini" "$out/layout_1080.ini"
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
key="$out/uav.key"
rm -f "$key" "$key.last"
"$bin/uav-keygen" "$key" > /dev/null
"$bin/uav-onboard" --sim --speed 2 --lcm-url "$url" --key "$key" \
  --scene "$(dirname "$0")/../../resources/scenes/tracking.scene.json" > "$out/onboard.log" 2>&1 &
trap 'kill $(jobs -p) 2>/dev/null || true' EXIT
cd "$out"
status=0
LIBGL_ALWAYS_SOFTWARE=1 scaled_timeout 180 xvfb-run -a -s "-screen 0 1600x900x24" \
  "$bin/uav-gcs" --name e2e --lcm-url "$url" --key "$key" --layout "$out/layout.ini" --script "$script" || status=$?
[ $status -eq 0 ] || exit $status
# The layout persists: the window wrote where every panel was, for the next start to restore.
for panel in Plot Map Video "Vehicle state" "Live map"; do
  grep -q "^\[Window\]\[$panel\]" "$out/layout.ini" || { echo "FAIL: layout.ini lacks $panel"; exit 1; }
done
"$bin/check_screenshot" "$out/gcs_1.png" "$out/gcs_2.png" "$out" "$out/gcs_3.png"
# The same layout on a 1920 x 1080 display (a fresh layout file: the default table again).
LIBGL_ALWAYS_SOFTWARE=1 scaled_timeout 120 xvfb-run -a -s "-screen 0 1920x1080x24" \
  "$bin/uav-gcs" --name e2e1080 --lcm-url "$url" --key "$key" --layout "$out/layout_1080.ini" --size 1920x1080 \
  --script "$(dirname "$script")/window_1080.gcs"
"$bin/check_screenshot" --layout "$out/gcs_1080.png"
