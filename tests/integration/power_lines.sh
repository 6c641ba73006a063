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
ranges = sorted(float(r["wire_range"]) for r in rows if float(r["wire_range"]) >= 0)
q = lambda f: ranges[min(len(ranges) - 1, int(f * len(ranges)))]
low = [(float(r["t"]) if "t" in r else i, float(r["wire_range"]), float(r["x"]), float(r["alt"])) for i, r in enumerate(rows)
       if 0 <= float(r["wire_range"]) < 8.0]
print(f"flight log: {len(rows)} rows, {len(ranges)} with a ranged wire; nearest {ranges[0]:.2f} m, 1 % {q(0.01):.2f} m, "
      f"5 % {q(0.05):.2f} m; {len(low)} rows under 8 m")
for t, r, x, alt in low[:20]: print(f"  t {t} range {r:.2f} x {x:.2f} alt {alt:.2f}")
sys.exit(0 if ranges and 7.5 < q(0.01) < 12.0 else 1)
PY
