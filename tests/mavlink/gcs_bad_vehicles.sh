#!/usr/bin/env bash
# Our GCS (headless) with three misbehaving mock MAVLink vehicles (mock_vehicle.js), each on a port
# of its own: gcs_bad_vehicles.gcs names what it must see.
# Usage: gcs_bad_vehicles.sh BIN_DIR OUT_DIR FIRST_PORT
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source "$here/../integration/scaled_timeout.sh"
bin=$(cd "$1" && pwd) out=$2 port=$3
passphrase="a passphrase typed into QGroundControl"
mkdir -p "$out" && cd "$out"
pids=()
trap 'kill "${pids[@]}" 2>/dev/null || true' EXIT
node "$here/mock_vehicle.js" --autopilot px4 --sysid 2 --gcs "127.0.0.1:$port" --passphrase "$passphrase" --silent \
  --drop-every 10 \
  > mock_silent.log 2>&1 & pids+=($!)
node "$here/mock_vehicle.js" --autopilot arducopter --sysid 3 --gcs "127.0.0.1:$((port + 1))" --passphrase "$passphrase" \
  --stop-upload-at 3 --unknown > mock_stops.log 2>&1 & pids+=($!)
node "$here/mock_vehicle.js" --autopilot px4 --sysid 4 --gcs "127.0.0.1:$((port + 2))" --passphrase "another one" \
  > mock_other_key.log 2>&1 & pids+=($!)
scaled_timeout 300 "$bin/uav-gcs" --headless --insecure --lcm-url memq:// --name gcs-test --no-speech \
  --mavlink "udpin:127.0.0.1:$port" --mavlink "udpin:127.0.0.1:$((port + 1))" --mavlink "udpin:127.0.0.1:$((port + 2))" \
  --mavlink-passphrase "$passphrase" --mavlink-video 0 --script "$here/gcs_bad_vehicles.gcs" --layout "$out/layout.ini"
