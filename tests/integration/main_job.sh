#!/usr/bin/env bash
# The README's main job, headless: uav-demo flies the full survey mission over the village,
# the GCS downloads the stitched map at landing; the saved GeoTIFF must be the onboard one. The
# village has no power line: no wire may be reported within the GCS's warning distance (15 m).
# Usage: main_job.sh BIN_DIR [--ulion]   (--ulion: the survey flown by U-Lion on its wing)
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/scaled_timeout.sh"
bin=$1
shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
UAV_LOG_DIR="$work/logs" UAV_MAP_DIR="$work/maps" scaled_timeout 600 "$bin/uav-demo" --headless "$@" | tee demo.txt
grep -q "uav-demo: PASSED" demo.txt
grep -q "uav-demo: map saved as $work/maps/map_1.tif" demo.txt
for f in "$work"/logs/maps_*/map_1.*; do
  cmp "$f" "$work/maps/$(basename "$f")"
done
echo "main job: map files identical to the onboard ones: $(ls "$work/maps" | tr '\n' ' ')"
python3 - "$work"/logs/flight_*.csv <<'PY'
import csv, sys
wires = [float(r["wire_range"]) for log in sys.argv[1:] for r in csv.DictReader(open(log)) if float(r["wire_range"]) >= 0]
print(f"main job: wires reported in {len(wires)} log rows, nearest {min(wires) if wires else -1:.1f} m (the village has none)")
sys.exit(0 if all(w >= 15.0 for w in wires) else 1)
PY
