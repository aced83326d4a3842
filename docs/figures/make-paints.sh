#!/usr/bin/env bash
# scenes/paints.json three ways, left to right: full spectral under D65 as the scene says; full
# spectral under illuminant A (the metameric greys at the bottom part; the rest is adapted to A's
# white); the same A render through the rgb representation (each paint's body reflectance reduced
# to three channels — the greys match again, as an RGB renderer would show them). 400×267 each,
# CIE 1931 observer on an sRGB display. Needs a build (bash ci/build.sh) and oiiotool
# (openimageio-tools).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
metamer="${METAMER:-$here/build/metamer}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
size=(--set camera.width=400 --set camera.height=267)
panels=()
for case in d65 a rgb; do
  case "$case" in
    d65) flags=() label="full spectral, D65" ;;
    a) flags=(--set lights.0.spectrum=illuminants/A) label="full spectral, A" ;;
    *) flags=(--set lights.0.spectrum=illuminants/A --mode rgb) label="rgb, A" ;;
  esac
  "$metamer" render "$here/scenes/paints.json" --out "$work/$case" --write png "${size[@]}" "${flags[@]}"
  # A black band of 36 px below each panel holds its label.
  panels+=("$work/$case/paints.png" --fullsize 400x303 --croptofull
           --text:x=12:y=292:size=20:color=1,1,1:font="$font" "$label")
done
oiiotool "${panels[@]}" --mosaic:pad=8 3x1 -d uint8 -o "$here/docs/figures/paints.png"
echo "wrote docs/figures/paints.png (left to right: full spectral D65, full spectral A, rgb A)"
