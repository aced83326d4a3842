#!/usr/bin/env bash
# Builds and runs the whole test suite (googletest + script tests) under CTest, Vulkan validation
# layers on, on whatever Vulkan device is present (lavapipe on a machine without a GPU); then the
# fuzz targets for 30 s each (ci/fuzz.sh) and the suite again, built with AddressSanitizer + UBSan
# (ci/sanitize.sh). METAMER_SKIP_SANITIZERS=1 runs the plain suite only.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
bash "$here/ci/build.sh"
(cd "$here/build" && ctest --output-on-failure -j "$(nproc)" --timeout 600)
if [ "${METAMER_SKIP_SANITIZERS:-0}" != 1 ]; then
  bash "$here/ci/fuzz.sh"
  bash "$here/ci/sanitize.sh"
fi
