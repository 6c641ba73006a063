#!/usr/bin/env bash
# Integration test (DLG, thesis 2.3.2): kill -9 the vehicle mid-flight; its CSV flight log and its
# LCM event log must both be readable and lose at most 0.2 s, measured against an independent
# lcm-logger on the same bus. The event log must also replay with lcm-logplayer.
# Usage: kill9_logs.sh BIN_DIR SCRIPT
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/scaled_timeout.sh"
bin=$1 script=$2
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"' EXIT
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
key="$work/uav.key"
"$bin/uav-keygen" "$key" > /dev/null
lcm-logger --lcm-url="$url" --flush-interval=10 -f "$work/reference.lcmlog" > /dev/null 2>&1 &
logger=$!
"$bin/uav-onboard" --sim --speed 2 --vehicle-id UAV1 --lcm-url "$url" --key "$key" --log-dir "$work/log" > "$work/onboard.log" 2>&1 &
vehicle=$!
scaled_timeout 120 "$bin/uav-gcs" --headless --name kill9 --lcm-url "$url" --key "$key" --script "$script"
kill -9 $vehicle
sleep 0.5   # the logger writes what was already on the bus
kill -INT $logger
wait $logger || true
events=$(ls "$work"/log/events_*.lcmlog) csv=$(ls "$work"/log/flight_*.csv)
"$bin/check_logs" "$events" "$work/reference.lcmlog" "$csv" 0.2
# lcm-logplayer reads the whole truncated log (on a private in-process bus).
scaled_timeout 60 lcm-logplayer -s 50 -l "memq://" "$events"
echo "ok: lcm-logplayer replayed $(du -h "$events" | cut -f1) of events"
