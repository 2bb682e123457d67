#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite twice: a Release build, then a clang
# build under AddressSanitizer + UndefinedBehaviorSanitizer (reduced sample counts) that
# fails on any sanitizer report; then runs each libFuzzer target of fuzz/, built by that
# same clang build, for a fixed time (GONIO_FUZZ_SECONDS, default 10; one target per core
# at a time) from the seed corpus in fuzz/corpus/. A crash fails the command and leaves its reproducer in
# build-sanitize/artifacts/<target>/.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"

scripts/setup.sh

echo "== Release build and tests ==" >&2
# Without the benchmark programs (`scripts/build.sh` builds them): they are not tests,
# and they would cost two minutes of the budget.
# Unity builds (CMAKE_UNITY_BUILD: up to 8 source files of a target compiled as one): the
# files share most of their headers and template instantiations, and this cuts the
# compile CPU of both builds by about a quarter. Helpers in the files' anonymous
# namespaces must therefore have distinct names (CONTRIBUTING.md). Configure with
# -DCMAKE_UNITY_BUILD=OFF to compile file by file, which also checks that each file
# includes what it uses.
# GONIO_WERROR: a warning in gonio's own code fails the command (both builds).
# clang, as in the sanitizer pass: it compiles gonio in two thirds of gcc's CPU time
# (2026-12-05: 479 against 719 CPU-s for this pass), and the builds are two thirds of the
# command's time. gcc remains scripts/build.sh's compiler, so both compilers' warnings are
# seen. Ninja in a new build directory: Make holds a target's compiles until every target it
# links has been built, Ninja only until the headers it includes are generated, so the two
# cores have work to the end. (CC, CXX and the generator count only when the directory is
# configured the first time: a directory configured before keeps its own.) Its own
# directory, build-test: build/ is the main command's (scripts/run.sh: GCC, file by file,
# which checks that each file includes what it uses), and a user types that command first.
fresh_dir() { if [ -f "$1/CMakeCache.txt" ]; then :; elif command -v ninja >/dev/null; then echo "-GNinja"; fi; }
CC=clang CXX=clang++ cmake -S . -B build-test $(fresh_dir build-test) -DCMAKE_BUILD_TYPE=Release -DGONIO_BUILD_BENCHMARKS=OFF \
  -DCMAKE_UNITY_BUILD=ON -DGONIO_WERROR=ON >/dev/null
cmake --build build-test -j"$jobs"
ctest --test-dir build-test --output-on-failure -j"$jobs"

echo "== ASan + UBSan build (clang, with the libFuzzer targets) and tests ==" >&2
# One clang build serves the sanitizer tests and the fuzz targets: GONIO_FUZZ compiles
# everything with -fsanitize=address,undefined -fno-sanitize-recover=all, and the code the
# fuzz targets reach (the core and renderer libraries) also with -fsanitize=fuzzer-no-link
# (CMakeLists.txt); the tests link the sanitizer runtimes as with GONIO_SANITIZE. A third
# full build (gcc's ASan and a separate fuzz build) used to cost nine minutes of the
# 25-minute budget.
# -O1 with line tables only: the sanitizers need no more, and it builds twice as fast.
# Without the Python module: an ASan-instrumented extension would need the ASan runtime
# preloaded into python3; its C++ (gonio/batch.h, the models) runs under the sanitizers
# through the CLI and the unit tests.
# The albedo tables are data, the same for every build type: generated once, by the
# Release build (a minute of CPU per build otherwise).
tables="$PWD/build-test/generated/microfacet_albedo_tables.cpp"
CC=clang CXX=clang++ cmake -S . -B build-sanitize $(fresh_dir build-sanitize) -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1" \
  -DGONIO_FUZZ=ON -DGONIO_BUILD_BENCHMARKS=OFF -DGONIO_REUSE_ALBEDO_TABLES="$tables" \
  -DGONIO_BUILD_PYTHON=OFF -DCMAKE_UNITY_BUILD=ON -DGONIO_WERROR=ON >/dev/null
# Only what ctest runs (target gonio_tests) and the fuzz targets: the tools' programs are
# built by the Release pass.
cmake --build build-sanitize -j"$jobs" --target gonio_tests gonio_fuzz
# Left out here, run in the Release pass: the value sweeps that start one gonio process
# per case (CliFresnel, CliFinite per material, `gonio check` per material; 3.5 of the
# pass's 8 CPU-minutes, mostly ASan's process start-up), and the suites of bad arguments
# that do the same (CliBsdfErrors, CliInputLimits, CliFiniteMaterials: 3.5 CPU-minutes
# more, an ASan process costing 0.27 CPU-s to start against 0.02 s in Release). The same
# code paths run under the sanitizers in-process (the validator sweep, the model tests,
# the parser and fuzz targets) and through the CLI's other tests. Also left to the Release
# pass: the validator sweep's multiple-scattering rough dielectrics and conductors (2 of
# the pass's 9 CPU-minutes); their code runs here in the Multiscatter tests. And the
# explorer's browser tests (ExploreBrowser: headless Chromium, 4 launches of ~3 s), whose
# server code the API tests run here under the sanitizers. Also left to the Release pass
# (2026-12-04: 140 of the pass's 675 CPU-s): the sweep's openpbr and layered materials and
# OpenPBR's furnace quadratures, whose code runs here in the other OpenPbr*, Layered* and
# adversarial tests; and the CLI suites that start a process per malformed input
# (CliStdinErrors, CliFormat, CliNumberErrors, CliWavelength), whose parsers the fuzz
# targets run under the same sanitizers. And docs.blocks (every block of README.md and docs/
# run as pasted): it needs the Python module, which this build lacks.
# Third-party libraries' own leaks (OpenImageIO's error store) are suppressed by name.
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan_suppressions.txt"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
GONIO_TEST_SCALE=0.1 \
  ctest --test-dir build-sanitize --output-on-failure -j"$jobs" -E '^(CliFresnel\.|AllMaterials/CliFinite|check\.|CliBsdfErrors\.|CliInputLimits\.|CliFiniteMaterials\.|ExploreBrowser\.|Sweep/ValidateBuiltIn\.EveryPropertyHolds/.*(multiscatter|openpbr|layered)|OpenPbrFurnace\.|CliStdinErrors\.|CliFormat\.|CliNumberErrors\.|CliWavelength\.|docs\.blocks$)'

echo "== libFuzzer targets ==" >&2
fuzz_seconds="${GONIO_FUZZ_SECONDS:-10}"
# One fuzzer per core at a time: each is a single process, and each still gets its full
# fuzz_seconds (libFuzzer's -max_total_time is wall time).
fuzz_one() {
  local t="$1" dict=()
  case "$t" in material | scene | surface | explore) dict=(-dict=fuzz/json.dict) ;; mtlx) dict=(-dict=fuzz/mtlx.dict) ;; esac
  # The grown corpus stays in build-sanitize; the repository's seeds are only read.
  mkdir -p "build-sanitize/corpus/$t" "build-sanitize/artifacts/$t"
  build-sanitize/bin/fuzz_"$t" "${dict[@]}" -max_total_time="$fuzz_seconds" -print_final_stats=1 \
    -artifact_prefix="build-sanitize/artifacts/$t/" "build-sanitize/corpus/$t" "fuzz/corpus/$t" \
    >"build-sanitize/fuzz_$t.log" 2>&1
}
targets=(material merl scene obj png exr surface mtlx gltf rgl)
[ -x build-sanitize/bin/fuzz_explore ] && targets+=(explore)  # built with cpp-httplib (gonio explore)
for ((i = 0; i < ${#targets[@]}; i += jobs)); do
  batch=("${targets[@]:i:jobs}")
  pids=()
  for t in "${batch[@]}"; do
    echo "fuzz_$t: ${fuzz_seconds} s" >&2
    fuzz_one "$t" &
    pids+=($!)
  done
  for k in "${!batch[@]}"; do
    t="${batch[k]}"
    if ! wait "${pids[k]}"; then
      wait || true  # the other fuzzers of the batch finish first
      tail -n 60 "build-sanitize/fuzz_$t.log" >&2
      echo "fuzz_$t failed: reproducer in build-sanitize/artifacts/$t/, log build-sanitize/fuzz_$t.log" >&2
      exit 1
    fi
    grep -E "stat::number_of_executed_units" "build-sanitize/fuzz_$t.log" >&2 || true
  done
done
echo "all tests passed" >&2
