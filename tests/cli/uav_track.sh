#!/usr/bin/env bash
# uav-track on damaged input and bad options: a truncated video is reported (frames read against
# frames declared, exit 1, the boxes still written for what was read); a folder with a truncated
# and a garbled frame skips them by name; --tracker foo and a hexadecimal box are refused naming
# the option.
set -uo pipefail
bin=$1 data=/usr/share/doc/opencv-doc/examples/data
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# A third of vtest.avi (795 frames declared in its header).
head -c 2700000 "$data/vtest.avi" > "$work/cut.avi"
"$bin/uav-track" "$work/cut.avi" --box 300,200,40,90 --out "$work/cut.csv" > "$work/stdout" 2> "$work/stderr"
status=$?
cat "$work/stdout" "$work/stderr"
[ $status -eq 1 ] || fail "exit $status on a truncated video, expected 1"
grep -q "cut.avi: the video ends at frame [0-9]* of the 795 it declares (truncated or damaged)" "$work/stderr" \
  || fail "the truncated video is not reported"
grep -q '"damaged": "the video ends at frame' "$work/stdout" || fail "the report does not say the video is damaged"
[ "$(wc -l < "$work/cut.csv")" -gt 10 ] || fail "no boxes for the frames that were read"

# A folder of frames (opencv-doc's chessboard views) with a truncated and a garbled one.
mkdir "$work/frames"
for i in 01 02 03 04 05 06 07 08 09 11 12 13; do cp "$data/left$i.jpg" "$work/frames/f$i.jpg"; done
python3 - "$work/frames" <<'PY'
import sys
out = sys.argv[1]
data = open(f"{out}/f05.jpg", "rb").read()
open(f"{out}/f05.jpg", "wb").write(data[: len(data) // 2])
data = bytearray(open(f"{out}/f07.jpg", "rb").read())
for k in range(600):
    data[len(data) // 2 + k] = (k * 37 + 11) & 0xFF
open(f"{out}/f07.jpg", "wb").write(bytes(data))
PY
"$bin/uav-track" "$work/frames" --box 200,150,120,100 --tracker kcf > "$work/stdout" 2> "$work/stderr"
status=$?
cat "$work/stdout" "$work/stderr"
[ $status -eq 1 ] || fail "exit $status with two bad frames, expected 1"
grep -q "skipped $work/frames/f05.jpg: corrupt JPEG (Premature end of JPEG file)" "$work/stderr" || fail "f05 not named"
grep -q "skipped $work/frames/f07.jpg: corrupt JPEG" "$work/stderr" || fail "f07 not named"
grep -q '"frames": 10' "$work/stdout" || fail "not 10 frames tracked"

# Options: each error names its option.
"$bin/uav-track" "$work/frames" --box 100,80,40,60 --tracker foo > "$work/out" 2>&1 && fail "--tracker foo accepted"
grep -q -- "--tracker" "$work/out" || fail "--tracker foo not named: $(cat "$work/out")"
grep -q -- "--box" "$work/out" && fail "--tracker foo reported as a --box error"
"$bin/uav-track" "$work/frames" --box 0x10,80,40,60 > "$work/out" 2>&1 && fail "a hexadecimal box accepted"
grep -q "'0x10' is not a finite decimal number" "$work/out" || fail "the hexadecimal box is not named: $(cat "$work/out")"
echo "ok"
