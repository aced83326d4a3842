#!/usr/bin/env bash
# scenes/spheres.json three ways, left to right: as the paper's OpenGL could show it (no shadows,
# no environment: the metals are black but for their highlights), with shadows, and with shadows
# and the sky and ground the scene describes (the metals show their colour). 384² each, CIE 1931
# observer on an sRGB display. Needs a build (bash ci/build.sh) and oiiotool (openimageio-tools).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
metamer="${METAMER:-$here/build/metamer}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
size=(--set camera.width=384 --set camera.height=384)
no_env=(--set lights.2.scale=0 --set lights.3.scale=0)
no_shadows=(--set lights.0.shadows=false --set lights.1.shadows=false)
panels=()
for case in plain shadows environment; do
  case "$case" in
    plain) flags=("${no_env[@]}" "${no_shadows[@]}") label="no shadows, no environment" ;;
    shadows) flags=("${no_env[@]}") label="shadows" ;;
    *) flags=() label="shadows, sky and ground" ;;
  esac
  "$metamer" render "$here/scenes/spheres.json" --out "$work/$case" --write png "${size[@]}" "${flags[@]}"
  # A black band of 40 px below each panel holds its label.
  panels+=("$work/$case/spheres.png" --fullsize 384x424 --croptofull
           --text:x=12:y=412:size=22:color=1,1,1:font="$font" "$label")
done
oiiotool "${panels[@]}" --mosaic:pad=8 3x1 -d uint8 -o "$here/docs/figures/spheres.png"
echo "wrote docs/figures/spheres.png (left to right: no shadows or environment, shadows, shadows + sky and ground)"
