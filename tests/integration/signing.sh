#!/usr/bin/env bash
# Integration test: signed commands over LCM (inside netns.sh). A simulated vehicle started with
# its key; a GCS with another key cannot arm it, an --insecure one neither; the operator's GCS
# (the vehicle's key) arms and takes off; the stranger cannot land or disarm it in flight; the
# operator lands. The operator's commands, recorded off the network, are played again after the
# vehicle restarted: refused as stale (the newest timestamp survived in KEY.last). Then both
# programs refuse a key file that others can read, and refuse to start with neither --key nor
# --insecure.
# Usage: signing.sh BIN_DIR
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/scaled_timeout.sh"
bin=$1
dir=$(cd "$(dirname "$0")" && pwd)
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"' EXIT
"$bin/uav-keygen" "$work/vehicle.key" > /dev/null
"$bin/uav-keygen" "$work/stranger.key" > /dev/null
"$bin/uav-onboard" --sim --speed 4 --vehicle-id UAV1 --lcm-url "$url" --key "$work/vehicle.key" > "$work/onboard.log" 2>&1 &
vehicle=$!
# An eavesdropper records every command sent.
lcm-logger --lcm-url="$url" -c 'UAV1/COMMAND' --flush-interval=10 "$work/commands.lcmlog" > /dev/null 2>&1 &
logger=$!
gcs() {
  local name=$1 script=$2
  shift 2
  echo "--- $name"
  (cd "$work" && scaled_timeout 120 "$bin/uav-gcs" --headless --name "$name" --lcm-url "$url" "$@" --script "$dir/$script") ||
    { echo "FAIL: $name"; cat "$work/onboard.log"; exit 1; }
}
gcs stranger signing_stranger.gcs --key "$work/stranger.key"
gcs insecure signing_insecure.gcs --insecure
gcs operator signing_operator.gcs --key "$work/vehicle.key"
gcs stranger signing_stranger_flying.gcs --key "$work/stranger.key"
gcs operator signing_operator_lands.gcs --key "$work/vehicle.key"
kill -INT $logger
kill $vehicle
wait $vehicle || true
grep -q "signed with key" "$work/onboard.log"
[ -s "$work/vehicle.key.last" ] || { echo "FAIL: no signing state kept in vehicle.key.last"; exit 1; }
# The vehicle restarted; the recording played onto the bus while a GCS watches.
"$bin/uav-onboard" --sim --speed 4 --vehicle-id UAV1 --lcm-url "$url" --key "$work/vehicle.key" > "$work/onboard2.log" 2>&1 &
vehicle=$!
(sleep 3 && lcm-logplayer --lcm-url="$url" "$work/commands.lcmlog") > /dev/null 2>&1 &
gcs watcher signing_replay_watch.gcs --key "$work/vehicle.key"
kill $vehicle
wait $vehicle || true
# Refused keys and missing choices: a clear error naming the fault, nothing started.
chmod 644 "$work/stranger.key"
expect_refusal() {
  local what=$1
  shift
  if "$@" > "$work/out.txt" 2>&1; then echo "FAIL: started: $*"; exit 1; fi
  grep -q -- "$what" "$work/out.txt" || { echo "FAIL: no '$what' in:"; cat "$work/out.txt"; exit 1; }
}
expect_refusal "mode 0644" "$bin/uav-gcs" --headless --lcm-url "$url" --key "$work/stranger.key" --exit-after 1
expect_refusal "mode 0644" "$bin/uav-onboard" --sim --lcm-url "$url" --key "$work/stranger.key" --duration 1
expect_refusal "give --key FILE" "$bin/uav-gcs" --headless --lcm-url "$url" --exit-after 1
expect_refusal "give --key FILE" "$bin/uav-onboard" --sim --lcm-url "$url" --duration 1
expect_refusal "excludes" "$bin/uav-onboard" --sim --insecure --key "$work/vehicle.key" --duration 1
echo "signing: the stranger and the unsigned GCS were refused, the operator flew; bad keys refused"
