#!/usr/bin/env bash
# Configures and builds gonio in build/ (Release). The CLI ends up at build/bin/gonio.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
