#!/usr/bin/env bash
# Integration test of the GCS link-loss failsafe over LCM in a private network namespace: the GCS
# sends a goto and exits. The vehicle must hold from 5 s without heartbeats (wall clock), return
# home from 20 s, land and disarm there; its flight log shows the sequence and the timings (in
# simulated time at --speed 4: the hold lasts 15 s of wall time, 60 s simulated).
# Usage: link_loss.sh BIN_DIR SCRIPT
set -euo pipefail
bin=$1 script=$2
source "$(dirname "$0")/sim_and_gcs.sh"
# Done when the log's last row says disarmed after it was armed.
landed() {
  local log
  log=$(ls "$work"/log/flight_*.csv 2>/dev/null) || return 1
  python3 - "$log" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
sys.exit(0 if rows and any(r["armed"] == "1" for r in rows) and rows[-1]["armed"] == "0" else 1)
PY
}
run_sim_and_gcs "$bin" 4 linkloss "$script" 120 90 landed
[ $status -eq 0 ] || exit $status
python3 - "$work"/log/flight_*.csv <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
task = [int(float(r["task"])) for r in rows]
# Runs of (task, first time, last time) after the goto (3).
runs = []
for r, k in zip(rows, task):
    t = float(r["t"])
    if runs and runs[-1][0] == k: runs[-1][2] = t
    else: runs.append([k, t, t])
seq = [k for k, _, _ in runs]
i = max(j for j, k in enumerate(seq) if k == 3)
after = seq[i:]
assert after[:5] == [3, 2, 7, 4, 0], f"task sequence after the goto {after} (want goto, hover, return, land, idle)"
hold = runs[i + 1][2] - runs[i + 1][1]
# The failsafe times the link on the wall clock: 15 s of hold is 60 s simulated at x4, less when
# a loaded machine cannot keep x4, more when the simulation catches up a lag from before (the
# exact 5 s / 20 s timing is ClosedLoop.LinkLoss*, on the simulated clock).
assert 30 < hold < 90, f"held {hold:.1f} s simulated (15 s wall at x4 = 60 s)"
last = rows[-1]
assert last["armed"] == "0", "not disarmed"
x, y, alt = float(last["x"]), float(last["y"]), -float(last["z"])
assert (x * x + y * y) ** 0.5 < 0.5 and abs(alt) < 0.1, f"landed at ({x:.2f}, {y:.2f}, {alt:.2f})"
print(f"link loss: goto -> hold for {hold:.1f} s simulated -> return -> land at ({x:.2f}, {y:.2f}) -> disarmed")
PY
