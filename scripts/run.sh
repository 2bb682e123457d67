#!/usr/bin/env bash
# The main job: set up, build, and print the lecture's Fresnel reflectance table.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >&2
build/bin/gonio table
