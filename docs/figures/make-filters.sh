#!/usr/bin/env bash
# scenes/filters.json three ways, left to right: full spectral under D65 as the scene says; the
# same through the rgb representation (gels, dye and glass multiplied in three channels, as an RGB
# renderer would); full spectral with the key light switched to illuminant A. 400×267 each, CIE
# 1931 observer on an sRGB display. Needs a build (bash ci/build.sh) and oiiotool (openimageio-tools).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
metamer="${METAMER:-$here/build/metamer}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
size=(--set camera.width=400 --set camera.height=267)
panels=()
for case in full rgb tungsten; do
  case "$case" in
    full) flags=() label="full spectral, D65" ;;
    rgb) flags=(--mode rgb) label="rgb, D65" ;;
    *) flags=(--set lights.0.spectrum=illuminants/A) label="full spectral, key light A" ;;
  esac
  "$metamer" render "$here/scenes/filters.json" --out "$work/$case" --write png "${size[@]}" "${flags[@]}"
  # A black band of 36 px below each panel holds its label.
  panels+=("$work/$case/filters.png" --fullsize 400x303 --croptofull
           --text:x=12:y=292:size=20:color=1,1,1:font="$font" "$label")
done
oiiotool "${panels[@]}" --mosaic:pad=8 3x1 -d uint8 -o "$here/docs/figures/filters.png"
echo "wrote docs/figures/filters.png (left to right: full spectral, rgb, full spectral with the key light A)"
