#!/usr/bin/env bash
# Integration test: uav-onboard --sim and uav-gcs --headless as separate processes over LCM in a
# private network namespace. The GCS script sends arm, takeoff 10, hover, goto 20 10 15, land and
# asserts from telemetry that each target is reached within 0.5 m and the vehicle lands and
# disarms; it also checks that bad commands are refused on both sides and change nothing, and
# downloads the flight log the vehicle offers at the landing.
# Usage: fly_mission.sh BIN_DIR SCRIPT
set -euo pipefail
bin=$1 script=$2
source "$(dirname "$0")/sim_and_gcs.sh"
run_sim_and_gcs "$bin" 4 itest "$script" 180
# The flight log exists, has the thesis's header and one row per 20 ms.
log=$(ls "$work"/log/flight_*.csv)
head -1 "$log" | grep -q '^t,x,y,z,u,v,w,phi,theta,psi,p,q,r,acx,acy,acz,M1,M2,M3,M4,Ua,Ue,Uth,Ur' \
  || { echo "FAIL: flight log header"; exit 1; }
python3 - "$log" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
dt = [round(float(b["t"]) - float(a["t"]), 3) for a, b in zip(rows, rows[1:])]
assert rows and all(d == 0.02 for d in dt), "rows are not 20 ms apart"
alt = max(-float(r["z"]) for r in rows)
assert 14.5 < alt < 15.5, f"log max altitude {alt}"
print(f"flight log: {len(rows)} rows at 20 ms, max altitude {alt:.2f} m")
PY
# The flight log downloaded at the landing is the vehicle's log up to then, byte for byte.
python3 - "$log" "$work"/flight-logs/flight_*_landing1.csv <<'PY'
import sys
full, landed = open(sys.argv[1], "rb").read(), open(sys.argv[2], "rb").read()
assert full.startswith(landed), "the downloaded log is not the start of the vehicle's log"
rows = landed.decode().splitlines()
assert len(rows) > 1000, f"only {len(rows)} rows downloaded"
print(f"downloaded flight log: {len(rows) - 1} rows of {len(full.decode().splitlines()) - 1}, a prefix of the vehicle's")
PY
exit $status
