#!/usr/bin/env bash
# scenes/paints.json three ways, left to right: full spectral under D65 as the scene says; full
# spectral under illuminant A (the metameric greys at the bottom part; the rest is adapted to A's
# white); the same A render through the rgb representation (each paint's body reflectance reduced
# to three channels — the greys match again, as an RGB renderer would show them). 400×267 each,
# CIE 1931 observer on an sRGB display. Needs a build (bash ci/build.sh) and oiiotool
# (openimageio-tools).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/mosaic.sh"
scene=scenes/paints.json
size=(--set camera.width=400 --set camera.height=267)
lamp_a=(--set lights.0.spectrum=illuminants/A)
label_band 36 20
panel "full spectral, D65" "$scene" "${size[@]}"
panel "full spectral, A" "$scene" "${size[@]}" "${lamp_a[@]}"
panel "rgb, A" "$scene" "${size[@]}" "${lamp_a[@]}" --mode rgb
mosaic paints
