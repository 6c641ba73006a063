#!/usr/bin/env bash
# The command service and the onboard tracker from a QGroundControl-style client
# (tests/mavlink/qgc_commands.js) on the simulated vehicle with a gimbal camera (the tracking scene).
# Usage: qgc_commands.sh BIN_DIR OUT_DIR   (inside netns.sh)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source "$here/../integration/scaled_timeout.sh"
bin=$(cd "$1" && pwd) out=$2
mkdir -p "$out"
cd "$out"
rm -f uav.key uav.key.last
passphrase="a passphrase typed into QGroundControl"
"$bin/uav-keygen" uav.key --passphrase "$passphrase" > /dev/null
"$bin/uav-onboard" --sim --speed 4 --lcm-url "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608" --key uav.key \
  --scene "$here/../../resources/scenes/tracking.scene.json" --mavlink udpin:127.0.0.1:14551 --mavlink-video off \
  > onboard.log 2>&1 &
onboard=$!
trap 'kill $onboard 2>/dev/null || true' EXIT
# udpin: the vehicle listens and answers whoever speaks; the client's first frame opens the link.
scaled_timeout 180 node "$here/qgc_commands.js" --passphrase "$passphrase" --connect 127.0.0.1:14551 --report report.json
