#!/usr/bin/env bash
# scenes/cornell-box.json three ways, left to right: full spectral with interreflection, as the
# scene says; the same through the rgb representation (each reflectance and the light reduced to
# three channels before the bounces multiply them); and without interreflection (the light alone:
# every other surface is lit only by light that bounced). 320×320 each, CIE 1931 observer on an
# sRGB display, white the light's emitted radiance. Needs a build (bash ci/build.sh) and oiiotool
# (openimageio-tools).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/mosaic.sh"
scene=scenes/cornell-box.json
size=(--set camera.width=320 --set camera.height=320)
label_band 36 20
panel "full spectral" "$scene" "${size[@]}"
panel "rgb" "$scene" "${size[@]}" --mode rgb
panel "no interreflection" "$scene" "${size[@]}" --set interreflection=false
mosaic cornell
