#!/usr/bin/env bash
# Speed of the marble scenes (docs/subsurface.md, "Speed"): samples/s with the
# opaque BRDF, the random walk and the diffusion method at equal spp, and the walk's mean
# number of steps. Usage: scripts/subsurface_speed.sh [BUILD_DIR] [SPP] (defaults: build, 8).
set -euo pipefail
build=${1:-build}
export GONIO_SPEED_SPP=${2:-8}
"$build/bin/gonio_render_tests" --gtest_also_run_disabled_tests \
  --gtest_filter='SubsurfaceRenderSpeed.DISABLED_MarbleScenes' | grep -v '^\[\|^$\|^Note:'
