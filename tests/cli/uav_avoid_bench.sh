#!/usr/bin/env bash
# uav-avoid-bench: one closed-loop flight through a seeded 1/49 field (perception in the loop),
# its per-flight and per-cell report, the picture in a folder that did not exist; bad arguments
# refused with the reason.
set -euo pipefail
bin=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$bin/uav-avoid-bench" --density 1/49 --speed 3 --seeds 2 --quiet --json "$out/r.json" --picture "$out/pictures/d49" \
  --trace "$out/trace" > "$out/stdout.json"
python3 - "$out" <<'PY'
import json, math, sys
out = sys.argv[1]
j = json.load(open(f"{out}/r.json"))
assert json.load(open(f"{out}/stdout.json")) == j["cell"]
assert open(f"{out}/pictures/d49/field_2.png", "rb").read(8) == b"\x89PNG\r\n\x1a\n"
f = j["flights"][0]
assert f["seed"] == 2 and f["success"], f
assert j["rig_roll_deg"] == 0 and j["wire_rig_roll_deg"] == 45, j
# The true clearance never under the body radius (0.5 m); the path near the shortest.
assert f["min_clearance_m"] >= 0.5 and f["path_m"] <= 1.15 * f["shortest_m"], f
for k in ("replan_p50_ms", "replan_p99_ms", "replan_cpu_p50_ms", "replan_cpu_p99_ms"):
    assert math.isfinite(f[k]) and f[k] >= 0, (k, f[k])
assert f["replan_cpu_p50_ms"] <= f["replan_p50_ms"] + 0.5, f
# The map's odometry frame holds steadier than N (measured 0.08 against 0.15 m on this seed).
assert 0 < f["nav_error_drift_3s_O_m"] < f["nav_error_drift_3s_N_m"] < 0.5, f
c = j["cell"]
assert c["flights"] == 1 and c["success_rate"] == 1.0, c
# The time lost against cruise, by cause: each part a time, together at least what the mean
# speed says was lost (flown time minus path over cruise) and no more than the time flown.
l = f["time_lost_s"]
parts = ("blocked", "last_4m", "start", "seen_free_limit", "other")
assert all(l[k] >= 0 for k in parts) and abs(sum(l[k] for k in parts) - l["total"]) < 1e-6, l
assert f["flown_s"] - f["path_m"] / 3.0 - 0.5 <= l["total"] < f["flown_s"], (f["flown_s"], f["path_m"], l)
assert l["last_4m"] > 0 and l["start"] > 0, l  # it accelerates after the goto and stops at the goal
assert c["time_lost_flights"] == 1 and c["time_flown_s"] == f["flown_s"] and c["time_lost_s"] == l, c
# Each wire passed within 3 m, with its least true clearance; the cell counts those at 1 m or more.
w = f["wire_clearances_m"]
assert all(0.5 <= x < 3.0 for x in w), w
assert c["wires_passed"] == len(w) and c["wires_passed_at_1m"] == sum(x >= 1.0 for x in w), (c, w)
# And each one's angle to the corridor's axis; those at 45 degrees or more run across it.
g = f["wire_angles_deg"]
assert len(g) == len(w) and all(0 <= x <= 90 for x in g), g
across = [x for x, a in zip(w, g) if a >= 45]
assert c["wires_across_passed"] == len(across) and c["wires_across_passed_at_1m"] == sum(x >= 1.0 for x in across), (c, w, g)
# The trace: a row every 0.1 s from the goto to the goal; the heading, course and climb rate
# agree with a flight north along the corridor at its altitude.
import csv
rows = list(csv.DictReader(open(f"{out}/trace/trace_2.csv")))
assert len(rows) > 10 * 0.5 * j["flights"][0]["path_m"] / 3.0, len(rows)
for r in rows:
    assert -180 <= float(r["yaw_deg"]) <= 180 and -180 <= float(r["course_deg"]) <= 180, r
    assert abs(float(r["climb_mps"])) < 3.0, r
    assert abs(float(r["pitch_deg"])) < 45 and abs(float(r["roll_deg"])) < 45, r
moving = [r for r in rows if float(r["speed_mps"]) > 1.0]
north = sorted(abs(float(r["course_deg"])) for r in moving)
assert north[len(north) // 2] < 30, north[len(north) // 2]
assert sorted(abs(float(r["yaw_deg"])) for r in moving)[len(moving) // 2] < 30
print("uav-avoid-bench: ok", json.dumps(f))
PY
# An obstacle layout of one's own (a scene file): a brick wall 8 m wide across the way and a pole
# behind it, flown from home to (24, 0) with the bench's pairs in place of the file's cameras.
cat > "$out/layout.json" <<'JSON'
{"name": "wall and pole", "seed": 4,
 "objects": [
   {"type": "box", "kind": "wall", "center_ned": [12, 0, -4], "size": [0.3, 8, 8], "material": "brick"},
   {"type": "cylinder", "kind": "pole", "base_ned": [18, 2.5, 0], "radius_m": 0.3, "height_m": 8, "material": "concrete"}],
 "cameras": {"downward": {"rate_hz": 5}}}
JSON
"$bin/uav-avoid-bench" --scene "$out/layout.json" --to 24,0 --speed 3 --quiet --json "$out/s.json" --picture "$out/scene_pictures" > /dev/null
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
j = json.load(open(f"{out}/s.json"))
assert j["scene"].endswith("layout.json") and j["goal_ne_m"] == [24, 0] and j["altitude_m"] == 4, j
f = j["flights"][0]
# The file's own seed; around the wall (the straight line runs through it), clear of both.
assert f["seed"] == 4 and f["success"] and f["min_clearance_m"] >= 0.5, f
assert 24.5 < f["shortest_m"] < 30 and f["path_m"] < 1.3 * f["shortest_m"], f
assert open(f"{out}/scene_pictures/field_4.png", "rb").read(8) == b"\x89PNG\r\n\x1a\n"
print("uav-avoid-bench --scene: ok", json.dumps(f))
PY
# A power line across the whole way, its two cables sagging to about the flight's height: there
# is no level way, so the path is not scored against one; the vehicle passes under or over with
# a metre from each cable.
"$bin/uav-avoid-bench" --scene "$(dirname "$0")/../../resources/scenes/avoid/power_line_across.scene.json" --to 30,0 --altitude 5 --speed 3 --json "$out/w.json" 2> "$out/w.err" > /dev/null
grep -q "no level way" "$out/w.err" || { echo "no level way not said:"; cat "$out/w.err"; exit 1; }
python3 - "$out" <<'PY'
import json, sys
j = json.load(open(f"{sys.argv[1]}/w.json"))
f = j["flights"][0]
assert f["success"] and f["shortest_m"] is None, f
assert len(f["wire_clearances_m"]) == 2 and min(f["wire_clearances_m"]) >= 1.0, f
assert all(a > 80 for a in f["wire_angles_deg"]), f
c = j["cell"]
assert c["path_over_shortest"] is None and 0 < c["speed_over_cruise"] <= 1, c
print("uav-avoid-bench power line: ok", json.dumps(f))
PY
refuse() {  # refuse EXPECTED_TEXT ARGS...
  local expected=$1
  shift
  if "$bin/uav-avoid-bench" --quiet "$@" > /dev/null 2> "$out/err"; then echo "accepted: $*"; exit 1; fi
  grep -qF -- "$expected" "$out/err" || { echo "wrong reason for $*:"; cat "$out/err"; exit 1; }
}
refuse "density must be in" --density 0
refuse "seeds must be A-B" --seeds 5-2
refuse "rig-roll" --rig-roll 120 --seeds 1
refuse "wire-rig-roll" --wire-rig-roll -91 --seeds 1
refuse "no_such_parameter" --param no_such_parameter=1 --seeds 1
touch "$out/file"
refuse "pictures" --seeds 1 --picture "$out/file/pictures"
# An output that cannot be written is refused before the flights (100 of them would take an hour).
start=$(date +%s)
refuse "--json: no folder $out/missing" --density 1/49 --speed 3 --seeds 1-100 --json "$out/missing/r.json"
[ $(( $(date +%s) - start )) -lt 20 ] || { echo "the missing --json folder was said only after the flights"; exit 1; }
echo "refusals: ok"
refuse "within the body radius" --scene "$out/layout.json" --to 12,0
refuse "not both" --scene "$out/layout.json" --to 24,0 --density 1/49
refuse "needs the goal" --scene "$out/layout.json"
refuse "must be N,E" --scene "$out/layout.json" --to 24
refuse "is for --scene" --density 1/49 --to 30,0
printf '{"objects": [' > "$out/broken.json"
refuse "is not JSON" --scene "$out/broken.json" --to 24,0
refuse "seeds must be" --seeds 2-x
refuse "not a finite number" --scene "$out/layout.json" --to 24,0 --altitude nan
refuse "not a finite number" --speed nan --seeds 1
refuse "density must be" --density 0x10
refuse "must be N,E" --scene "$out/layout.json" --to 24,0x1
echo "scene refusals: ok"
# --merge: a cell flown in parts scored as one. The shipped 1/25, 5 m/s cell in five files gives
# the figures its table states (100 of 100, clearance p5 1.50 / least 0.52 m, path 1.18 x,
# speed 0.50 x, planning CPU p99 6.0 ms per flight, 14.3 ms at worst, 270 wires at 1 m or more).
bench=$(dirname "$0")/../../resources/benchmarks
"$bin/uav-avoid-bench" --merge "$bench"/avoid_1-25_5mps_flatface_seeds{1-8,9-34,35-54,55-82,83-100}.json --json "$out/m.json" > "$out/m.out"
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
j = json.load(open(f"{out}/m.json"))
c = j["cell"]
assert json.load(open(f"{out}/m.out")) == c
assert c["flights"] == 100 and c["success_rate"] == 1.0 and c["failed_seeds"] == [], c
assert [f["seed"] for f in j["flights"]] == list(range(1, 101)) and j["speed"] == 5 and j["density"] == 0.04, j["speed"]
for key, want, within in (("clearance_p5_m", 1.50, 0.005), ("clearance_min_m", 0.52, 0.005), ("path_over_shortest", 1.18, 0.005),
                          ("speed_over_cruise", 0.50, 0.005), ("replan_cpu_p99_median_flight_ms", 6.0, 0.05),
                          ("replan_cpu_p99_worst_flight_ms", 14.3, 0.05)):
    assert abs(c[key] - want) <= within, (key, c[key])
assert c["wires_passed"] == 270 == c["wires_passed_at_1m"] and c["replan_cpu_p99_ms"] is None, c
# Those files were written before the time lost was kept: the cell says it sums none.
assert c["time_lost_flights"] == 0 and c["time_lost_s"]["total"] == 0, c
print("uav-avoid-bench --merge: ok")
PY
# A file that keeps the time lost gives it back through --merge; a broken one is refused by name.
"$bin/uav-avoid-bench" --merge "$out/r.json" > "$out/rm.out"
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
c, r = json.load(open(f"{out}/rm.out")), json.load(open(f"{out}/r.json"))["cell"]
for k in ("time_lost_flights", "time_flown_s", "time_lost_s"):
    assert c[k] == r[k], (k, c[k], r[k])
j = json.load(open(f"{out}/r.json"))
del j["flights"][0]["time_lost_s"]["start"]
json.dump(j, open(f"{out}/lost.json", "w"))
PY
# A failed flight makes the exit status 1 and is named; files of other courses, a seed twice and
# a file that is not the bench's are refused by name.
python3 - "$bench" "$out" <<'PY'
import json, sys
j = json.load(open(f"{sys.argv[1]}/avoid_1-25_5mps_flatface_seeds1-8.json"))
j["flights"][2]["success"] = False
json.dump(j, open(f"{sys.argv[2]}/failed.json", "w"))
PY
status=0
"$bin/uav-avoid-bench" --merge "$out/failed.json" > "$out/f.out" || status=$?
[ "$status" = 1 ] && python3 -c "import json,sys; assert json.load(open(sys.argv[1]))['failed_seeds'] == [3]" "$out/f.out"
refuse "seed 1 is in both" --merge "$bench/avoid_1-25_5mps_flatface_seeds1-8.json" "$out/failed.json"
refuse "another course or speed" --merge "$bench/avoid_1-25_5mps_flatface_seeds1-8.json" "$bench/avoid_1-49_5mps_seenbody_seeds1-30.json"
refuse "is not a uav-avoid-bench" --merge "$out/layout.json"
refuse "is not JSON" --merge "$out/broken.json"
refuse "excludes" --merge "$out/failed.json" --density 1/25
refuse "'time_lost_s' has no time 'start'" --merge "$out/lost.json"
echo "merge refusals: ok"
