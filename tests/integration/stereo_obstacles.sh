#!/usr/bin/env bash
# Integration test: stereo obstacles end to end. uav-onboard --sim in the forest scene and a
# headless uav-gcs whose script takes off facing a person and a pole and asserts the nearest
# obstacle; then the vehicle's flight log must carry the obstacle count and nearest distance,
# and the nearest while hovering at (3, -1.5) must be the person's surface at 2.8 m (+-0.7 m:
# the hover point is the INS estimate's, up to half a metre from the truth).
# Usage: stereo_obstacles.sh BIN_DIR SCRIPT SCENE
set -euo pipefail
bin=$1 script=$2 scene=$3
ONBOARD_ARGS="--scene $scene"
source "$(dirname "$0")/sim_and_gcs.sh"
run_sim_and_gcs "$bin" max itest "$script" 240
[ "$status" -eq 0 ] || { echo "FAIL: GCS script"; exit 1; }
log=$(ls "$work"/log/flight_*.csv)
python3 - "$log" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
seen = [r for r in rows if int(float(r["obstacles"])) > 0]
# Hovering at (3, -1.5), 1.5 m up: within 0.2 m of the spot.
hover = [float(r["obstacle_nearest"]) for r in seen
         if abs(float(r["x"]) - 3) < 0.2 and abs(float(r["y"]) + 1.5) < 0.2 and abs(float(r["alt"]) - 1.5) < 0.3]
print(f"flight log: {len(rows)} rows, {len(seen)} with obstacles; {len(hover)} hovering at (3, -1.5)")
if not hover: sys.exit(1)
median = statistics.median(hover)
print(f"nearest obstacle while hovering at (3, -1.5): median {median:.2f} m (truth 2.8 m), "
      f"min {min(hover):.2f}, max {max(hover):.2f}")
sys.exit(0 if abs(median - 2.8) < 0.7 else 1)
PY
