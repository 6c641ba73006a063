#!/usr/bin/env bash
# The GCS's disk full while it saves a map: runs MapsDiskFull (test_gcs) with its download
# directory on a 1 MB tmpfs mounted in a private mount namespace (as root, like netns.sh), so
# the file system really fills up and nothing else on the machine is touched.
# Usage: disk_full.sh TEST_GCS
set -euo pipefail
exec unshare -m bash -c '
  set -euo pipefail
  fs=$(mktemp -d)
  mount -t tmpfs -o size=1m tmpfs "$fs"
  out=$(UAV_SMALL_FS="$fs" "$1" --gtest_filter="MapsDiskFull.*" 2>&1) || { echo "$out"; exit 1; }
  echo "$out"
  grep -q "\[  PASSED  \] 1 test" <<< "$out" && ! grep -q "SKIPPED" <<< "$out"
' disk_full "$1"
