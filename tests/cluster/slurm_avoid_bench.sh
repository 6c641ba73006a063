#!/usr/bin/env bash
# uav-avoid-bench on a Slurm cluster, end to end: a one-node cluster (munge, slurmctld, slurmd)
# runs a job array of two tasks, one seed each, through a small obstacle layout; the merged
# results equal a local run's of the same seeds in two processes (--jobs 2), flight by flight
# (the planning times aside: they are wall and CPU times), and --merge of the tasks' files gives
# the same cell again. A task that fails is named with its log's last line; sbatch's refusal is
# passed on.
# Usage: slurm_avoid_bench.sh BIN_DIR
set -uo pipefail
bin=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
fail() { echo "FAIL: $*"; exit 1; }
[ "$(id -u)" = 0 ] || fail "needs root (slurmd runs jobs as their user)"
for c in munged slurmctld slurmd sbatch sinfo; do command -v "$c" > /dev/null || fail "no $c (Debian's slurm-wlm)"; done
out=$(mktemp -d)
# shellcheck source=one_node_slurm.sh
source "$here/one_node_slurm.sh"
trap 'slurm_stop; rm -rf "$out"' EXIT
slurm_start "$out/cluster" || fail "the one-node cluster did not start"
cd "$out" || exit 1
cat > layout.json << 'JSON'
{"name": "wall and pole", "seed": 4,
 "objects": [
   {"type": "box", "kind": "wall", "center_ned": [12, 0, -4], "size": [0.3, 8, 8], "material": "brick"},
   {"type": "cylinder", "kind": "pole", "base_ned": [18, 2.5, 0], "radius_m": 0.3, "height_m": 8, "material": "concrete"}]}
JSON
course=(--scene layout.json --to 24,0 --speed 3)
flight=("${course[@]}" --seeds 4-5)
"$bin/uav-avoid-bench" "${flight[@]}" --slurm array --seeds-per-task 1 --wait --json slurm.json > slurm.out 2> slurm.err ||
  { cat slurm.err array/*.log; fail "the job array did not fly"; }
grep -q "job array [0-9]*: 2 task(s) of up to 1 seeds (4-5)" slurm.err || { cat slurm.err; fail "no job array announced"; }
"$bin/uav-avoid-bench" "${flight[@]}" --jobs 2 --json local.json > /dev/null 2> local.err || { cat local.err; fail "the local run did not fly"; }
"$bin/uav-avoid-bench" --merge array/task_0.json array/task_1.json > merged.out || fail "--merge of the tasks' files"
python3 - << 'PY' || fail "the job array's results differ from the local run's"
import json
slurm, local = json.load(open("slurm.json")), json.load(open("local.json"))
timing = {"replan_p50_ms", "replan_p99_ms", "replan_cpu_p50_ms", "replan_cpu_p99_ms"}
for key in ("scene", "goal_ne_m", "speed", "altitude_m", "density"):
    assert slurm[key] == local[key], (key, slurm[key], local[key])
assert [f["seed"] for f in slurm["flights"]] == [4, 5] == [f["seed"] for f in local["flights"]]
for a, b in zip(slurm["flights"], local["flights"]):
    assert set(a) == set(b), (set(a) ^ set(b))
    differ = {k: (a[k], b[k]) for k in a if k not in timing and a[k] != b[k]}
    assert not differ, (a["seed"], differ)
cell, merged = slurm["cell"], json.load(open("merged.out"))
assert cell == merged and cell == json.load(open("slurm.out")), "the --wait cell is not --merge's"
# A merged report is the sum of its parts: flights, successes, wires passed, time flown.
parts = [json.load(open(f"array/task_{k}.json"))["cell"] for k in (0, 1)]
for key in ("flights", "wires_passed", "obstacles_passed") if "obstacles_passed" in cell else ("flights", "wires_passed"):
    assert cell[key] == sum(p[key] for p in parts), key
assert abs(cell["time_flown_s"] - sum(p["time_flown_s"] for p in parts)) < 1e-6
assert cell["success_rate"] * cell["flights"] == sum(p["success_rate"] * p["flights"] for p in parts)
print("slurm job array = local run, seed by seed:", [(f["seed"], f["success"], round(f["min_clearance_m"], 3)) for f in slurm["flights"]])
PY
# A task that cannot fly (its processes find no shipped data there) is named, with its log's last
# line; the other task's results stay.
if "$bin/uav-avoid-bench" "${course[@]}" --seeds 4 --slurm broken --wait --sbatch=--export=ALL,UAV_RESOURCE_DIR=/nonexistent \
  > /dev/null 2> broken.err; then fail "a failed task passed"; fi
grep -q "1 of 1 task(s) did not fly all their seeds" broken.err && grep -q "task 0 (seeds 4-4, 0 flown): uav-avoid-bench:" broken.err ||
  { cat broken.err; fail "the failed task was not named with its log"; }
# sbatch's refusal is passed on, and nothing is flown here.
if "$bin/uav-avoid-bench" "${course[@]}" --seeds 4 --slurm refused --sbatch=--partition=nowhere > /dev/null 2> refused.err; then
  fail "sbatch accepted a partition that does not exist"
fi
grep -q "sbatch refused the job array: .*nowhere\|sbatch refused the job array: .*[Pp]artition" refused.err || { cat refused.err; fail "sbatch's refusal lost"; }
cat broken.err refused.err
echo "slurm refusals: ok"
