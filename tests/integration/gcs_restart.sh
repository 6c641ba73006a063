#!/usr/bin/env bash
# Integration test: the GCS restarted mid-mission (inside netns.sh). One GCS uploads a survey and
# starts it, then exits; the vehicle flies on (the link-loss failsafe's timeout is longer than the
# gap); a new GCS process with the same key and name reconnects, shows the live state and watches
# the mission end where it should.
# Usage: gcs_restart.sh BIN_DIR
set -euo pipefail
bin=$1
dir=$(cd "$(dirname "$0")" && pwd)
source "$dir/sim_and_gcs.sh"
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
# The survey needs the downward camera only: obs_enable=0 leaves the stereo pair unrendered.
ONBOARD_ARGS="--scene $dir/../../resources/scenes/survey_village.scene.json --param obs_enable=0"
# Run once, as soon as the first GCS has exited (run_sim_and_gcs's until-function).
resume() {
  (cd "$work" && scaled_timeout 300 "$bin/uav-gcs" --headless --name operator --lcm-url "$url" --key "$key" \
    --script "$dir/gcs_restart_resume.gcs") > "$work/gcs2.log" 2>&1 || true
  echo "--- the restarted GCS"
  cat "$work/gcs2.log"
}
run_sim_and_gcs "$bin" 4 operator "$dir/gcs_restart_upload.gcs" 120 300 resume
[ "$status" -eq 0 ] || { echo "FAIL: the first GCS"; exit 1; }
grep -q "passed, 0 failed" "$work/gcs2.log" || { echo "FAIL: the restarted GCS"; exit 1; }
echo "gcs_restart: the restarted GCS showed the mission and watched it end"
