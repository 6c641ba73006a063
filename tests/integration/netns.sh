#!/usr/bin/env bash
# Runs a command inside a private network namespace: loopback only, multicast on, so LCM
# traffic (udpm, ttl=0) never leaves this machine and parallel tests do not hear each other.
# Usage: netns.sh COMMAND [ARGS...]   (needs root, as CI is)
set -euo pipefail
if [ "${UAV_IN_NETNS:-}" != 1 ]; then
  exec env UAV_IN_NETNS=1 unshare -n "$0" "$@"
fi
ip link set lo up
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
exec "$@"
