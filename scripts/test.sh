#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite twice: a Release build, then a build
# under AddressSanitizer + UndefinedBehaviorSanitizer (reduced sample counts) that fails
# on any sanitizer report.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"

scripts/setup.sh

echo "== Release build and tests ==" >&2
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$jobs"
ctest --test-dir build --output-on-failure -j"$jobs"

echo "== ASan + UBSan build and tests ==" >&2
# -O1 without debug info: the sanitizers need neither, and it builds twice as fast.
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1" \
  -DGONIO_SANITIZE=ON -DGONIO_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-sanitize -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
GONIO_TEST_SCALE=0.1 \
  ctest --test-dir build-sanitize --output-on-failure -j"$jobs"
echo "all tests passed" >&2
