#!/usr/bin/env bash
# Integration test: every camera and every vision algorithm in one flight. uav-onboard --sim over
# whole_suite.scene.json with x650_whole_suite.params and a headless uav-gcs whose script flies
# it and checks each algorithm publishes and every worker stays healthy (the survey stitcher runs
# too, idle without a survey: integration.survey_mission flies one); then the vehicle's exit
# line must count pairs from each stereo algorithm and frames from the gimbal.
# Usage: whole_suite.sh BIN_DIR SCRIPT SCENE PARAMS
set -euo pipefail
bin=$1 script=$2 scene=$3 params=$4
ONBOARD_ARGS="--scene $scene --params $params"
source "$(dirname "$0")/sim_and_gcs.sh"
run_sim_and_gcs "$bin" max itest "$script" 400
[ "$status" -eq 0 ] || { echo "FAIL: GCS script"; exit 1; }
for what in "stereo pairs" "active stereo pairs" "visual odometry pairs" "gimbal frames"; do
  grep -q "[1-9][0-9]* $what" "$work/onboard.log" || { echo "FAIL: no $what in the exit line"; exit 1; }
done
echo "PASS: the whole suite ran in one flight"
