#!/usr/bin/env bash
# Builds everything with AddressSanitizer + UndefinedBehaviorSanitizer (CMake option
# METAMER_SANITIZE; gcc, -Og with line tables and frame pointers) in build-asan/ and runs the test
# suite under them: a memory error, a leak or undefined behaviour in the project's code fails the
# run. Suppressions (ci/lsan.supp, ci/ubsan.supp) cover only the Vulkan drivers, never the
# project's code (docs/numerics.md, "Fuzzing and sanitizers"). Extra arguments go to ctest, e.g.
# `bash ci/sanitize.sh -R SceneJson`.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$here/build-asan"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"

mkdir -p "$build"
# The main build's RGB up-sampling table, when there is one: the same sources fit the same table,
# so it is copied rather than fitted again (85 s on 2 cores).
table=()
[ -f "$here/build/rgb_upsampling_srgb_d65.bin" ] && table=(-DMETAMER_RGB_TABLE_FROM="$here/build/rgb_upsampling_srgb_d65.bin")
# The lobe tables the plain suite built (deterministic data, keyed by gloss and version) are shared
# the same way: building one takes a few seconds of both cores, several times that instrumented.
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMETAMER_SANITIZE=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-Og -g1 -DNDEBUG" "${table[@]}" -DMETAMER_LOBE_CACHE_DIR="$here/build/lobe-cache" \
  >"$build/configure.log" 2>&1 \
  || { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j "$(nproc)"

# The Vulkan loader dlcloses the driver and the layers when the instance goes; LeakSanitizer, which
# runs at exit, would then see the memory they keep for the process's life as leaked from an
# unnamed module that no suppression can match. Preloading them keeps them mapped to the end
# (verify_asan_link_order=0 lets them come before the ASan runtime in the list).
preload=()
for json in /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json \
            /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json; do
  [ -f "$json" ] || continue
  lib="$(sed -n 's/.*"library_path" *: *"\([^"]*\)".*/\1/p' "$json" | head -n 1)"
  [ -n "$lib" ] && preload+=("$lib")
done
if ((${#preload[@]})); then
  LD_PRELOAD="$(IFS=:; echo "${preload[*]}")${LD_PRELOAD:+:$LD_PRELOAD}"
  export LD_PRELOAD
fi
export ASAN_OPTIONS="detect_leaks=1:verify_asan_link_order=0:strict_string_checks=1:check_initialization_order=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$here/ci/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$here/ci/ubsan.supp"

cd "$build"
# The scene-level comparisons of whole GPU renders (GPU against the CPU reference, the response
# pass against the bands, every representation and texture kind) and the harnesses around the
# binary (the Slurm daemons, the Xvfb window, the colour-science oracle) and the lobe tables'
# certification (1.5 · 10⁵ oracle integrals) run in the plain suite;
# under the sanitizers they would cost several of CI's 30 minutes on 2 cores for code the unit
# tests, the bad-input corpus and the CLI tests already drive. So do the scale test of the scene
# reader (2·10⁵ objects through the code every scene test reads with) and the bad-input corpus's
# second pass on the CPU backend: its 218 cases fail in the same reader and checks on either
# backend, and each is an instrumented process start (65 s of the 2 cores' time per backend).
# Arguments replace this default.
if (($# == 0)); then
  set -- -E '^(GpuVsReference|ResponsePass|Representation|Textures|LobeCertification)\.|^(slurm_batch|preview_window|colorimetry_standards)$|^SceneJson\.TwoHundredThousandObjects|^BadInputs\.EachFailsCleanlyOnTheCpuBackend$'
fi
ctest --output-on-failure -j "$(nproc)" --timeout 900 "$@"
