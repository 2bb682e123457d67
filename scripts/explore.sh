#!/usr/bin/env bash
# The BRDF explorer for a new user: set up, build, and start `gonio explore` (docs/explore.md).
# Prints the URL to open; Ctrl-C stops it. Arguments go to gonio explore, e.g.
#   scripts/explore.sh --port 8081 --data data/merl --open
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
"$repo/scripts/build.sh" gonio_cli >&2
if ! "$repo/build/bin/gonio" explore --help >/dev/null 2>&1; then
  echo "explore.sh: this build has no gonio explore (is libcpp-httplib-dev installed? scripts/setup.sh installs it)" >&2
  exit 2
fi
exec "$repo/build/bin/gonio" explore "$@"
