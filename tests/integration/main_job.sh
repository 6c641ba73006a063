#!/usr/bin/env bash
# The README's main job, headless: uav-demo flies the full survey mission over the village,
# the GCS downloads the stitched map at landing; the saved GeoTIFF must be the onboard one.
# Usage: main_job.sh BIN_DIR
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/scaled_timeout.sh"
bin=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
UAV_LOG_DIR="$work/logs" UAV_MAP_DIR="$work/maps" scaled_timeout 600 "$bin/uav-demo" --headless | tee demo.txt
grep -q "uav-demo: PASSED" demo.txt
grep -q "uav-demo: map saved as $work/maps/map_1.tif" demo.txt
for f in "$work"/logs/maps_*/map_1.*; do
  cmp "$f" "$work/maps/$(basename "$f")"
done
echo "main job: map files identical to the onboard ones: $(ls "$work/maps" | tr '\n' ' ')"
