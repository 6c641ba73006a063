#!/usr/bin/env bash
# uav-monodepth on the real KITTI sequence of ../shared/data/kitti_vo (left images, ground-truth
# poses), each known cell scored against the right image's depth at its features
# (--truth-stereo): the figures held at the values measured when this test was written
# (docs/modules/mono-depth.md), so a change to the method or to the scoring shows; and the inputs
# it must refuse, named.
# Usage: uav_monodepth_kitti.sh BIN_DIR DATA_DIR
set -uo pipefail
bin=$1 data=$2/kitti_vo
fail() { echo "FAIL: $*"; exit 1; }
[ -f "$data/calib.txt" ] || fail "no KITTI sequence in $data"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/uav-monodepth" "$data" --out "$work/grid.csv" --truth-stereo > "$work/report.json" 2> "$work/stderr" ||
  { cat "$work/stderr"; fail "uav-monodepth failed on $data"; }
cat "$work/report.json"
python3 - "$work/report.json" "$work/grid.csv" <<'PY' || fail "the figures moved"
import csv, json, sys
r = json.load(open(sys.argv[1]))
t = r["stereo_truth"]
checks = [
    ("frames", r["frames"], 51, 0),
    ("known cell fraction", r["known_cell_fraction"], 0.355, 0.03),
    ("cells scored", t["cells_scored"], 183, 20),
    ("median relative error", t["rel_error_median"], 0.040, 0.01),
    ("90th percentile", t["rel_error_p90"], 0.18, 0.04),
    ("bias", t["bias"], 0.0, 0.03),
]
bad = [f"{name} {got} not within {tol} of {want}" for name, got, want, tol in checks if abs(got - want) > tol]
# The centre cell has no parallax (the car drives towards it): never known, never made up.
if t["known_fraction_per_cell"][1][1] != 0: bad.append("the centre cell was given a depth")
rows = list(csv.DictReader(open(sys.argv[2])))
if len(rows) != 51 * 12: bad.append(f"{len(rows)} CSV rows, not 612")
if any(x["state"] == "unknown" and x["reason"] == "" for x in rows): bad.append("an unknown cell without its reason")
print("\n".join(bad) or "figures as measured")
sys.exit(1 if bad else 0)
PY
# Refused, and named: the stereo truth without a right image, poses that do not match the images.
mkdir -p "$work/capture" && echo '{}' > "$work/capture/session.json"
out=$("$bin/uav-monodepth" "$work/capture" --out "$work/x.csv" --truth-stereo 2>&1) && fail "--truth-stereo on a capture folder was taken"
echo "$out" | grep -q "needs a KITTI sequence" || fail "unexpected refusal: $out"
head -5 "$data/poses.txt" > "$work/short_poses.txt"
out=$("$bin/uav-monodepth" "$data" --poses "$work/short_poses.txt" --out "$work/x.csv" 2>&1) && fail "5 poses for 51 images were taken"
echo "$out" | grep -q "5 poses for 51 images" || fail "unexpected refusal: $out"
[ ! -e "$work/x.csv" ] || fail "a refused run wrote its output"
echo "ok"
