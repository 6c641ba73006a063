#!/usr/bin/env bash
# uav-ulion-bench: U-Lion's transitions over Monte-Carlo runs (wind, mass, thrust and aerodynamic
# coefficients drawn), ours against PX4's schedule; the plot and the per-run trace; a quadrotor
# file and a broken tail-sitter file refused with the reason.
set -euo pipefail
bin=$1
resources=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$bin/uav-ulion-bench" --runs 30 --json "$out/r.json" --plot "$out/t.png" --trace "$out/run.csv" > "$out/stdout.json"
python3 - "$out" <<'PY'
import csv, json, sys
out = sys.argv[1]
j = json.load(open(f"{out}/r.json"))
assert json.load(open(f"{out}/stdout.json")) == j
assert open(f"{out}/t.png", "rb").read(8) == b"\x89PNG\r\n\x1a\n"
ours, px4 = j["ours"], j["px4_ramp"]
assert ours["runs"] == 30 and ours["crashed"] == 0, ours
# Ours meets the front target in every run and beats the 5 s ramp on time.
assert ours["front"]["meets_target_pct"] == 100.0, ours["front"]
assert ours["front"]["time_s_p95"] <= 4.0 and ours["front"]["altitude_loss_m_p95"] <= 1.0, ours["front"]
assert ours["front"]["time_s_p50"] < 0.7 * px4["front"]["time_s_p50"], (ours["front"], px4["front"])
assert ours["back"]["meets_target_pct"] >= 90.0 and ours["back"]["time_s_p95"] <= 3.0, ours["back"]
# Cruise on the wing needs a fraction of hover's power.
e = j["endurance"]
assert e["cruise_w"] < 0.2 * e["hover_w"] and e["cruise_min"] > 10, e
rows = list(csv.DictReader(open(f"{out}/run.csv")))
modes = [r["mode"] for r in rows]
for m in ("hover", "transition_to_wing", "cruise", "transition_to_hover"):
    assert m in modes, m
print("uav-ulion-bench: ok")
PY
# A quadrotor's file is refused; so is a tail-sitter whose canards are outside the propwash.
if "$bin/uav-ulion-bench" --runs 1 --params "$resources/vehicles/x650.params" 2> "$out/err"; then exit 1; fi
grep -q "vehicle_type is not 1" "$out/err"
sed 's/^ts_canard_y .*/ts_canard_y 0.3/' "$resources/vehicles/ulion.params" > "$out/bad.params"
if "$bin/uav-ulion-bench" --runs 1 --params "$out/bad.params" 2> "$out/err"; then exit 1; fi
grep -q "ts_canard_y must lie inside the rotor's slipstream" "$out/err"
echo "refusals: ok"
