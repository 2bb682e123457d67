#!/usr/bin/env bash
# Regenerates the lecture's figures of docs/lecture.md into docs/figures/ (or DIR):
#   docs/figures/make.sh [DIR] [--quick]
# Needs the build's Python module (cmake --build build --target _gonio); uses Debian's
# /usr/bin/python3 when present, like the build (GONIO_PYTHON overrides it).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-$root/docs/figures}"
shift || true
python="${GONIO_PYTHON:-$( [ -x /usr/bin/python3 ] && echo /usr/bin/python3 || echo python3 )}"
PYTHONPATH="$root/build/python${PYTHONPATH:+:$PYTHONPATH}" MPLBACKEND=Agg \
  "$python" "$root/docs/figures/lecture_figures.py" "$out" "$@"
