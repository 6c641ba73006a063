#!/usr/bin/env bash
# uav-powerlines end to end: a mask of the input's size and a JSON per usable image (a grey
# camera's frame included); an unreadable file and a 16-bit image are named with the reason,
# nothing is written for them, and the rest are processed (exit 1 because some were skipped).
set -uo pipefail
bin=$1 data=/usr/share/doc/opencv-doc/examples/data
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf 'not an image' > "$work/junk.jpg"
{ printf 'P5\n40 40\n255\n'; head -c 1600 /dev/zero; } > "$work/gray.pgm"
{ printf 'P5\n40 40\n65535\n'; head -c 3200 /dev/zero; } > "$work/deep.pgm"
"$bin/uav-powerlines" "$data/building.jpg" "$work/junk.jpg" "$work/gray.pgm" "$work/deep.pgm" "$data/aero1.jpg" --out "$work/out" \
  > "$work/stdout" 2> "$work/stderr"
status=$?
cat "$work/stdout" "$work/stderr"
fail() { echo "FAIL: $*"; exit 1; }
[ $status -eq 1 ] || fail "exit $status, expected 1 (two images skipped)"
grep -q "junk.jpg: cannot read it as an image" "$work/stderr" || fail "the unreadable file is not named"
grep -q "deep.pgm: image has 1 channel(s) of depth 2" "$work/stderr" || fail "the 16-bit image is not named"
[ ! -e "$work/out/junk_lines.png" ] && [ ! -e "$work/out/deep.json" ] || fail "something was written for a bad image"
for name in building aero1 gray; do
  [ -s "$work/out/${name}_lines.png" ] && [ -s "$work/out/$name.json" ] || fail "no output for $name"
done
python3 - "$work/out" "$data" <<'PY'
import json, struct, sys
out, data = sys.argv[1], sys.argv[2]
for name, size in (("building", None), ("aero1", None), ("gray", None)):
    png = open(f"{out}/{name}_lines.png", "rb").read()
    w, h = struct.unpack(">II", png[16:24])
    j = json.load(open(f"{out}/{name}.json"))
    assert (w, h) == (j["width"], j["height"]), (name, w, h)
    for wire in j["wires"]:
        assert len(wire["b"]) == 3 and len(wire["first_px"]) == 2 and wire["rms_px"] >= 0
print("uav-powerlines: outputs match their inputs' sizes")
PY
