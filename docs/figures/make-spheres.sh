#!/usr/bin/env bash
# scenes/spheres.json three ways, left to right: as the paper's OpenGL could show it (no shadows,
# no environment: the metals are black but for their highlights), with shadows, and with shadows
# and the sky and ground the scene describes (the metals show their colour). 384² each, CIE 1931
# observer on an sRGB display. Needs a build (bash ci/build.sh) and oiiotool (openimageio-tools).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/mosaic.sh"
scene=scenes/spheres.json
size=(--set camera.width=384 --set camera.height=384)
no_env=(--set lights.2.scale=0 --set lights.3.scale=0)
no_shadows=(--set lights.0.shadows=false --set lights.1.shadows=false)
label_band 40 22
panel "no shadows, no environment" "$scene" "${size[@]}" "${no_env[@]}" "${no_shadows[@]}"
panel "shadows" "$scene" "${size[@]}" "${no_env[@]}"
panel "shadows, sky and ground" "$scene" "${size[@]}"
mosaic spheres
