#!/usr/bin/env bash
# The command service and the onboard tracker from a QGroundControl-style client
# (tests/mavlink/qgc_commands.js) on the simulated vehicle with a gimbal camera (the tracking scene).
# Usage: qgc_commands.sh BIN_DIR OUT_DIR   (inside netns.sh)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
passphrase="a passphrase typed into QGroundControl"
source "$here/prepare.sh"
"$bin/uav-onboard" --sim --speed 4 --lcm-url "$url" --key uav.key \
  --scene "$here/../../resources/scenes/tracking.scene.json" --mavlink udpin:127.0.0.1:14551 --mavlink-video off \
  > onboard.log 2>&1 &
onboard=$!
trap 'kill $onboard 2>/dev/null || true' EXIT
# udpin: the vehicle listens and answers whoever speaks; the client's first frame opens the link.
scaled_timeout 180 node "$here/qgc_commands.js" --passphrase "$passphrase" --connect 127.0.0.1:14551 --report report.json
