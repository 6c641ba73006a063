#!/usr/bin/env bash
# Integration test: the GCS operator scenarios (gcs_scenarios.gcs) run by uav-gcs --headless
# against two simulated vehicles on one bus: UAV1 in SCENE (with the gimballed tracking camera,
# whose onboard tracker answers the selections), UAV2 without a scene.
# Usage: gcs_scenarios.sh BIN_DIR SCRIPT SCENE
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/scaled_timeout.sh"
bin=$1 script=$2 scene=$3
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"' EXIT
key="$work/uav.key"
"$bin/uav-keygen" "$key" > /dev/null
"$bin/uav-onboard" --sim --speed 2 --vehicle-id UAV1 --lcm-url "$url" --key "$key" --scene "$scene" > "$work/uav1.log" 2>&1 &
"$bin/uav-onboard" --sim --speed 2 --vehicle-id UAV2 --lcm-url "$url" --key "$key" > "$work/uav2.log" 2>&1 &
status=0
(cd "$work" && scaled_timeout 240 "$bin/uav-gcs" --headless --name scenarios --lcm-url "$url" --key "$key" --script "$script") || status=$?
[ "$status" -eq 0 ] || { echo "--- uav1"; tail -20 "$work/uav1.log"; exit "$status"; }
