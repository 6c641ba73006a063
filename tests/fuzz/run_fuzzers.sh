#!/usr/bin/env bash
# Builds the fuzz harnesses with clang-14 and libFuzzer (ASan+UBSan) and runs every one for
# SECONDS, JOBS at a time, each on its own corpus (seeded from the project's files and the
# generated messages; it grows between runs). A crash, hang, leak or sanitizer report is kept
# as OUT/artifacts/<name>-crash-*; copy it to tests/fuzz/regressions/<name>/ once fixed, so the
# g++ build replays it on every CI run.
# Usage: tests/fuzz/run_fuzzers.sh [SECONDS per harness, default 60] [JOBS, default nproc]
# Env: UAV_FUZZ_DIR (build and corpus directory, default build-fuzz), UAV_FUZZERS (names to run).
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
secs=${1:-60}
jobs=${2:-$(nproc)}
out=${UAV_FUZZ_DIR:-$src/build-fuzz}
command -v clang++-14 > /dev/null || { echo "run_fuzzers: needs clang-14 and libfuzzer-14-dev (bash .ci/setup installs them)"; exit 2; }
CC=clang-14 CXX=clang++-14 cmake -S "$src" -B "$out" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DUAV_FUZZ=ON > "$out.configure.log" 2>&1 ||
  { cat "$out.configure.log"; exit 1; }
echo "run_fuzzers: building the harnesses in $out"
cmake --build "$out" -j"$jobs" --target fuzzers > "$out/build.log" 2>&1 || { tail -40 "$out/build.log"; exit 1; }
"$out/bin/make_fuzz_seeds" "$out/tests/fuzz/seeds" > /dev/null
names=${UAV_FUZZERS:-$(cat "$out/tests/fuzz/fuzzers.txt" | tr ';' ' ')}
mkdir -p "$out/artifacts" "$out/logs"
run_one() {
  local name=$1 secs=$2 out=$3
  # libFuzzer reads directories: the seed files go into one of their own.
  mkdir -p "$out/corpus/$name" "$out/seed_files/$name"
  mapfile -t seeds < "$out/tests/fuzz/seeds_$name.txt"
  local existing=("$out/seed_files/$name")
  for s in "${seeds[@]}"; do
    if [ -d "$s" ]; then existing+=("$s"); elif [ -f "$s" ]; then cp "$s" "$out/seed_files/$name/"; fi
  done
  # -timeout: an input slower than 10 s is a hang; -rss_limit_mb: more than 2 GB is a leak or a
  # bomb. Both are findings, like crashes.
  "$out/bin/fuzz_$name" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$out/artifacts/$name-" "$out/corpus/$name" "${existing[@]}" > "$out/logs/$name.log" 2>&1
  echo "$name $?"
}
export -f run_one
echo "run_fuzzers: ${secs} s each, $jobs at a time: $names"
start=$(date +%s)
printf '%s\n' $names | xargs -P "$jobs" -I{} bash -c "run_one {} $secs $out" > "$out/logs/status.txt"
failed=0 total_execs=0
printf '%-20s %12s %8s %8s  %s\n' harness executions exec/s corpus result
for name in $names; do
  log="$out/logs/$name.log"
  execs=$(awk '/stat::number_of_executed_units:/ {v = $2} END {print v}' "$log")
  rate=$(awk '/stat::average_exec_per_sec:/ {v = $2} END {print v}' "$log")
  corpus=$(ls "$out/corpus/$name" | wc -l)
  status=$(awk -v n="$name" '$1 == n {print $2}' "$out/logs/status.txt")
  result=ok
  if [ "$status" != 0 ] || compgen -G "$out/artifacts/$name-*" > /dev/null; then
    result="FOUND: $(compgen -G "$out/artifacts/$name-*" | head -1 || true) (log $log)"
    failed=1
  fi
  total_execs=$((total_execs + ${execs:-0}))
  printf '%-20s %12s %8s %8s  %s\n' "$name" "${execs:-?}" "${rate:-?}" "$corpus" "$result"
done
n=$(echo $names | wc -w)
echo "run_fuzzers: $n harnesses x $secs s = $((n * secs)) CPU-seconds in $(( $(date +%s) - start )) s wall, $total_execs executions, $([ $failed = 0 ] && echo 'no findings' || echo 'FINDINGS above')"
exit $failed
