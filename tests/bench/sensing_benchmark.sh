#!/usr/bin/env bash
# The whole-suite sensing benchmark at real time: the whole_suite flight (tests/integration/
# whole_suite.gcs) with uav-onboard at --speed 1, every rig and algorithm on, vision latencies
# measured. Prints the vehicle's JSON report (each worker's rate against its camera's, latency,
# compute, drops; the control loop's wall-clock period; CPU use) and writes it to OUT_JSON.
# Run inside tests/integration/netns.sh (the LCM traffic stays in a private namespace):
#   tests/integration/netns.sh tests/bench/sensing_benchmark.sh build/bin /tmp/sensing.json
# Usage: sensing_benchmark.sh BIN_DIR OUT_JSON
set -euo pipefail
bin=$(cd "$1" && pwd) out=$2
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
report=$(mktemp -u --suffix=.json)
ONBOARD_ARGS="--scene $root/resources/scenes/whole_suite.scene.json --params $root/resources/vehicles/x650_whole_suite.params --sensing-benchmark $report"
source "$root/tests/integration/sim_and_gcs.sh"
run_sim_and_gcs "$bin" 1 bench "$root/tests/integration/whole_suite.gcs" 400 >&2  # the flight to stderr
[ -s "$report" ] || { echo "FAIL: no report (GCS script status $status)"; exit 1; }
mv "$report" "$out"
cat "$out"
[ "$status" -eq 0 ] || echo "note: the flight's script failed (status $status); the figures are of the run as it went"
