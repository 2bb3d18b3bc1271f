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
# benchmark guard, docs, colcon-plain, colcon-test) with its wall time, the load average
# at its start and its end, then the sum. As `make test` does, pytest runs beside
# colcon-plain and docs beside colcon-test: each pair's own line gives its wall time,
# which is what the sum adds. Exit status: the first failing stage's (the others do not
# run).
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
# Two stages side by side, each timed; then the pair's wall time, which the sum adds.
timed() {
  local name=$1; shift
  local t0 t1 status=0
  t0=$(date +%s.%N)
  "$@" >"/tmp/stage_times.$name.log" 2>&1 || status=$?
  t1=$(date +%s.%N)
  printf '%s %s %s\n' "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')" "$status" \
    "$(cut -d' ' -f1 /proc/loadavg)" >"/tmp/stage_times.$name.time"
}
pair() {  # pair NAME1 NAME2: the commands are in the arrays cmd1 and cmd2
  local l0 t0 t1 dt failed=0
  l0=$(cut -d' ' -f1 /proc/loadavg)
  t0=$(date +%s.%N)
  timed "$1" "${cmd1[@]}" &
  local p1=$!
  timed "$2" "${cmd2[@]}" &
  local p2=$!
  wait "$p1" "$p2"
  t1=$(date +%s.%N)
  for name in "$1" "$2"; do
    read -r dt status l1 <"/tmp/stage_times.$name.time"
    if [ "$status" != 0 ]; then
      echo "stage $name FAILED (log: /tmp/stage_times.$name.log)"
      tail -n 20 "/tmp/stage_times.$name.log"
      failed=1
    fi
    printf 'stage %-13s %7.1f s   load average %s -> %s   (beside %s)\n' "$name" "$dt" \
      "$l0" "$l1" "$([ "$name" = "$1" ] && echo "$2" || echo "$1")"
  done
  [ "$failed" = 0 ] || exit 1
  dt=$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')
  total=$(awk -v a="$total" -v b="$dt" 'BEGIN { print a + b }')
  printf 'pair  %-13s %7.1f s   (%s and %s, side by side)\n' "" "$dt" "$1" "$2"
}
stage apt make apt
stage venv make .venv/.stamps/pip .venv/.stamps/editable
stage colcon-build make build
stage lint make lint
SUB=(make --no-print-directory -o deps -o build)
if [ "$loaded" = 1 ]; then
  cmd1=(.venv/bin/python tools/busy.py --per-core 2 -- "${SUB[@]}" pytest)
else
  cmd1=("${SUB[@]}" pytest)
fi
cmd2=("${SUB[@]}" colcon-plain)
pair pytest colcon-plain
stage bench-guard "${SUB[@]}" bench-guard
# colcon test in the workspace colcon-plain built (as in `make test`: not built twice)
cmd1=("${SUB[@]}" docs)
cmd2=("${SUB[@]}" -o colcon-plain colcon-test)
pair docs colcon-test
printf 'total %.1f s on %s cores\n' "$total" "$(nproc)"
