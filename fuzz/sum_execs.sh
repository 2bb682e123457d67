#!/usr/bin/env bash
# Executions so far per target of fuzz/run_long.sh: finished runs report
# stat::number_of_executed_units, a running one its last "#N" status line.
out="${1:-/tmp/gonio-fuzz-long}"
for t in material merl scene obj png exr surface; do
  total=0
  for log in "$out/$t"/run-*.log "$out/$t"/fuzz-0.log; do
    [ -f "$log" ] || continue
    n=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
    [ -n "$n" ] || n=$(grep -o '^#[0-9]*' "$log" | tail -1 | tr -d '#')
    total=$((total + ${n:-0}))
  done
  crashes=$(ls "$out/$t" | grep -c -E '^(crash|leak|timeout|oom)-' || true)
  echo "$t executions $total reproducers $crashes"
done
