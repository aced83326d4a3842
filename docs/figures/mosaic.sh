# What docs/figures/make-*.sh share: render each panel's display PNG, label it in a black band
# below, and lay the panels side by side, 8 px apart. Sourced, then:
#   label_band HEIGHT SIZE       the band's height and the label's font size in px (default 40 22)
#   panel LABEL SCENE [FLAG...]  render SCENE (a path from the checkout's root) with --write png
#                                and FLAGs; LABEL under it, 12 px from the left and the bottom
#   mosaic NAME                  write docs/figures/NAME.png from the panels, left to right
# METAMER names the binary (default build/metamer, from bash ci/build.sh); oiiotool comes with
# openimageio-tools. The scripts source it after `set -euo pipefail`: a failed render stops them.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
metamer="${METAMER:-$here/build/metamer}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
band=40 label_size=22
panels=() labels=()

label_band() { band=$1 label_size=$2; }

panel() {
  local label=$1 scene=$2
  shift 2
  local out="$work/${#labels[@]}"
  "$metamer" render "$here/$scene" --out "$out" --write png "$@"
  # oiiotool evaluates {TOP...} on the image at hand: the band is added below whatever size it is.
  panels+=("$out/$(basename "$scene" .json).png" --fullsize "{TOP.width}x{TOP.height+$band}" --croptofull
           --text:x=12:y="{TOP.height-12}":size="$label_size":color=1,1,1:font="$font" "$label")
  labels+=("$label")
}

mosaic() {
  oiiotool "${panels[@]}" --mosaic:pad=8 "${#labels[@]}x1" -d uint8 -o "$here/docs/figures/$1.png"
  local joined
  joined=$(printf '; %s' "${labels[@]}")
  echo "wrote docs/figures/$1.png (left to right: ${joined:2})"
}
