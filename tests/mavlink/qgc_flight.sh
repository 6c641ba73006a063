#!/usr/bin/env bash
# The vehicle on MAVLink, end to end: uav-onboard flies uav-demo's survey in the simulator under
# the command of a QGroundControl-style client written with npm's node-mavlink
# (tests/mavlink/qgc_client.js: connect sequence, mission with fence and rally, bad input, arm,
# start, every item reached, landing, parameters, every frame signed), while our own GCS watches
# over LCM (watch.gcs) and changes a parameter the MAVLink side must see; the RTP/H.264 video on
# UDP 5600 is decoded by GStreamer into pictures.
# Usage: qgc_flight.sh BIN_DIR OUT_DIR [--window]   (inside netns.sh: LCM and UDP stay on this machine)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
passphrase="correct horse battery staple"
source "$here/prepare.sh"
rm -f video_*.gray mavlink_watch.png report.json
# The video as QGroundControl receives it: RTP/H.264 on UDP 5600, every decoded frame a raw
# grey image.
gst-launch-1.0 -q udpsrc port=5600 \
  caps="application/x-rtp,media=video,encoding-name=H264,payload=96,clock-rate=90000" \
  ! rtph264depay ! avdec_h264 ! videoconvert ! video/x-raw,format=GRAY8 \
  ! multifilesink location=video_%05d.gray \
  > gst.log 2>&1 &
gst=$!
# uav-demo's vehicle and scene; lean: the stereo pair's workers (obstacles, wires) and depth from
# motion are off, the survey camera, its video and the stitching stay.
"$bin/uav-onboard" --sim --speed 8 --lcm-url "$url" --key uav.key \
  --param obs_enable=0 --param pwl_enable=0 --param mdp_camera=0 \
  --scene "$here/../../resources/scenes/survey_village.scene.json" --mavlink udp:127.0.0.1:14550 > onboard.log 2>&1 &
onboard=$!
# Our GCS, headless; with --window in its window under Xvfb, where it takes the manual's picture
# of the MAVLink flight (resources/screenshots/gcs_watches_mavlink.png; the software renderer
# slows the simulation about fivefold on two cores, so CI runs it headless).
if [ "${3:-}" = --window ]; then
  LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s "-screen 0 1600x900x24" \
    "$bin/uav-gcs" --name watcher --lcm-url "$url" --key uav.key --script "$here/watch.gcs" > gcs.log 2>&1 &
else
  grep -v '^screenshot' "$here/watch.gcs" > watch_headless.gcs
  "$bin/uav-gcs" --headless --name watcher --lcm-url "$url" --key uav.key --script watch_headless.gcs > gcs.log 2>&1 &
fi
gcs=$!
trap 'kill $onboard $gcs $gst 2>/dev/null || true' EXIT
status=0
scaled_timeout 600 node "$here/qgc_client.js" --bin "$bin" --passphrase "$passphrase" --report report.json \
  --lcm-param ctl_speed_max_up=1.5 || status=$?
wait $gcs || { echo "FAIL: our GCS on LCM did not see the flight through:"; tail -20 gcs.log; status=1; }
kill $onboard $gst 2>/dev/null || true
wait $onboard 2>/dev/null || true
frames=$(find . -maxdepth 1 -name "video_*.gray" | wc -l)
echo "video: $frames frames decoded from RTP/H.264 on UDP 5600"
if [ "$frames" -lt 20 ]; then echo "FAIL: fewer than 20 video frames decoded"; cat gst.log; status=1; fi
# The pictures are the stream's (the size VIDEO_STREAM_INFORMATION announced), the village in
# them while flying (at least ten sampled frames with more than one grey level; on the ground the
# camera sees one).
python3 - "$out" <<'PY' || status=1
import glob, json, statistics, sys
video = json.load(open(sys.argv[1] + "/report.json"))["video"]
files = sorted(glob.glob(sys.argv[1] + "/video_*.gray"))
sizes_ok = all(len(open(f, "rb").read()) == video["width"] * video["height"] for f in files[::10])
textured = sum(statistics.pstdev(open(f, "rb").read()[::97]) > 5 for f in files[::10])
print(f"video: {video['width']} x {video['height']} announced, every sampled frame that size: {sizes_ok}; "
      f"{textured} of {len(files[::10])} sampled frames show the ground's texture")
sys.exit(0 if sizes_ok and textured >= 10 else 1)
PY
[ $status = 0 ] && echo PASS || echo FAIL
exit $status
