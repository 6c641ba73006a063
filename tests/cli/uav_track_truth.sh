#!/usr/bin/env bash
# uav-track --truth on the real sequences of ../shared/data/tracking_real (OTB's Car4 and jogging at
# 30 frames/s, UAV123's person11 at 10): the score is OTB's (success AUC over IoU thresholds,
# precision at 20 px), and each tracker's score is held at the value measured when this test was
# written, so a change to a tracker or to the scoring shows.
# Usage: uav_track_truth.sh BIN_DIR DATA_DIR
set -uo pipefail
bin=$1 data=$2/tracking_real
fail() { echo "FAIL: $*"; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
[ -d "$data/jogging/img" ] || fail "no real sequences in $data"
declare -A scored  # "TRACKER SEQUENCE TRUTH" -> "auc precision method": each run once
fps() { [ "$1" = person11 ] && echo 10 || echo 30; }
score() {  # TRACKER SEQUENCE TRUTH -> scored[...]; the boxes in $out/TRACKER_SEQUENCE.csv
  local box
  box=$(head -1 "$data/$2/$3" | tr -d '\r' | tr '\t ' ',,')
  scored["$1 $2 $3"]=$("$bin/uav-track" "$data/$2/img" --box "$box" --tracker "$1" --fps "$(fps "$2")" --truth "$data/$2/$3" \
    --out "$out/$1_$2.csv" 2> /dev/null |
    python3 -c 'import json, sys; r = json.load(sys.stdin); t = r["truth"]; print(t["success_auc"], t["precision_20px"], r["method"])') ||
    fail "$1 on $2/$3 gave no score"
}
auc() { local s=${scored["$1 $2 $3"]}; echo "${s%% *}"; }
check() {  # TRACKER SEQUENCE TRUTH AUC: the measured AUC within 0.5 points
  score "$1" "$2" "$3"
  echo "$1 $2/$3: success AUC, precision at 20 px and method: ${scored["$1 $2 $3"]} (expected AUC $4)"
  python3 -c "import sys; sys.exit(abs($(auc "$1" "$2" "$3") - $4) > 0.5)" || fail "$1 on $2: AUC $(auc "$1" "$2" "$3"), expected $4"
}
check camshift jogging groundtruth_rect.1.txt 24.8
check csrt jogging groundtruth_rect.1.txt 69.6
check csrt jogging groundtruth_rect.2.txt 77.4
check csrt Car4 groundtruth_rect.txt 82.0
check dcf jogging groundtruth_rect.2.txt 82.0
# The default picks the correlation filter for the runners (a shirt's colour covers 6 % of the box)
# and the grey car (no colour), where CamShift drifts or refuses; on each sequence it scores at
# least CSRT's AUC.
check auto jogging groundtruth_rect.1.txt 72.5
check auto jogging groundtruth_rect.2.txt 82.0
check auto Car4 groundtruth_rect.txt 83.9
# A person seen from a drone, running across grass: CSRT's box follows his size a little better
# (ours, with the aspect filter, 64.0 against 64.9; DSST's scale alone shrank it to about 0.75 of
# him, 62.6), and ours does not drift onto the grass.
check csrt person11 groundtruth_rect.txt 64.9
check auto person11 groundtruth_rect.txt 64.0
for run in "jogging groundtruth_rect.1.txt" "jogging groundtruth_rect.2.txt" "Car4 groundtruth_rect.txt"; do
  set -- $run
  ours=$(auc auto "$1" "$2") theirs=$(auc csrt "$1" "$2")
  python3 -c "import sys; sys.exit($ours < $theirs)" || fail "auto scores AUC $ours on $1/$2, under CSRT's $theirs"
done
# Drift is loss: on person11 the default never says "tracking" with its box off the person (IoU
# under 0.05) for longer than the loss time, 0.3 s (3 frames at 10 frames/s). Before the colour
# model it tracked grass from frame 137 to the end with confidence 1.
python3 - "$out/auto_person11.csv" "$data/person11/groundtruth_rect.txt" << 'EOF' || fail "the default tracked grass on person11"
import sys
rows = [l.strip().split(",") for l in open(sys.argv[1]).readlines()[1:]]
truth = [[float(v) for v in l.replace("\t", ",").split(",")] for l in open(sys.argv[2]) if l.strip()]
run = longest = 0
for r, t in zip(rows, truth):
    x, y, w, h = map(float, r[1:5])
    ix = max(0.0, min(x + w, t[0] + t[2]) - max(x, t[0]))
    iy = max(0.0, min(y + h, t[1] + t[3]) - max(y, t[1]))
    iou = ix * iy / (w * h + t[2] * t[3] - ix * iy)
    run = run + 1 if r[6] == "tracking" and iou < 0.05 else 0
    longest = max(longest, run)
print(f"person11: longest run of frames tracking off the person: {longest}")
sys.exit(longest > 3)
EOF
method=${scored["auto Car4 groundtruth_rect.txt"]##* }
[ "$method" = dcf ] || fail "auto tracked the grey car with $method, not dcf"
box=$(head -1 "$data/Car4/groundtruth_rect.txt" | tr -d '\r')
"$bin/uav-track" "$data/Car4/img" --box "$box" --tracker camshift > /dev/null 2>&1 && fail "CamShift accepted the grey car"
echo ok
