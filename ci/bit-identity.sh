#!/usr/bin/env bash
# Bit-identity check for refactors that must not change behaviour: renders every bundled scene on
# both backends (the cube as raw ENVI floats, the display PNG), and two of them in the RGB, AC1C2
# and linear modes, and either records them or compares
# them byte for byte with a recording.
#
#   ci/bit-identity.sh record DIR     render into DIR
#   ci/bit-identity.sh compare DIR    render again and cmp every file with DIR's; exit 1 on any difference
#
# Needs a build (bash ci/build.sh); METAMER overrides the binary. The scenes render at their own
# size; the CPU backend takes a minute or two in all on 2 cores.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
metamer="${METAMER:-$here/build/metamer}"
mode="${1:?record|compare}" dir="${2:?folder}"
case "$mode" in record) out="$dir" ;; compare) out="$(mktemp -d)"; trap 'rm -rf "$out"' EXIT ;; *) echo "record|compare" >&2; exit 2 ;; esac
mkdir -p "$out"
for scene in "$here"/scenes/*.json; do
  name="$(basename "$scene" .json)"
  for backend in gpu cpu; do
    "$metamer" render "$scene" --backend "$backend" --out "$out/$name-$backend" --write cube,png --format envi >/dev/null
  done
done
# The representation modes (represent/representation.cpp) on two scenes with every material kind:
# their channel images are OpenEXR (written without a date, so byte for byte comparable).
for scene in metamers fluorescent; do
  for representation in rgb ac1c2 linear:3; do
    for backend in gpu cpu; do
      "$metamer" render "$here/scenes/$scene.json" --backend "$backend" --mode "$representation" \
        --out "$out/$scene-$backend-${representation/:/}" --write cube,png >/dev/null 2>&1
    done
  done
done
[ "$mode" = record ] && { echo "recorded $(find "$out" -type f | wc -l) files in $out"; exit 0; }
differ=0 total=0
while IFS= read -r f; do
  rel="${f#"$dir"/}"
  total=$((total + 1))
  if ! cmp -s "$f" "$out/$rel"; then echo "differs: $rel"; differ=$((differ + 1)); fi
done < <(find "$dir" -type f \( -name '*.img' -o -name '*.png' -o -name '*.exr' \))
echo "bit-identity: $differ of $total files differ"
[ "$differ" = 0 ]
