# Sourced by the integration scripts: limits in seconds multiplied by UAV_TIMEOUT_SCALE (default
# 1), which a sanitized build sets for these tests (tests/CMakeLists.txt): a sanitized vehicle
# runs several times slower than real time. uav-gcs scales its scripts' waits by the same variable.
scaled_seconds() { awk -v t="$1" -v s="${UAV_TIMEOUT_SCALE:-1}" 'BEGIN { printf "%d", t * s }'; }
# timeout(1) with a scaled limit.
scaled_timeout() {
  local limit
  limit=$(scaled_seconds "$1")
  shift
  timeout "$limit" "$@"
}
