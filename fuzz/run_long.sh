#!/usr/bin/env bash
# The long fuzzing run of docs/robustness.md: each target for SECONDS (default 4 h) in
# its own working directory under OUT (default /tmp/gonio-fuzz-long), one job each
# (-jobs=1; the log is OUT/<target>/fuzz-0.log), the repository's seeds read-only and the
# grown corpus in OUT/<target>/corpus. Crash reproducers land in OUT/<target>/.
#   fuzz/run_long.sh BUILD_DIR [SECONDS] [OUT]
set -euo pipefail
src="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "$1" && pwd)"
seconds="${2:-14400}"
out="${3:-/tmp/gonio-fuzz-long}"
for t in material scene obj png exr; do
  mkdir -p "$out/$t/corpus" "$out/$t/bin"
  cp "$build/bin/fuzz_$t" "$out/$t/bin/"  # a rebuild must not replace the running binary
  dict=()
  case "$t" in material | scene) dict=(-dict="$src/json.dict") ;; esac
  (cd "$out/$t" && nohup nice -n 10 "./bin/fuzz_$t" "${dict[@]}" -jobs=1 -max_total_time="$seconds" \
     -artifact_prefix="$out/$t/" -print_final_stats=1 corpus "$src/corpus/$t" >/dev/null 2>&1 &)
done
echo "logs: $out/<target>/fuzz-0.log" >&2
