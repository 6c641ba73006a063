#!/usr/bin/env bash
# End-to-end on the bench: uav-onboard plays the real KITTI sequence of ../shared/data/kitti_vo
# through its workers (--rig, half real time) and the real GCS window under Xvfb shows it as a
# flight: the camera's video, the odometry's report, the vehicle moving with the recording's
# truth; arming is refused saying why. The screenshot is the manual's picture of the bench.
# Usage: gcs_bench.sh BIN_DIR SCRIPT DATA_DIR OUT_DIR
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/../integration/scaled_timeout.sh"
bin=$1 script=$2 data=$(cd "$3" && pwd)/kitti_vo out=$4
mkdir -p "$out"
rm -f "$out"/gcs_bench*.png
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
key="$out/uav.key"
rm -f "$key" "$key.last"
"$bin/uav-keygen" "$key" > /dev/null
cat > "$out/kitti.rig.json" <<JSON
{"cameras": {"front": {"type": "kitti", "path": "$data", "mount": {"xyz_m": [0, 0, -1.65]}}},
 "workers": {"odometry": "front", "obstacles": "front", "wires": "front"}}
JSON
"$bin/uav-onboard" --rig "$out/kitti.rig.json" --speed 0.4 --lcm-url "$url" --key "$key" > "$out/bench.log" 2>&1 &
trap 'kill $(jobs -p) 2>/dev/null || true' EXIT
cd "$out"
LIBGL_ALWAYS_SOFTWARE=1 scaled_timeout 120 xvfb-run -a -s "-screen 0 1600x900x24" \
  "$bin/uav-gcs" --name bench --lcm-url "$url" --key "$key" --script "$script"
[ -s "$out/gcs_bench.png" ] || { echo "FAIL: no screenshot"; exit 1; }
wait
grep -q "51 visual odometry pairs" "$out/bench.log" || { cat "$out/bench.log"; echo "FAIL: the bench did not play every pair"; exit 1; }
echo PASS
