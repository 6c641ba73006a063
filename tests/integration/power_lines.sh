#!/usr/bin/env bash
# Integration test: power lines end to end. uav-onboard --sim in the power-line scene and a
# headless uav-gcs whose script flies toward the wires until the GCS warns and back; then the
# vehicle's flight log must carry the nearest-wire distance, near 10 m at the closest.
# Usage: power_lines.sh BIN_DIR SCRIPT SCENE
set -euo pipefail
bin=$1 script=$2 scene=$3
ONBOARD_ARGS="--scene $scene"
source "$(dirname "$0")/sim_and_gcs.sh"
run_sim_and_gcs "$bin" max itest "$script" 240
[ "$status" -eq 0 ] || { echo "FAIL: GCS script"; exit 1; }
log=$(ls "$work"/log/flight_*.csv)
python3 - "$log" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
ranges = [float(r["wire_range"]) for r in rows if float(r["wire_range"]) >= 0]
print(f"flight log: {len(rows)} rows, {len(ranges)} with a ranged wire, nearest {min(ranges):.2f} m")
sys.exit(0 if ranges and 7.5 < min(ranges) < 12.0 else 1)
PY
