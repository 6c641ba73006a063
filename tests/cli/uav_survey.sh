#!/usr/bin/env bash
# uav-survey end to end: plans the shipped L-shaped area, writes every output, and the files read
# back; a plan that cannot give the front overlap and a bad polygon are refused with the reason
# and write nothing.
# Usage: uav_survey.sh BIN_DIR RESOURCE_DIR
set -euo pipefail
bin=$1 res=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/uav-survey" --polygon-file "$res/areas/village_l.area" --home 1.2966,103.7764,15 --altitude 30 \
  --plan "$work/s.plan" --wpl "$work/s.waypoints" --captures "$work/c.csv" --picture "$work/p.png" > "$work/report.json"
python3 - "$work" <<'PY'
import csv, json, sys
w = sys.argv[1]
r = json.load(open(f"{w}/report.json"))
assert r["ok"] and r["altitude_m"] == 30 and abs(r["gsd_cm_per_px"] - 6.25) < 1e-9, r
plan = json.load(open(f"{w}/s.plan"))
survey = [i for i in plan["mission"]["items"] if i["type"] == "ComplexItem"][0]
assert survey["complexItemType"] == "survey" and len(survey["polygon"]) == 6
assert abs(survey["TransectStyleComplexItem"]["CameraCalc"]["DistanceToSurface"] - 30) < 1e-9
wpl = open(f"{w}/s.waypoints").read().splitlines()
assert wpl[0] == "QGC WPL 110" and all(len(l.split("\t")) == 12 for l in wpl[1:])
rows = list(csv.DictReader(open(f"{w}/c.csv")))
assert len(rows) == r["images"], (len(rows), r["images"])
print(f"ok: {r['lines']} lines, {r['images']} images, {len(wpl) - 1} WPL lines, flight {r['flight_time_s']:.0f} s")
PY
test -s "$work/p.png"
# A fixed wing's plan (U-Lion at 12 m/s, 30 m turns): the same lines, flown at least 60 m apart.
"$bin/uav-survey" --polygon-file "$res/areas/village_l.area" --altitude 30 --speed 12 --turn-radius 30 --turnaround 60 \
  --captures "$work/wing.csv" > "$work/wing.json"
python3 - "$work" <<'PY'
import csv, json, sys
w = sys.argv[1]
r, wing = json.load(open(f"{w}/report.json")), json.load(open(f"{w}/wing.json"))
assert wing["turn_radius_m"] == 30 and wing["tight_turns"] == 0 and wing["lines"] == r["lines"], wing
lines = []
for row in csv.DictReader(open(f"{w}/wing.csv")):
    if not lines or lines[-1][0] != row["line"]:
        lines.append((row["line"], float(row["north_m"]), float(row["east_m"])))
gaps = [abs(b[2] - a[2]) for a, b in zip(lines, lines[1:])]
assert len(lines) == r["lines"] and min(gaps) >= 60 - 1e-6, gaps
print(f"fixed wing: {len(lines)} lines, at least {min(gaps):.0f} m between consecutive ones")
PY
# Too fast for the front overlap at 1 Hz: exit 2, the fix proposed, no mission written.
status=0
"$bin/uav-survey" --polygon-file "$res/areas/village_l.area" --altitude 30 --rate 1 --speed 12 \
  --plan "$work/fast.plan" > /dev/null 2> "$work/err.txt" || status=$?
[ $status -eq 2 ] || { echo "FAIL: expected exit 2, got $status"; exit 1; }
grep -q "fly at 7.5 m/s or slower" "$work/err.txt" || { echo "FAIL: no speed proposed"; cat "$work/err.txt"; exit 1; }
[ ! -e "$work/fast.plan" ] || { echo "FAIL: a mission was written"; exit 1; }
# A bowtie is refused naming the crossing edges.
status=0
"$bin/uav-survey" --polygon "1.2968,103.7766 1.2975,103.7776 1.2968,103.7776 1.2975,103.7766" --altitude 20 \
  --plan "$work/bow.plan" > /dev/null 2> "$work/err.txt" || status=$?
[ $status -eq 1 ] && grep -q "self-intersecting: edges 0 and 2 cross" "$work/err.txt" \
  || { echo "FAIL: bowtie not refused properly (exit $status)"; cat "$work/err.txt"; exit 1; }
[ ! -e "$work/bow.plan" ]
echo "ok: refusals"
