#!/usr/bin/env bash
# Configures and builds gonio in build/ (Release). The CLI ends up at build/bin/gonio.
# With arguments, builds only those targets (e.g. `scripts/build.sh gonio_cli`).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DGONIO_BUILD_BENCHMARKS=ON >/dev/null
if (($# > 0)); then
  cmake --build build -j"$(nproc)" --target "$@"
else
  cmake --build build -j"$(nproc)"
fi
