#!/usr/bin/env bash
# Integration test: the survey planned and uploaded in the GCS (headless, mouse on the map) is
# flown by uav-onboard --sim over LCM in a private network namespace. The flight log must show
# the vehicle at the survey altitude, across the whole area, whenever the camera was capturing.
# Usage: survey_mission.sh BIN_DIR SCRIPT
set -euo pipefail
bin=$1 script=$2
source "$(dirname "$0")/sim_and_gcs.sh"
# The village scene's downward camera runs on the simulated clock: previews to the GCS, and
# captures to the log directory while the mission's camera is on, and depth from motion on it.
# The survey is what is tested here: the forward pair's obstacles are off (integration.main_job
# flies the survey with every worker on).
ONBOARD_ARGS="--scene $(dirname "$0")/../../resources/scenes/survey_village.scene.json --param obs_enable=0"
# --speed 8 is an upper bound: the vision runs on the simulated clock, so beside another test on
# two cores the 125 s mission takes a few minutes of wall time.
run_sim_and_gcs "$bin" 8 survey "$script" 420
[ $status -eq 0 ] || exit $status
python3 - "$work"/log/flight_*.csv <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["capturing"] == "1"]
assert rows, "no rows with the camera capturing"
alt = [-float(r["z"]) for r in rows]
north = [float(r["x"]) for r in rows]
east = [float(r["y"]) for r in rows]
assert 9.7 < min(alt) and max(alt) < 10.3, f"altitude {min(alt):.2f}..{max(alt):.2f} m while capturing, planned 10 m"
# The area spans 8..30 m north and -15..15 m east: the lines must reach across it.
assert min(east) < -9 and max(east) > 9 and min(north) < 14 and max(north) > 24, (min(east), max(east), min(north), max(north))
print(f"flight log: {len(rows)} rows capturing, altitude {min(alt):.2f}..{max(alt):.2f} m, east {min(east):.1f}..{max(east):.1f} m, "
      f"north {min(north):.1f}..{max(north):.1f} m")
PY
# Survey captures: one JPEG per row of captures.csv, 5 Hz on the simulated clock, taken at the
# survey altitude.
python3 - "$work"/log/captures_*/ <<'PY'
import csv, os, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(d, "captures.csv"))))
assert len(rows) > 50, f"only {len(rows)} captures"
for r in rows:
    data = open(os.path.join(d, r["file"]), "rb").read()
    assert data[:2] == b"\xff\xd8" and len(data) > 10000, r["file"]
dt = [(int(b["utime"]) - int(a["utime"])) / 1e6 for a, b in zip(rows, rows[1:])]
steady = sorted(dt)[len(dt) // 2]
assert abs(steady - 0.2) < 1e-6, f"median capture interval {steady} s, planned 0.2 s"
alt = [-float(r["down_m"]) for r in rows]
assert 9.5 < min(alt) and max(alt) < 10.5, (min(alt), max(alt))
print(f"captures: {len(rows)} images, median interval {steady:.3f} s, altitude {min(alt):.2f}..{max(alt):.2f} m")
PY
# The onboard map: written at landing, geo-referenced over the surveyed area (8..30 m north,
# -15..15 m east of home, seen from 10 m: the footprint adds ~5 m around the lines).
python3 - "$work"/log/maps_*/ "$work"/log/captures_*/session.json <<'PY'
import json, math, os, sys
d, session = sys.argv[1], json.load(open(sys.argv[2]))
for ext in ("tif", "png", "pgw", "prj", "kml"):
    path = os.path.join(d, "map_1." + ext)
    assert os.path.getsize(path) > 50, path
png = open(os.path.join(d, "map_1.png"), "rb").read()
assert png[:8] == b"\x89PNG\r\n\x1a\n"
width, height = int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
a, _, _, e, lon, lat = (float(x) for x in open(os.path.join(d, "map_1.pgw")).read().split())
home = session["home"]
m_lat = 111132.954 - 559.822 * math.cos(2 * math.radians(home["latitude_deg"]))
m_lon = 111412.84 * math.cos(math.radians(home["latitude_deg"]))
west = (lon - home["longitude_deg"]) * m_lon
north = (lat - home["latitude_deg"]) * m_lat
east = west + width * a * m_lon
south = north + height * e * m_lat
assert 28 < north < 40 and -25 < west < -14 and 14 < east < 25 and 0 < south < 9, (north, south, west, east)
print(f"map: {width}x{height} px, north {north:.1f} m, south {south:.1f} m, west {west:.1f} m, east {east:.1f} m")
PY
# The downloaded files are byte-identical to the onboard ones.
for f in "$work"/log/maps_*/map_1.*; do
  cmp "$f" "$work/downloads/$(basename "$f")"
done
echo "download: $(ls "$work/downloads" | tr '\n' ' ')identical to the onboard map"
# Replay: the onboard event log played into a headless GCS (no bus) shows the same flight: the
# altitude series sample for sample where the live GCS had it, and the same live-map tiles.
tiles=$(grep -o 'livemap.received = [0-9]*' "$work/gcs.log" | tail -1 | grep -o '[0-9]*$')
[ -n "$tiles" ] || { echo "no live tile count in the GCS output"; exit 1; }
cat > "$work/replay.gcs" <<GCS
wait_until vehicles >= 1 timeout 10
seek 100000
wait_until replay.position > 10 timeout 10
assert livemap.received == $tiles
tick alt
set plot:from 0
set plot:to 100000
set plot:file replay_alt.csv
click plot:export
wait_until log contains replay_alt.csv timeout 10
GCS
(cd "$work" && scaled_timeout 120 "$bin/uav-gcs" --headless --replay "$(ls "$work"/log/events_*.lcmlog)" --script "$work/replay.gcs") \
  | tee "$work/replay.log"
if grep -q "damaged" "$work/replay.log"; then echo "the log of a clean flight was read as damaged"; exit 1; fi
python3 - "$work/live_alt.csv" "$work/replay_alt.csv" <<'PY'
import csv, sys
live = [(float(r["t"]), float(r["STATE.alt"])) for r in csv.DictReader(open(sys.argv[1]))]
replay = [(float(r["t"]), float(r["STATE.alt"])) for r in csv.DictReader(open(sys.argv[2]))]
assert len(live) > 1000 and len(replay) >= len(live), (len(live), len(replay))
# Both plot from their own first sample: find the offset where the live series starts, by its
# first 200 values (the vehicle is climbing or flying then: they are not all alike).
head = [a for _, a in live[:200]]
values = [a for _, a in replay]
starts = [i for i in range(len(replay) - 200) if values[i:i + 200] == head]
assert starts, "the live altitude series is not in the replay"
offset = replay[starts[0]][0] - live[0][0]
# In order, each live sample must be the next replayed sample at its time (times can repeat when
# the estimate did not advance); the log may end a moment before the live GCS stopped listening.
j, missing, after_end = starts[0], [], 0
for t, a in live:
    if t + offset > replay[-1][0] + 1e-6:
        after_end += 1
        continue
    while j < len(replay) and replay[j][0] < t + offset - 1e-6:
        j += 1
    while j < len(replay) and abs(replay[j][0] - t - offset) < 1e-6 and replay[j][1] != a:
        j += 1
    if j < len(replay) and abs(replay[j][0] - t - offset) < 1e-6:
        j += 1
    else:
        missing.append(t)
assert not missing, f"{len(missing)} live samples not in the replay, first at t = {missing[0]}"
assert after_end < 10, f"{after_end} live samples after the log's end"
print(f"replay: {len(live)} live altitude samples found sample for sample among {len(replay)} replayed")
PY
