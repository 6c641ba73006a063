#!/usr/bin/env bash
# Integration: the GCS link is lost in the middle of a survey. The vehicle must fail safe (hold,
# return home, land) and the onboard stitcher must still write the map of what it captured.
# Usage: link_loss_survey.sh BIN_DIR SCRIPT
set -euo pipefail
bin=$1 script=$2
source "$(dirname "$0")/sim_and_gcs.sh"
map_written() { ls "$work"/log/maps_*/map_1.tif > /dev/null 2>&1; }
# The survey needs the downward camera only: obs_enable=0 leaves the stereo pair unrendered (the
# obstacle flights test obstacles), which halves the vehicle's CPU.
ONBOARD_ARGS="--scene $(dirname "$0")/../../resources/scenes/survey_village.scene.json --param obs_enable=0"
run_sim_and_gcs "$bin" 4 linklosssurvey "$script" 120 150 map_written
[ $status -eq 0 ] || exit $status
map_written || { echo "no map written after the link loss"; exit 1; }
python3 - "$work"/log/flight_*.csv "$work"/log/captures_*/captures.csv <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
captures = list(csv.DictReader(open(sys.argv[2])))
tasks = []
for r in rows:
    k = int(float(r["task"]))
    if not tasks or tasks[-1] != k: tasks.append(k)
i = tasks.index(6)  # the mission
assert tasks[i:i + 5] == [6, 2, 7, 4, 0], f"task sequence after the mission {tasks[i:]} (want mission, hover, return, land, idle)"
assert rows[-1]["armed"] == "0"
assert len(captures) > 5, f"{len(captures)} captures"
print(f"link loss mid-survey: {len(captures)} captures, tasks {tasks[i:i + 5]}, map written after landing")
PY
