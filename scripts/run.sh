#!/usr/bin/env bash
# The main job: set up, build, and render the built-in default scene (gonio render with
# no arguments) to gonio.png in the current directory; gonio prints the path it wrote.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
"$repo/scripts/build.sh" gonio_cli >&2
"$repo/build/bin/gonio" render
