#!/usr/bin/env bash
# Main job: a simulated vehicle and the GCS.
#  - With a display: uav-onboard --sim and the GCS window; fly it from the command bar.
#  - Without one (or with --headless): the GCS runs headless with the built-in demo flight
#    (takeoff, hover, goto, land), one line per step and a closing summary; exit 0 only if every
#    step passed. As root it runs in a private network namespace so no LCM traffic leaves.
set -euo pipefail
bin=$(cd "$(dirname "$0")" && pwd)
mode=window
{ [ -z "${DISPLAY:-}" ] || [ "${1:-}" = --headless ]; } && mode=headless
if [ "$mode" = headless ] && [ "$(id -u)" = 0 ] && [ "${UAV_IN_NETNS:-}" != 1 ] && command -v unshare >/dev/null; then
  exec env UAV_IN_NETNS=1 unshare -n "$0" --headless
fi
if [ "${UAV_IN_NETNS:-}" = 1 ]; then
  ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo
fi
logs=${UAV_LOG_DIR:-$PWD/flight-logs}
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
speed=1; [ "$mode" = headless ] && speed=4
echo "uav-demo: starting the simulated vehicle (speed x$speed, logs in $logs)"
"$bin/uav-onboard" --sim --speed "$speed" --lcm-url "$url" --log-dir "$logs" &
onboard=$!
trap 'kill $onboard 2>/dev/null || true; wait $onboard 2>/dev/null || true' EXIT
status=0
if [ "$mode" = window ]; then
  "$bin/uav-gcs" --lcm-url "$url" || status=$?
else
  echo "uav-demo: no display, running the GCS headless with the built-in demo flight"
  "$bin/uav-gcs" --headless --demo --lcm-url "$url" || status=$?
fi
echo "uav-demo: flight log $(ls -t "$logs"/flight_*.csv 2>/dev/null | head -1)"
[ $status -eq 0 ] && echo "uav-demo: PASSED" || echo "uav-demo: FAILED (exit $status)"
exit $status
