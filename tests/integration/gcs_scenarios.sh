#!/usr/bin/env bash
# Integration test: the GCS operator scenarios (gcs_scenarios.gcs) run by uav-gcs --headless
# against two simulated vehicles on one bus (UAV1 with the village camera, UAV2 without) and a
# stand-in tracker for UAV1. Afterwards the tracker's log shows exactly the selections the
# GCS sent.
# Usage: gcs_scenarios.sh BIN_DIR SCRIPT SCENE
set -euo pipefail
bin=$1 script=$2 scene=$3
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT
"$bin/uav-onboard" --sim --speed 2 --vehicle-id UAV1 --lcm-url "$url" --scene "$scene" > "$work/uav1.log" 2>&1 &
"$bin/uav-onboard" --sim --speed 2 --vehicle-id UAV2 --lcm-url "$url" > "$work/uav2.log" 2>&1 &
"$bin/track_echo" "$url" UAV1 300 > "$work/tracker.log" 2>&1 &
status=0
(cd "$work" && timeout 240 "$bin/uav-gcs" --headless --name scenarios --lcm-url "$url" --script "$script") || status=$?
echo "--- tracker"
cat "$work/tracker.log"
[ "$status" -eq 0 ] || exit "$status"
# Three selections reached the vehicle: four clicks, a drag, a cancel.
[ "$(grep -c '^target ' "$work/tracker.log")" -eq 3 ] || { echo "FAIL: tracker did not see 3 selections"; exit 1; }
grep -Eq 'method 1 x 0\.(29|30)' "$work/tracker.log" || { echo "FAIL: four-click selection"; exit 1; }
grep -Eq 'method 0 x 0\.(09|10)' "$work/tracker.log" || { echo "FAIL: drag selection"; exit 1; }
grep -q 'method 2 ' "$work/tracker.log" || { echo "FAIL: cancel"; exit 1; }
