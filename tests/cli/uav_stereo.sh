#!/usr/bin/env bash
# uav-stereo on opencv-doc's rectified Middlebury aloe pair: the 16-bit disparity PNG (x 16, 0
# invalid, the left image's size), a PCD cloud and an obstacle JSON with --focal/--baseline, the
# score against aloeGT.png; a raw pair with a calibration written by the library's YAML; bad
# input named with nothing written; uav-stereo-calibrate on opencv-doc's chessboard pairs.
set -euo pipefail
bin=$1
data=/usr/share/doc/opencv-doc/examples/data
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$bin/uav-stereo" "$data/aloeL.jpg" "$data/aloeR.jpg" --rectified --focal 1000 --baseline 0.16 \
  --disparity "$out/d.png" --cloud "$out/c.pcd" --obstacles "$out/o.json" --truth "$data/aloeGT.png" > "$out/report.json"
python3 - "$out" <<'PY'
import json, struct, sys, zlib
out = sys.argv[1]
r = json.load(open(f"{out}/report.json"))
png = open(f"{out}/d.png", "rb").read()
w, h, depth, colour = struct.unpack(">IIBB", png[16:26])
assert (w, h, depth, colour) == (1282, 1110, 16, 0), (w, h, depth, colour)
pcd = open(f"{out}/c.pcd", "rb").read(400).decode("latin1")
assert "FIELDS x y z" in pcd and "DATA binary" in pcd, pcd[:200]
o = json.load(open(f"{out}/o.json"))
assert "obstacles" in o and o["range_gate_m"] > 0
assert all(isinstance(c["crown_on_trunk"], bool) for c in o["obstacles"]), o["obstacles"][:2]
e, dense = r["errors"]["bad_fraction"], r["dense_errors"]["bad_fraction"]
cv = r["opencv"]
d = cv["sgbm_defaults"]["bad_fraction"]
print(f"aloe: bad pixels {100*e:.1f} %, densified {100*dense:.1f} % (OpenCV SGBM defaults, same range, {100*d:.1f} %), stages {r['stage_ms']}")
for name, m in cv.items():
    print(f"  opencv {name}: " + (m["skipped"] if "skipped" in m else f"bad {100*m['bad_fraction']:.1f} %, {m['ms']:.0f} ms"))
assert set(cv) == {"bm_defaults", "sgbm_defaults", "sgbm_sample", "sgbm_sample_3way", "sgbm_sample_hh", "sgbm_sample_wls"}, cv.keys()
assert e < 0.6 * d and dense < 0.45 * d and r["dense_errors"]["invalid_fraction"] == 0
assert all(e < m["bad_fraction"] for m in cv.values() if "skipped" not in m)
PY
# Bad input: each named, nothing written.
fail() { echo "FAIL: $*"; exit 1; }
if "$bin/uav-stereo" "$data/aloeL.jpg" "$data/left01.jpg" --rectified --disparity "$out/x.png" 2> "$out/err"; then fail "sizes"; fi
grep -q "1282x1110" "$out/err" && grep -q "640x480" "$out/err" || fail "size message: $(cat "$out/err")"
if "$bin/uav-stereo" "$out/none.png" "$data/aloeR.jpg" --rectified 2> "$out/err"; then fail "missing"; fi
grep -q "no such file" "$out/err" || fail "missing message"
if "$bin/uav-stereo" "$data/aloeL.jpg" "$data/aloeR.jpg" --calib "$out/none.yml" 2> "$out/err"; then fail "calib"; fi
grep -q "none.yml: no such file" "$out/err" || fail "calib message: $(cat "$out/err")"
echo "not an image" > "$out/bad.jpg"
if "$bin/uav-stereo" "$out/bad.jpg" "$data/aloeR.jpg" --rectified 2> "$out/err"; then fail "unreadable"; fi
grep -q "cannot read it as an image" "$out/err" || fail "unreadable message"
# A calibration for 640x480 cameras on the 1282x1110 pair: named, nothing written.
cat > "$out/rig.yml" <<'YML'
%YAML:1.0
---
image_width: 640
image_height: 480
K1: !!opencv-matrix {rows: 3, cols: 3, dt: d, data: [500, 0, 319.5, 0, 500, 239.5, 0, 0, 1]}
D1: !!opencv-matrix {rows: 1, cols: 5, dt: d, data: [0, 0, 0, 0, 0]}
K2: !!opencv-matrix {rows: 3, cols: 3, dt: d, data: [500, 0, 319.5, 0, 500, 239.5, 0, 0, 1]}
D2: !!opencv-matrix {rows: 1, cols: 5, dt: d, data: [0, 0, 0, 0, 0]}
R: !!opencv-matrix {rows: 3, cols: 3, dt: d, data: [1, 0, 0, 0, 1, 0, 0, 0, 1]}
T: !!opencv-matrix {rows: 3, cols: 1, dt: d, data: [-0.12, 0, 0]}
YML
if "$bin/uav-stereo" "$data/aloeL.jpg" "$data/aloeR.jpg" --calib "$out/rig.yml" --disparity "$out/y.png" 2> "$out/err"; then fail "calib size"; fi
grep -q "640x480" "$out/err" || fail "calib size message: $(cat "$out/err")"
[ ! -e "$out/x.png" ] && [ ! -e "$out/y.png" ] || fail "a file was written for bad input"
# The same calibration on a pair of its size works (rectifies, then matches).
"$bin/uav-stereo" "$data/left01.jpg" "$data/right01.jpg" --calib "$out/rig.yml" --disparity "$out/z.png" > /dev/null
[ -s "$out/z.png" ] || fail "no disparity for a fitting calibration"
# Calibrate opencv-doc's 13 real pairs (9x6 corners, 1 unit squares), then rectify and match one.
pairs=()
for i in 01 02 03 04 05 06 07 08 09 11 12 13 14; do pairs+=("$data/left$i.jpg" "$data/right$i.jpg"); done
"$bin/uav-stereo-calibrate" --board 9x6 --square 1 --out "$out/doc.yml" "${pairs[@]}" | tee "$out/calib.txt"
grep -q "13 of 13 pairs" "$out/calib.txt" || fail "calibration used too few pairs"
"$bin/uav-stereo" "$data/left01.jpg" "$data/right01.jpg" --calib "$out/doc.yml" --disparity "$out/doc.png" > /dev/null
[ -s "$out/doc.png" ] || fail "no disparity from the calibrated pair"
if "$bin/uav-stereo-calibrate" --out "$out/bad.yml" "$data/left01.jpg" 2> "$out/err"; then fail "odd image count"; fi
[ ! -e "$out/bad.yml" ] || fail "calibration written for bad input"
echo "uav-stereo: ok"
