#!/usr/bin/env bash
# scenes/filters.json three ways, left to right: full spectral under D65 as the scene says; the
# same through the rgb representation (gels, dye and glass multiplied in three channels, as an RGB
# renderer would); full spectral with the key light switched to illuminant A. 400×267 each, CIE
# 1931 observer on an sRGB display. Needs a build (bash ci/build.sh) and oiiotool (openimageio-tools).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/mosaic.sh"
scene=scenes/filters.json
size=(--set camera.width=400 --set camera.height=267)
label_band 36 20
panel "full spectral, D65" "$scene" "${size[@]}"
panel "rgb, D65" "$scene" "${size[@]}" --mode rgb
panel "full spectral, key light A" "$scene" "${size[@]}" --set lights.0.spectrum=illuminants/A
mosaic filters
