#!/usr/bin/env bash
# Our GCS (headless) flies a mock MAVLink vehicle (mock_vehicle.js, node-mavlink) with the script
# gcs_flies_AUTOPILOT.gcs, the link signed with a passphrase's key on both sides and the vehicle's
# RTP/H.264 video on its own port.
# Usage: gcs_flies.sh px4|arducopter BIN_DIR OUT_DIR MAVLINK_PORT VIDEO_PORT [--window]
# (--window: the GCS in its window under Xvfb, where the script takes its picture; headless, the
# script's screenshot step is left out.)
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
gcs=("$bin/uav-gcs" --insecure --lcm-url memq:// --name gcs-test --no-speech --mavlink "udpin:127.0.0.1:$port"
     --mavlink-passphrase "$passphrase" --mavlink-video "$video" --layout "$out/layout.ini")
if [ "${6:-}" = --window ]; then
  LIBGL_ALWAYS_SOFTWARE=1 scaled_timeout 400 xvfb-run -a -s "-screen 0 1600x900x24" "${gcs[@]}" \
    --script "$here/gcs_flies_$autopilot.gcs" || status=$?
else
  grep -v '^screenshot' "$here/gcs_flies_$autopilot.gcs" > script.gcs
  scaled_timeout 400 "${gcs[@]}" --headless --script script.gcs || status=$?
fi
kill $mock 2>/dev/null || true
wait $mock 2>/dev/null || true
echo "--- the mock vehicle's side:"
tail -n 15 "mock_$autopilot.log"
exit $status
