#!/usr/bin/env bash
# Integration test: the survey planned and uploaded in the GCS (headless, mouse on the map) is
# flown by uav-onboard --sim over LCM in a private network namespace. The flight log must show
# the vehicle at the survey altitude while it flew the lines.
# Usage: survey_mission.sh BIN_DIR SCRIPT
set -euo pipefail
bin=$1 script=$2
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
"$bin/uav-onboard" --sim --speed 8 --vehicle-id UAV1 --lcm-url "$url" --log-dir "$work/log" > "$work/onboard.log" 2>&1 &
status=0
timeout 240 "$bin/uav-gcs" --headless --name survey --lcm-url "$url" --script "$script" || status=$?
kill %1 2>/dev/null || true
wait || true
echo "--- onboard output"; cat "$work/onboard.log"
exit $status
