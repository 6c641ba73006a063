#!/usr/bin/env bash
# Our GCS (headless) flies a mock MAVLink vehicle (mock_vehicle.js, node-mavlink) with the script
# gcs_flies_AUTOPILOT.gcs, the link signed with a passphrase's key on both sides and the vehicle's
# RTP/H.264 video on its own port.
# Usage: gcs_flies.sh px4|arducopter BIN_DIR OUT_DIR MAVLINK_PORT VIDEO_PORT
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source "$here/../integration/scaled_timeout.sh"
autopilot=$1 bin=$(cd "$2" && pwd) out=$3 port=$4 video=$5
passphrase="a passphrase typed into QGroundControl"
mkdir -p "$out" && cd "$out"
node "$here/mock_vehicle.js" --autopilot "$autopilot" --gcs "127.0.0.1:$port" --passphrase "$passphrase" \
  --video "$video" --rate 4 > "mock_$autopilot.log" 2>&1 &
mock=$!
trap 'kill $mock 2>/dev/null || true' EXIT
status=0
scaled_timeout 400 "$bin/uav-gcs" --headless --insecure --lcm-url memq:// --name gcs-test --no-speech \
  --mavlink "udpin:127.0.0.1:$port" --mavlink-passphrase "$passphrase" --mavlink-video "$video" \
  --script "$here/gcs_flies_$autopilot.gcs" --layout "$out/layout.ini" || status=$?
kill $mock 2>/dev/null || true
wait $mock 2>/dev/null || true
echo "--- the mock vehicle's side:"
tail -n 15 "mock_$autopilot.log"
exit $status
