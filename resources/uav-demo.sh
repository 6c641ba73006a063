#!/usr/bin/env bash
# Main job: the full survey mission in the simulator (issue 7 item 9). uav-onboard flies the
# simulated quadrotor over the village scene with its cameras; the GCS plans a survey on the
# map, uploads it, arms and starts it (take-off, zig-zag with capture, return home, land). The
# vehicle stitches the map while it flies and streams tiles to the GCS's Live map panel; at
# landing it offers the finished map, which the GCS downloads (chunked, SHA-256 verified) into
# ./maps. The script prints a line per step and a summary; exit 0 only if every step passed.
#  - With a display: in the GCS window, so you watch the flight, the video and the map grow.
#  - Without one (or with --headless): the same mission headless. As root it runs in a private
#    network namespace so no LCM traffic leaves the machine.
# With --ulion the survey is flown by U-Lion, the tail-sitter (resources/vehicles/ulion.params):
# a larger block planned for its cruise and turns, the vertical take-off, the survey on the wing,
# the vertical landing at home.
set -euo pipefail
bin=$(cd "$(dirname "$0")" && pwd)
usage="usage: uav-demo [--headless] [--ulion] [--help] [--version]"
mode=window ulion=0
for arg in "$@"; do
  case $arg in
    --headless) mode=headless ;;
    --ulion) ulion=1 ;;
    -h|--help)
      cat <<HELP
uav-demo: the main job. The simulated vehicle flies a survey over the village while the GCS
plans, uploads and starts it, watches the map grow and downloads the finished map.
$usage
  --headless  no window (the default without a display); as root, in a private network namespace
  --ulion     fly the survey with U-Lion, the tail-sitter, on its wing
Logs go to \$UAV_LOG_DIR (./flight-logs), maps to \$UAV_MAP_DIR (./maps), the signing key is
\$UAV_KEY (./uav.key, made on the first run).
HELP
      exit 0 ;;
    --version) echo "uav-demo $("$bin/uav-keygen" --version | cut -d' ' -f2-)"; exit 0 ;;
    *) echo "uav-demo: unknown option '$arg' ($usage)" >&2; exit 2 ;;
  esac
done
# The shipped data: installed beside the programs (PREFIX/share/uav) or in the source tree.
share="$bin/../share/uav"
[ -d "$share/scenes" ] || share="@PROJECT_SOURCE_DIR@/resources"  # filled in by CMake
[ -z "${DISPLAY:-}" ] && mode=headless
if [ "$mode" = headless ] && [ "$(id -u)" = 0 ] && [ "${UAV_IN_NETNS:-}" != 1 ] && command -v unshare >/dev/null; then
  exec env UAV_IN_NETNS=1 unshare -n "$0" --headless "$@"
fi
if [ "${UAV_IN_NETNS:-}" = 1 ]; then
  ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo
fi
logs=${UAV_LOG_DIR:-$PWD/flight-logs}
maps=${UAV_MAP_DIR:-$PWD/maps}
scene="$share/scenes/survey_village.scene.json"
mkdir -p "$logs" "$maps"
# The signing key the vehicle and the GCS share (made once, kept beside the logs; see docs/user-guide/signing.md).
key=${UAV_KEY:-$PWD/uav.key}
[ -e "$key" ] || "$bin/uav-keygen" "$key"
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
speed=2; [ "$mode" = headless ] && speed=8
vehicle=(); demo=--demo; who="the simulated vehicle"
if [ $ulion = 1 ]; then
  vehicle=(--params "$share/vehicles/ulion.params"); demo=--demo-ulion; who="U-Lion, the simulated tail-sitter,"
fi
echo "uav-demo: starting $who over the village (speed x$speed, logs in $logs)"
"$bin/uav-onboard" --sim --speed "$speed" --lcm-url "$url" --key "$key" --log-dir "$logs" --scene "$scene" "${vehicle[@]}" > "$logs/onboard.txt" 2>&1 &
onboard=$!
trap 'kill $onboard 2>/dev/null || true; wait $onboard 2>/dev/null || true' EXIT
status=0
if [ "$mode" = window ]; then
  "$bin/uav-gcs" "$demo" --lcm-url "$url" --key "$key" --download-dir "$maps" || status=$?
else
  echo "uav-demo: no display, running the survey mission headless"
  "$bin/uav-gcs" --headless "$demo" --lcm-url "$url" --key "$key" --download-dir "$maps" || status=$?
fi
echo "uav-demo: flight log $(ls -t "$logs"/flight_*.csv 2>/dev/null | head -1)"
echo "uav-demo: map saved as $(ls -t "$maps"/map_*.tif 2>/dev/null | head -1) (GeoTIFF; PNG + world file and KML beside it)"
[ $status -eq 0 ] && echo "uav-demo: PASSED" || echo "uav-demo: FAILED (exit $status)"
exit $status
