#!/usr/bin/env bash
# The paper's Figure 5: scenes/imaging-systems.json as seen by a human observer (CIE 1931), a
# digital camera (Nikon D5100, NPL measured sensitivities) and a colour transparency film (the
# parametric reversal model of spectra/film), left to right, each shown on an sRGB display after
# Bradford adaptation to D65. Needs a build (bash ci/build.sh) and oiiotool (openimageio-tools).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/mosaic.sh"
scene=scenes/imaging-systems.json
display=(--adapt bradford --display srgb)
label_band 40 24
panel "CIE 1931 observer" "$scene" --detector cie1931 "${display[@]}"
panel "Nikon D5100" "$scene" --detector camera:nikon_d5100 "${display[@]}"
panel "reversal film" "$scene" --detector film:reversal "${display[@]}"
mosaic figure5
