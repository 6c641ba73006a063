#!/usr/bin/env bash
# Integration test: U-Lion (resources/vehicles/ulion.params) flown by uav-onboard --sim and a
# headless uav-gcs over LCM: the transition button, a goto on the wing, the landing with the
# automatic back-transition; then the flight log must hold the cruise (vtol_mode 2 at 10 m/s or
# more of airspeed) and end on the ground in hover.
# Usage: ulion_flight.sh BIN_DIR SCRIPT PARAMS_FILE
set -euo pipefail
bin=$1 script=$2 params=$3
source "$(dirname "$0")/sim_and_gcs.sh"
ONBOARD_ARGS="--params $params" run_sim_and_gcs "$bin" 8 itest "$script" 300
[ "$status" -eq 0 ] || { echo "FAIL: GCS script"; exit 1; }
log=$(ls "$work"/log/flight_*.csv | head -1)
python3 - "$log" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
cruise = [r for r in rows if r["vtol_mode"] == "2"]
fast = [r for r in cruise if float(r["airspeed"]) >= 10]
print(f"flight log: {len(rows)} rows, {len(cruise)} on the wing, {len(fast)} of them at 10 m/s or more")
if len(cruise) < 50 * 15 or len(fast) < 0.9 * len(cruise): sys.exit("FAIL: too little cruise in the log")
if rows[-1]["vtol_mode"] != "0": sys.exit("FAIL: the log does not end in hover")
PY
echo ok
