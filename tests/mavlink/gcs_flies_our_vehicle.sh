#!/usr/bin/env bash
# Our GCS over MAVLink alone flying our simulated vehicle's MAVLink endpoint (gcs_flies_our_vehicle.gcs).
# Usage: gcs_flies_our_vehicle.sh BIN_DIR OUT_DIR   (inside netns.sh)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
passphrase="a passphrase typed into QGroundControl"
source "$here/prepare.sh"
"$bin/uav-onboard" --sim --speed 2 --lcm-url "$url" --key uav.key --mavlink udpin:127.0.0.1:14551 --mavlink-video off \
  --param obs_enable=0 --param pwl_enable=0 --param mdp_camera=0 > onboard.log 2>&1 &
onboard=$!
trap 'kill $onboard 2>/dev/null || true' EXIT
scaled_timeout 240 "$bin/uav-gcs" --headless --insecure --lcm-url memq:// --name gcs-test --no-speech \
  --mavlink udp:127.0.0.1:14551 --mavlink-key uav.key --mavlink-video 0 \
  --script "$here/gcs_flies_our_vehicle.gcs" --layout layout.ini
