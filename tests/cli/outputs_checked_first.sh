#!/usr/bin/env bash
# Every program that writes files refuses an output it cannot write when its command line is read,
# before any work, naming the option and the folder: a run of an hour does not end in "cannot
# write". Each runs with only the bad output (the check comes before the other options' own).
# Usage: outputs_checked_first.sh BIN_DIR
set -uo pipefail
bin=$1
missing=/nonexistent_uav_folder
fail=0
while read -r program option file; do
  [ -z "$program" ] && continue
  # At once: a program still running after 10 s had started its work (timeout's exit 124).
  out=$(timeout 10 "$bin/$program" "$option" "$missing/$file" 2>&1)
  rc=$?
  if [ $rc -eq 0 ] || [ $rc -eq 124 ] || ! grep -q -- "$option: no folder $missing for $missing/$file" <<<"$out"; then
    echo "FAIL: $program $option (exit $rc): $out"
    fail=1
  else
    echo "ok: $program $option"
  fi
done <<'LIST'
uav-render --out frame
uav-sysid --plot fit.png
uav-sysid --json fit.json
uav-vo --out poses.txt
uav-vo-eval --plot track.png
uav-vo-eval --json report.json
uav-active-stereo --csv heights.csv
uav-monodepth --out depth.csv
uav-stereo-error --out errors.json
uav-stereo-error --plot errors.png
uav-stereo-calibrate --out calib.yml
uav-track --out boxes.csv
uav-stitch --out map
uav-stitch --report report.json
uav-survey --plan s.plan
uav-survey --wpl s.waypoints
uav-survey --captures c.csv
uav-survey --picture p.png
uav-avoid-bench --json cells.json
uav-ulion-bench --json report.json
uav-ulion-bench --plot transitions.png
LIST
exit $fail
