#!/usr/bin/env bash
# Integration test: obstacle avoidance end to end. uav-onboard --sim in the forest scene with
# avd_enable 1 and a headless uav-gcs whose script sends the vehicle 50 m through the trees; then
# the flight log must show the detour (avoid state "avoiding") and a true clearance (the
# simulator's distance to the nearest surface) never under the body radius, and the map must
# have been saved at landing as an OctoMap file. The forest has no cable: no wire may be reported
# within the GCS's warning distance (15 m) at any time of the flight.
# Usage: avoid_forest.sh BIN_DIR SCRIPT SCENE
set -euo pipefail
bin=$1 script=$2 scene=$3
ONBOARD_ARGS="--scene $scene --param avd_enable=1"
source "$(dirname "$0")/sim_and_gcs.sh"
run_sim_and_gcs "$bin" max itest "$script" 400
log=$(ls "$work"/log/flight_*.csv)
# The flight every 2 s (where, the avoidance state, the speed it allowed, the true clearance).
python3 - "$log" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
names = ["off", "clear", "avoiding", "blocked", "no_path", "no_data"]
for r in rows[::100]:
    print(f"t {float(r['t']):6.1f}  x {float(r['x']):6.1f} y {float(r['y']):6.1f} alt {float(r['alt']):5.1f}  task {r['task']}  "
          f"avoid {names[int(float(r['avoid']))]:9s} limit {float(r['avoid_speed']):5.2f} m/s  clearance {float(r['clearance_m']):5.2f} m")
PY
[ "$status" -eq 0 ] || { echo "FAIL: GCS script"; exit 1; }
map=$(ls "$work"/log/map_*.bt)
head -c 40 "$map" | grep -q "# Octomap OcTree binary file" || { echo "FAIL: $map is not an OctoMap binary tree"; exit 1; }
python3 - "$log" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
goto = [r for r in rows if int(float(r["task"])) == 3]
clearance = [float(r["clearance_m"]) for r in goto if float(r["clearance_m"]) >= 0]
avoiding = sum(1 for r in goto if int(float(r["avoid"])) == 2)
replan = sorted(float(r["replan_ms"]) for r in goto if float(r["replan_ms"]) >= 0)
print(f"goto: {len(goto)} rows, {avoiding} avoiding; true clearance min {min(clearance):.2f} m; "
      f"replan p50 {replan[len(replan) // 2]:.1f} ms")
wires = [float(r["wire_range"]) for r in rows if float(r["wire_range"]) >= 0]
print(f"wires reported: {len(wires)} rows, nearest {min(wires) if wires else -1:.1f} m (the forest has none)")
ok = clearance and min(clearance) >= 0.5 and avoiding > 0 and all(w >= 15.0 for w in wires)
sys.exit(0 if ok else 1)
PY
