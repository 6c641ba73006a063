#!/usr/bin/env bash
# Builds the project with sanitizers in its own tree and runs tests under them; any report
# fails (halt on the first error, leaks included).
#   asan       ASan+UBSan: every unit and integration test (build-asan/)
#   asan-unit  ASan+UBSan: the unit tests of the shared code, the wire and the missions, and the
#              fuzz harnesses of the messages, files and GCS scripts over their seeds (CI runs
#              this; the GCS model is reached through its harnesses, its panels only in 'asan')
#   tsan       TSan: the threaded parts, the lockstep scheduler and the workers (test_onboard),
#              the GCS link (test_gcs), and a whole flight over LCM (integration.fly_mission)
# Usage: tests/sanitizers/sanitize.sh MODE [BUILD_DIR [CTEST_ARGS...]]   (UAV_SANITIZE_JOBS: parallel
# jobs, default nproc; UAV_SANITIZE_TIMEOUT: seconds per test, default 900; CTEST_ARGS narrow the
# mode's tests further, e.g. -R integration)
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
mode=${1:?usage: sanitize.sh asan|asan-unit|tsan [BUILD_DIR]}
jobs=${UAV_SANITIZE_JOBS:-$(nproc)}
supp="$src/tests/sanitizers"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1:verify_asan_link_order=0"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$supp/tsan.supp"
case "$mode" in
  asan | asan-unit) flags=address,undefined dir=${2:-$src/build-asan} ;;
  tsan) flags=thread dir=${2:-$src/build-tsan} ;;
  *) echo "sanitize.sh: unknown mode '$mode' (asan, asan-unit or tsan)"; exit 2 ;;
esac
case "$mode" in
  # Unit tests are labelled with their executable's name (tests/CMakeLists.txt).
  asan) targets=(all) select=(-E '^bench\.') ;;
  # The fuzz harnesses of the scene and the stereo calibration would pull the renderer and PCL
  # into this build; their seeds run in the g++ build and under libFuzzer's ASan.
  asan-unit)
    targets=(test_shared test_wire test_waypoints make_fuzz_seeds fuzz_command_grammar fuzz_mission_files fuzz_parameters
             fuzz_capture_folder fuzz_gcs_script fuzz_vehicle_messages fuzz_gcs_messages fuzz_event_log fuzz_mavlink
             fuzz_gcs_mavlink)
    select=(-L '^(test_shared|test_wire|test_waypoints|fuzz)$' -E '^fuzz\.(scene|stereo_calibration)\.seeds$') ;;
  tsan) targets=(test_onboard test_gcs uav-onboard uav-gcs uav-keygen)
        select=(-R '^(LockstepScheduler|CameraWorker|StereoWorker|ActiveStereoWorker|TrackWorker|LinkTest|integration\.fly_mission)') ;;
esac
shift $(( $# < 2 ? $# : 2 ))
echo "sanitize.sh: $mode (-fsanitize=$flags) in $dir"
if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir/CMakeCache.txt"; then rm -rf "$dir"; fi
# asan-unit compiles its libraries and tests as unity builds (batches of sources in one
# translation unit): CI builds this tree from nothing on one core beside the other tests, and
# most of the time went to parsing the same Eigen, OpenCV and nlohmann headers once per source.
unity=OFF
[ "$mode" = asan-unit ] && unity=ON
cmake -S "$src" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DUAV_SANITIZE=$flags -DCMAKE_UNITY_BUILD=$unity > /dev/null
start=$(date +%s)
cmake --build "$dir" -j"$jobs" --target "${targets[@]}" > "$dir/build.log" 2>&1 || { tail -40 "$dir/build.log"; exit 1; }
echo "sanitize.sh: built in $(( $(date +%s) - start )) s"
start=$(date +%s)
ctest --test-dir "$dir" "${select[@]}" "$@" -j"$jobs" --output-on-failure --timeout "${UAV_SANITIZE_TIMEOUT:-900}"
echo "sanitize.sh: $mode tests clean in $(( $(date +%s) - start )) s"
