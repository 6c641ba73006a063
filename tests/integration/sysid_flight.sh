#!/usr/bin/env bash
# Integration test: system identification end to end. uav-onboard --sim (sensor noise, INS) and a
# headless uav-gcs whose command bar flies hover, a throttle chirp and a rudder chirp; then
# uav-sysid on the vehicle's CSV flight log must recover K_f, tau_f and d within 5 % of the
# vehicle file the simulator flew, and draw its plot.
# Usage: sysid_flight.sh BIN_DIR SCRIPT PARAMS_FILE
set -euo pipefail
bin=$1 script=$2 params=$3
source "$(dirname "$0")/sim_and_gcs.sh"
run_sim_and_gcs "$bin" 8 itest "$script" 240
[ "$status" -eq 0 ] || { echo "FAIL: GCS script"; exit 1; }
log=$(ls "$work"/log/flight_*.csv)
"$bin/uav-sysid" "$log" --params "$params" --json "$work/sysid.json" --plot "$work/sysid.png" > /dev/null
test -s "$work/sysid.png" || { echo "FAIL: no plot"; exit 1; }
python3 - "$work/sysid.json" "$params" <<'PY'
import json, sys
result = json.load(open(sys.argv[1]))
truth = {}
for line in open(sys.argv[2]):
    f = line.split("#")[0].split()
    if len(f) == 2: truth[f[0]] = float(f[1])
got = {}
for m in result["models"]:
    got.update(m["params"])
checks = {"Kf": truth["thrust_gain"], "tau_f": truth["thrust_time_constant"], "d": truth["induced_torque_coeff"]}
bad = 0
for name, want in checks.items():
    err = 100 * (got[name] - want) / want
    print(f"{name}: identified {got[name]:.5f}, vehicle file {want:.5f} ({err:+.2f} %)")
    bad += abs(err) > 5
trim = result["trim"]["values"]
print(f"trim: u_a0 {trim['u_a0']:.4f} u_e0 {trim['u_e0']:.4f} u_th0 {trim['u_th0']:.4f} u_r0 {trim['u_r0']:.4f}")
bad += abs(trim["u_th0"] - 0.18) > 0.01
sys.exit(1 if bad else 0)
PY
