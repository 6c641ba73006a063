#!/usr/bin/env bash
# The Debian packages, built and installed into an empty root: cpack builds uav-common, uav-gcs,
# uav-onboard and uav-tools from the build tree; each is checked (its control fields, its files)
# and unpacked into ROOT; then the programs run from ROOT, with ROOT's data and configuration and
# nothing of the source or build tree: every program answers --version and --help, uav-onboard
# flies the simulated vehicle for 3 s from the packaged vehicle file, uav-survey plans with the
# packaged camera, uav-gcs scripts a headless session with the packaged vehicle.
# Usage: install_and_run.sh BUILD_DIR WORK_DIR   (runs in a private network namespace: netns.sh)
set -euo pipefail
build=$1 work=$2
rm -rf "$work"; mkdir -p "$work/debs" "$work/root"
fail() { echo "install_and_run: FAILED: $*" >&2; exit 1; }

echo "install_and_run: cpack (gzip, to keep the test short)"
(cd "$work/debs" && cpack --config "$build/CPackConfig.cmake" -D CPACK_DEBIAN_COMPRESSION_TYPE=gzip >cpack.log 2>&1) \
  || { tail -30 "$work/debs/cpack.log"; fail "cpack"; }
for p in uav-common uav-gcs uav-onboard uav-tools; do
  deb=$(ls "$work"/debs/${p}_*.deb 2>/dev/null | head -1)
  [ -n "$deb" ] || fail "no package $p"
  dpkg-deb --info "$deb" > "$work/$p.info"
  grep -q "^ Package: $p$" "$work/$p.info" || fail "$p: wrong Package field"
  if [ $p != uav-common ]; then
    grep -q "^ Depends:.*uav-common (= " "$work/$p.info" || fail "$p does not depend on uav-common"
  fi
  dpkg-deb -x "$deb" "$work/root"
  echo "install_and_run: $p $(grep '^ Version:' "$work/$p.info" | cut -d' ' -f3), $(du -k "$deb" | cut -f1) kB"
done
# Shared libraries found by dpkg-shlibdeps (OpenCV, LCM, GDAL, ...), so apt installs them.
grep -q "^ Depends:.*libopencv" "$work/uav-tools.info" || fail "uav-tools: no library dependencies (shlibdeps)"
grep -q "^ Depends:.*liblcm" "$work/uav-onboard.info" || fail "uav-onboard: no dependency on LCM"
grep -q "^ Depends:.*adduser" "$work/uav-onboard.info" || fail "uav-onboard: no dependency on adduser"

r=$work/root
for f in usr/bin/uav-gcs usr/bin/uav-onboard usr/bin/uav-keygen usr/bin/uav-demo usr/bin/uav-track \
         usr/share/uav/vehicles/x650.params usr/share/uav/cameras/sim_downward_640x480.camera \
         usr/share/uav/scenes/survey_village.scene.json usr/share/doc/uav/README.md \
         usr/share/applications/uav-gcs.desktop usr/share/icons/hicolor/scalable/apps/uav-gcs.svg \
         usr/lib/systemd/system/uav-onboard.service etc/uav/onboard.conf etc/uav/vehicle.params; do
  [ -e "$r/$f" ] || fail "/$f is not in the packages"
done
[ -e "$r/usr/share/doc/uav/docs/reference/parameters.md" ] || fail "the manual is not in uav-common"
# The installed manual's relative links and pictures resolve where it is installed.
python3 "$(dirname "$0")/../docs/check_links.py" "$r/usr/share/doc/uav" > "$work/links.txt" || { cat "$work/links.txt"; fail "the installed manual has broken links"; }
# The onboard package's maintainer scripts and conffiles.
mkdir -p "$work/control"; dpkg-deb -e "$work"/debs/uav-onboard_*.deb "$work/control"
grep -qx /etc/uav/onboard.conf "$work/control/conffiles" || fail "onboard.conf is not a conffile"
sh -n "$work/control/postinst" && sh -n "$work/control/prerm" || fail "maintainer scripts do not parse"
if command -v desktop-file-validate >/dev/null; then
  desktop-file-validate "$r/usr/share/applications/uav-gcs.desktop" || fail "the desktop entry is invalid"
fi
# The unit starts the packaged program with the packaged configuration.
grep -q '^ExecStart=/usr/bin/uav-onboard \$UAV_ONBOARD_ARGS$' "$r/usr/lib/systemd/system/uav-onboard.service" || fail "unit ExecStart"
grep -q '^EnvironmentFile=/etc/uav/onboard.conf$' "$r/usr/lib/systemd/system/uav-onboard.service" || fail "unit EnvironmentFile"

# From here on nothing of the source or build tree: the programs' own lookup finds ROOT's data.
cd "$work"
unset UAV_RESOURCE_DIR
export PATH="$r/usr/bin:/usr/bin:/bin"
n=0
for exe in "$r"/usr/bin/uav-*; do
  name=$(basename "$exe")
  v=$("$exe" --version) || fail "$name --version"
  [[ $v =~ ^$name\ [0-9]+\.[0-9]+\.[0-9]+\ \(commit\ ([0-9a-f]{12}(-modified)?|unknown)\)$ ]] || fail "$name --version said '$v'"
  "$exe" --help > help.txt || fail "$name --help"
  grep -qi "usage\|options" help.txt || fail "$name --help printed no usage"
  n=$((n + 1))
done
echo "install_and_run: $n programs answer --version and --help ($(uav-gcs --version))"

# Their data is ROOT's, not the source tree's: the defaults they show are under ROOT.
uav-onboard --help | grep -qF -- "$r/usr/share/uav/vehicles/x650.params" || fail "uav-onboard's default vehicle file is not ROOT's"
uav-survey --help | grep -qF -- "$r/usr/share/uav/cameras/sim_downward_640x480.camera" || fail "uav-survey's default camera is not ROOT's"
uav-keygen "$work/key" >/dev/null
# uav-onboard's default vehicle file is the packaged one; the configuration's vehicle file flies too.
uav-onboard --sim --insecure --lcm-url memq:// --speed max --duration 3 > onboard_default.txt 2>&1 \
  || { cat onboard_default.txt; fail "uav-onboard from the packages"; }
grep -q "X650 quadrotor" onboard_default.txt || fail "uav-onboard did not fly the packaged X650"
uav-onboard --sim --key "$work/key" --params "$r/etc/uav/vehicle.params" --lcm-url memq:// --speed max --duration 3 \
  --log-dir "$work/logs" > onboard_etc.txt 2>&1 || { cat onboard_etc.txt; fail "uav-onboard with /etc/uav/vehicle.params"; }
ls "$work"/logs/flight_*.csv >/dev/null || fail "no flight log"
# uav-survey plans with its default camera, found in ROOT/usr/share/uav.
uav-survey --polygon-file "$r/usr/share/uav/areas/village_l.area" --altitude 25 > survey.json 2> survey.err || { cat survey.err; fail "uav-survey"; }
grep -q '"images"' survey.json || fail "uav-survey printed no plan"
# The GCS, headless, against a packaged vehicle on a private bus: it hears it and takes off.
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
uav-onboard --sim --key "$work/key" --lcm-url "$url" --speed 2 --duration 60 > onboard_gcs.txt 2>&1 &
onboard=$!
trap 'kill $onboard 2>/dev/null || true' EXIT
cat > session.gcs <<'GCS'
wait_until vehicles >= 1 and link == up timeout 30
type arm
wait_until ack == completed timeout 20
type takeoff 3
wait_until alt ~ 3 0.5 timeout 40
type land
wait_until armed == 0 timeout 60
GCS
uav-gcs --headless --key "$work/key" --lcm-url "$url" --script session.gcs > gcs.txt 2>&1 || { cat gcs.txt; tail -5 onboard_gcs.txt; fail "uav-gcs session"; }
echo "install_and_run: uav-gcs flew the packaged uav-onboard (arm, takeoff 3, land)"
echo "install_and_run: PASSED"
