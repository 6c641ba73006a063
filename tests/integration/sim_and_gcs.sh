# Sourced by the integration tests: runs uav-onboard --sim and a headless uav-gcs script against
# it over LCM (inside netns.sh), then prints the vehicle's output.
# A failed script's log/, onboard.log and gcs.log are copied to $UAV_FAILED_RUNS_DIR (default
# $TMPDIR/uav-failed-runs or /tmp/uav-failed-runs).
# Sets: work (temporary directory with log/, onboard.log and gcs.log, the GCS's output), key (the
# signing key both use), status
# (the GCS's exit code).
# Usage: run_sim_and_gcs BIN_DIR SPEED GCS_NAME SCRIPT TIMEOUT_S [LINGER_S UNTIL_FUNCTION]
# With LINGER_S, the vehicle keeps flying after the GCS exits, until UNTIL_FUNCTION succeeds or
# LINGER_S pass. Both limits are multiplied by UAV_TIMEOUT_SCALE (scaled_timeout.sh).
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/scaled_timeout.sh"
run_sim_and_gcs() {
  local bin=$1 speed=$2 name=$3 script=$4 limit=$5 linger=${6:-0} until=${7:-false}
  local url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
  work=$(mktemp -d)
  trap 'kill $(jobs -p) 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"' EXIT
  # A signing key for this test alone, shared by the vehicle and the GCS.
  key="$work/uav.key"
  "$bin/uav-keygen" "$key" > /dev/null
  # shellcheck disable=SC2086  # ONBOARD_ARGS: extra options, word-split on purpose
  "$bin/uav-onboard" --sim --speed "$speed" --vehicle-id UAV1 --lcm-url "$url" --key "$key" --log-dir "$work/log" ${ONBOARD_ARGS:-} \
    > "$work/onboard.log" 2>&1 &
  status=0
  # From inside the work directory: relative paths the script types (downloads) land there.
  (cd "$work" && scaled_timeout "$limit" "$bin/uav-gcs" --headless --name "$name" --lcm-url "$url" --key "$key" --script "$script") \
    > "$work/gcs.log" 2>&1 || status=$?
  cat "$work/gcs.log"
  local waited=0
  linger=$(scaled_seconds "$linger")
  while [ "$waited" -lt "$linger" ] && ! "$until"; do sleep 1; waited=$((waited + 1)); done
  kill %1 2>/dev/null || true
  wait || true
  echo "--- onboard output"
  cat "$work/onboard.log"
  # A failed run's flight log, events and outputs are kept (the work directory goes at exit):
  # a failure that does not come back is otherwise left with nothing to read.
  if [ "$status" -ne 0 ]; then
    local kept="${UAV_FAILED_RUNS_DIR:-${TMPDIR:-/tmp}/uav-failed-runs}/$(basename "$script" .gcs)-$(date +%Y%m%d-%H%M%S)-$$"
    mkdir -p "$kept" && cp -r "$work/onboard.log" "$work/gcs.log" "$kept/" &&
      { [ ! -d "$work/log" ] || cp -r "$work/log" "$kept/"; } &&
      echo "--- the failed run's logs are kept in $kept"
  fi
}
