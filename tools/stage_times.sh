#!/usr/bin/env bash
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
# The stages of `make test`, each timed, in the working tree it is run from (a fresh
# clone for the figures of docs/testing.md):
#
#   tools/stage_times.sh            # quiet
#   tools/stage_times.sh --loaded   # the pytest stage beside two busy processes per core
#
# Prints one line per stage (apt, venv and ROS wheels, colcon build, lint, pytest, the
# benchmark guard, docs, colcon-plain, colcon-test) with its wall time, the load average at its start and its
# end, then the sum. Exit status: the first failing stage's (the others do not run).
set -euo pipefail
cd "$(dirname "$0")/.."
loaded=0
[ "${1:-}" = "--loaded" ] && loaded=1
total=0
stage() {
  local name=$1; shift
  local l0 t0 t1 dt
  l0=$(cut -d' ' -f1 /proc/loadavg)
  t0=$(date +%s.%N)
  if ! "$@" >"/tmp/stage_times.$name.log" 2>&1; then
    echo "stage $name FAILED (log: /tmp/stage_times.$name.log)"
    tail -n 20 "/tmp/stage_times.$name.log"
    exit 1
  fi
  t1=$(date +%s.%N)
  dt=$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')
  total=$(awk -v a="$total" -v b="$dt" 'BEGIN { print a + b }')
  printf 'stage %-13s %7.1f s   load average %s -> %s\n' "$name" "$dt" "$l0" \
    "$(cut -d' ' -f1 /proc/loadavg)"
}
stage apt make apt
stage venv make .venv/.stamps/pip .venv/.stamps/editable
stage colcon-build make build
stage lint make lint
if [ "$loaded" = 1 ]; then
  stage pytest-loaded .venv/bin/python tools/busy.py --per-core 2 -- make pytest
else
  stage pytest make pytest
fi
stage bench-guard make bench-guard
stage docs make docs
stage colcon-plain make colcon-plain
# colcon test in the workspace colcon-plain built (as in `make test`: not built twice)
stage colcon-test make -o colcon-plain -o deps colcon-test
printf 'total %.1f s on %s cores\n' "$total" "$(nproc)"
