#!/usr/bin/env bash
# The paper's Figure 5: scenes/imaging-systems.json as seen by a human observer (CIE 1931), a
# digital camera (Nikon D5100, NPL measured sensitivities) and a colour transparency film (the
# parametric reversal model of spectra/film), left to right, each shown on an sRGB display after
# Bradford adaptation to D65. Needs a build (bash ci/build.sh) and oiiotool (openimageio-tools).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
metamer="${METAMER:-$here/build/metamer}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
panels=()
for detector in cie1931 camera:nikon_d5100 film:reversal; do
  name="${detector//:/-}"
  "$metamer" render "$here/scenes/imaging-systems.json" --out "$work/$name" --detector "$detector" \
    --adapt bradford --display srgb --write png
  case "$detector" in
    cie1931) label="CIE 1931 observer" ;;
    camera:*) label="Nikon D5100" ;;
    *) label="reversal film" ;;
  esac
  # A black band of 40 px below each panel holds its label.
  panels+=("$work/$name/imaging-systems.png" --fullsize 480x400 --croptofull
           --text:x=14:y=388:size=24:color=1,1,1:font="$font" "$label")
done
oiiotool "${panels[@]}" --mosaic:pad=8 3x1 -d uint8 -o "$here/docs/figures/figure5.png"
echo "wrote docs/figures/figure5.png (left to right: CIE 1931 observer, Nikon D5100, reversal film)"
