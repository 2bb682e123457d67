#!/usr/bin/env bash
# The long fuzzing run of docs/robustness.md: each target for SECONDS (default 4 h) in
# its own working directory under OUT (default /tmp/gonio-fuzz-long), one fuzzing process
# per target at a time (what -jobs=1 gives), at nice 10. The repository's seeds are read,
# the grown corpus is OUT/<target>/corpus, reproducers land in OUT/<target>/. A crash
# ends a run; the target is restarted on the grown corpus until SECONDS have passed, so
# that one known crash does not end the campaign. Logs: OUT/<target>/run-N.log; the
# executions are the sum of their stat::number_of_executed_units (fuzz/sum_execs.sh).
# Inputs above 1 GB of memory or 60 s are reported (oom-*, timeout-*) and the run restarts.
#   [GONIO_FUZZ_TARGETS="material exr"] fuzz/run_long.sh BUILD_DIR [SECONDS] [OUT]
set -euo pipefail
src="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "$1" && pwd)"
seconds="${2:-14400}"
out="${3:-/tmp/gonio-fuzz-long}"
for t in ${GONIO_FUZZ_TARGETS:-material merl scene obj png exr surface mtlx gltf rgl}; do
  mkdir -p "$out/$t/corpus" "$out/$t/bin"
  cp "$build/bin/fuzz_$t" "$out/$t/bin/"  # a rebuild must not replace the running binary
  dict=()
  case "$t" in material | scene | surface) dict=(-dict="$src/json.dict") ;; mtlx) dict=(-dict="$src/mtlx.dict") ;; esac
  # Seeds without the known reproducers (crash-*), which would end every run at start.
  mkdir -p "$out/$t/seeds"
  find "$src/corpus/$t" -maxdepth 1 -type f ! -name 'crash-*' -exec cp {} "$out/$t/seeds/" \;
  (
    cd "$out/$t"
    end=$((SECONDS + seconds))
    n=$(find . -maxdepth 1 -name 'run-*.log' | wc -l)  # a resumed campaign keeps its logs
    while ((SECONDS < end)); do
      n=$((n + 1))
      nice -n 10 "./bin/fuzz_$t" "${dict[@]}" -max_total_time=$((end - SECONDS)) -print_final_stats=1 -rss_limit_mb=1024 -timeout=60 \
        -artifact_prefix="$out/$t/" corpus seeds >"run-$n.log" 2>&1 || true
      # A reproducer is named <kind>-<sha1>, as its copy in the grown corpus is <sha1>:
      # drop that copy so that the next run does not stop on it again.
      for a in crash-* oom-* timeout-* leak-*; do [ -e "$a" ] && rm -f "corpus/${a#*-}"; done
    done
  ) </dev/null >/dev/null 2>&1 &
  disown
done
echo "logs: $out/<target>/run-N.log" >&2
