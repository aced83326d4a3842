#!/usr/bin/env bash
# Builds and runs the whole test suite (googletest + script tests) under CTest, Vulkan validation
# layers on, on whatever Vulkan device is present (lavapipe on a machine without a GPU).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
bash "$here/ci/build.sh"
cd "$here/build"
ctest --output-on-failure -j "$(nproc)" --timeout 600
