#!/usr/bin/env bash
# uav-powerlines --truth on the 50 real aerial photos of ../shared/data/powerlines_real (PLD-UAV,
# mountain scenes, pixel masks), with each segment detector, and on the 40 urban photos of
# ../shared/data/powerlines_real_urban: precision, recall and F1 with the data set's boundary matching,
# beside the LSD-only baseline, held at the values measured when this test was written (F1 within
# 0.3 points, and 5 points above the baseline), so a change to the detector or to the scoring shows. Also: false wires on
# opencv-doc's photos without wires, at most today's count, and a truth folder missing a mask is
# named; the report's per-photo figures find the photos that fail. Usage: uav_powerlines_truth.sh BIN_DIR DATA_DIR
set -uo pipefail
bin=$1 data=$2/powerlines_real docs=/usr/share/doc/opencv-doc/examples/data
fail() { echo "FAIL: $*"; exit 1; }
[ -d "$data/images" ] || fail "no real photos in $data"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Each segment detector: EDLines (the detector's default) and LSD (the vehicle's, pwl_segments 0).
for segments in edlines lsd; do
"$bin/uav-powerlines" "$data/images" --truth "$data/truth" --segments $segments > "$work/report.json" 2> "$work/stderr" || fail "exit $?: $(cat "$work/stderr")"
python3 - "$work/report.json" $segments <<'PY' || fail "scores moved ($segments)"
import json, sys
r = json.load(open(sys.argv[1]))
segments = sys.argv[2]
t = r["truth"]
ours, lsd = t["ours"], t["lsd_baseline"]
print(f"{segments}: ours F1 {ours['f1']:.2f} (P {ours['precision']:.3f} R {ours['recall']:.3f}), LSD-only F1 {lsd['f1']:.2f}")
assert r["processed"] == 50 and r["segments"] == segments, r
assert abs(ours["f1"] - {"edlines": 98.63, "lsd": 98.73}[segments]) < 0.3, ours
assert abs(lsd["f1"] - 93.38) < 0.3, lsd
assert ours["f1"] > lsd["f1"] + 4.5
# Each photo's own figures, to find the hard ones: one entry per photo, and the ones that score
# under F1 90 (two wires a few pixels apart over forest; a faint wire over a hillside) are the
# ones the documentation names.
per = t["per_image"]
assert len(per) == 50 and len({p["image"] for p in per}) == 50, len(per)
assert all(0 <= p["precision"] <= 1 and 0 <= p["recall"] <= 1 for p in per)
worst = sorted(p["image"] for p in per if p["f1"] < 90)
print("photos under F1 90:", worst)
assert worst == ["12.jpg", "195.jpg"], worst
PY
# Photos without wires (a building's facade, a butterfly, fruit, a face, paintings, aerial
# photos, graffiti, a fish, a board): false wires per image, at most what was measured.
"$bin/uav-powerlines" $docs/building.jpg $docs/butterfly.jpg $docs/fruits.jpg $docs/baboon.jpg $docs/home.jpg \
  $docs/messi5.jpg $docs/starry_night.jpg $docs/aero1.jpg $docs/aero3.jpg $docs/graf1.png $docs/graf3.png \
  $docs/HappyFish.jpg $docs/orange.jpg $docs/apple.jpg $docs/board.jpg $docs/smarties.png $docs/notes.png \
  --out "$work/none" --segments $segments > "$work/none.json" 2> /dev/null || fail "the photos without wires were not all processed"
python3 - "$work/none.json" $segments <<'PY' || fail "more false wires than measured ($segments)"
import json, sys
r = json.load(open(sys.argv[1]))
print(f"photos without wires: {r['wires']} false wires on {r['processed']} photos ({r['wires_per_image']:.2f} per photo)")
assert r["processed"] == 17 and r["wires"] <= {"edlines": 16, "lsd": 14}[sys.argv[2]]
PY
done
# The urban photos (roofs, roads, facades under the wires), with EDLines. The learned verifier was
# trained on these photos and the mountain ones, so both figures here are on its training data;
# cli.uav_powerlines_train holds the cross-validated ones, and the photos without wires above
# were never seen in training.
urban=$2/powerlines_real_urban
"$bin/uav-powerlines" "$urban/images" --truth "$urban/truth" > "$work/urban.json" 2> /dev/null || fail "the urban photos were not all processed"
python3 - "$work/urban.json" <<'PY' || fail "urban scores moved"
import json, sys
t = json.load(open(sys.argv[1]))["truth"]
print(f"urban: ours F1 {t['ours']['f1']:.2f}, LSD-only F1 {t['lsd_baseline']['f1']:.2f}")
assert abs(t["ours"]["f1"] - 92.81) < 0.3 and t["ours"]["f1"] > t["lsd_baseline"]["f1"] + 5.0, t
PY
# A truth folder without the image's mask: named, nothing scored for it, exit 1.
mkdir "$work/empty_truth"
"$bin/uav-powerlines" "$data/images/12.jpg" --truth "$work/empty_truth" > /dev/null 2> "$work/err"
status=$?
[ $status -eq 1 ] || fail "exit $status for a missing mask, expected 1"
grep -q "truth .*12.png: missing or unreadable" "$work/err" || fail "the missing mask is not named: $(cat "$work/err")"
"$bin/uav-powerlines" "$data/images/12.jpg" > /dev/null 2>&1 && fail "no --out and no --truth was accepted"
echo "uav-powerlines --truth: scores held"
