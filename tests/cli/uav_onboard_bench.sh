#!/usr/bin/env bash
# uav-onboard on the bench, as an operator runs it: --rig on the real KITTI sequence of
# ../shared/data/kitti_vo plays every pair through the vehicle's odometry and exits at its end
# (the obstacle and wire workers on it: e2e.gcs_bench),
# its odometry scored exactly as uav-vo's on the same folder; a broken rig file and a rig with
# a simulator's scene are refused before anything runs, named.
# Usage: uav_onboard_bench.sh BIN_DIR DATA_DIR
set -uo pipefail
bin=$1 data=$(cd "$2" && pwd)/kitti_vo
fail() { echo "FAIL: $*"; exit 1; }
[ -f "$data/calib.txt" ] || fail "no KITTI sequence in $data"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/kitti.rig.json" <<JSON
{"cameras": {"front": {"type": "kitti", "path": "$data", "mount": {"xyz_m": [0, 0, -1.65]}}},
 "workers": {"odometry": "front"}}
JSON
out=$("$bin/uav-onboard" --rig "$tmp/kitti.rig.json" --insecure --lcm-url memq:// --speed max --log-dir "$tmp/log" 2>&1) ||
  fail "the bench run failed: $out"
echo "$out"
grep -q "bench: control off, pose from the recorded ground truth" <<< "$out" || fail "the start line does not say it is the bench"
grep -q "51 visual odometry pairs (0 unhealthy)" <<< "$out" || fail "not every pair reached the odometry"
poses=$(ls "$tmp"/log/vo_*.txt) || fail "no odometry poses written"
"$bin/uav-vo" "$data" --out "$tmp/uav_vo.txt" > /dev/null 2>&1 || fail "uav-vo failed"
score() { "$bin/uav-vo-eval" "$data/poses.txt" "$1" --lengths 10 20 30 40 50 | sed -n 's/.*translation \([0-9.]*\) %.*/\1/p' | head -1; }
worker=$(score "$poses") tool=$(score "$tmp/uav_vo.txt")
echo "translation error: the vehicle's VO worker $worker %, uav-vo $tool %"
[ -n "$worker" ] && [ "$worker" = "$tool" ] || fail "the worker's odometry ($worker %) differs from uav-vo's ($tool %)"
ls "$tmp"/log/flight_*.csv "$tmp"/log/events_*.lcmlog > /dev/null || fail "the run's logs are missing"

# Refused before the run, exit 2, naming the field.
echo '{"cameras": {"front": {"type": "kitti", "path": "/nowhere"}}, "workers": {"odometry": "front"}}' > "$tmp/bad.rig.json"
err=$("$bin/uav-onboard" --rig "$tmp/bad.rig.json" --insecure --lcm-url memq:// 2>&1); status=$?
[ $status -eq 2 ] || fail "a rig naming a missing folder exited $status"
grep -q "rig file '.*bad.rig.json': cameras.front: KITTI sequence '/nowhere'" <<< "$err" || fail "the refusal does not name it: $err"
err=$("$bin/uav-onboard" --rig "$tmp/kitti.rig.json" --scene x.scene.json --insecure --lcm-url memq:// 2>&1); status=$?
[ $status -eq 2 ] && grep -q "needs --sim" <<< "$err" || fail "--scene on the bench was not refused ($status): $err"
err=$("$bin/uav-onboard" --insecure --lcm-url memq:// 2>&1); status=$?
[ $status -eq 2 ] && grep -q "use --sim (the simulator) or --rig FILE" <<< "$err" || fail "no vehicle was not refused ($status): $err"
echo PASS
