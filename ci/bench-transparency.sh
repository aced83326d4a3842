#!/usr/bin/env bash
# The cost of transparent objects (docs/performance.md, "Transparent objects"): scenes/filters.json
# as shipped against the same scene with its transparent objects removed, and without its slab
# (the window: sheets and media only), at 512² and 1024²:
#   cube:    `metamer render --write cube --frames 6 --timings`, the median shading of the frames
#            after the first (band passes, and with transparency the transmission passes);
#   display: `metamer render --write png --frames 6 --timings`, the median shading + tonemap
#            (without transparency the response pass; with it, the band passes and their tonemap).
# One run per row; compare ratios within a run. Prints figures, asserts nothing. The lavapipe
# ceiling (../shared/tools/lavapipe-ceiling, built by its build.sh) is run beside it when CEILING
# names its binary (proto).
#
#   bash ci/bench-transparency.sh [SIZES...]    default: 512 1024
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
metamer="${METAMER:-$here/build/metamer}"
work="$(mktemp -d)"
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(512 1024)
# The variant lives in the scenes folder so that library names resolve the same way.
python3 - "$here/scenes/filters.json" "$here/scenes/bench-filters-opaque.json" "$here/scenes/bench-filters-no-slab.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
clear = {n for n, m in scene["materials"].items() if {"transmittance", "absorbance", "dyes", "slab"} & set(m)}
scene["objects"] = [o for o in scene["objects"] if o.get("material") not in clear]
scene["materials"] = {n: m for n, m in scene["materials"].items() if n not in clear}
json.dump(scene, open(sys.argv[2], "w"))
# And the scene without its slab (the window): sheets and media only, whose camera transmission is
# the channel pass (docs/physics.md, "Transparent objects").
scene = json.load(open(sys.argv[1]))
slabs = {n for n, m in scene["materials"].items() if "slab" in m}
scene["objects"] = [o for o in scene["objects"] if o.get("material") not in slabs]
scene["materials"] = {n: m for n, m in scene["materials"].items() if n not in slabs}
json.dump(scene, open(sys.argv[3], "w"))
PY
trap 'rm -rf "$work" "$here/scenes/bench-filters-opaque.json" "$here/scenes/bench-filters-no-slab.json"' EXIT
median() { grep -oE "median of the other [0-9]+: [^;]*" <<<"$1" | head -1; }
field() {  # OUTPUT NAME: a stage's median from the "median of the other N" line
  median "$1" | grep -oE "$2 [0-9.]+" | grep -oE "[0-9.]+$" || echo "?"
}
printf "%-20s %6s %10s %10s %12s %12s\n" variant size "cube ms" "upload ms" "display ms" "(tonemap ms)"
# Variants: the scene without its transparent objects and as shipped, each with and without the
# key light's shadows (without them, nothing is filtered: no coloured shadows, no transmittance maps).
for size in "${sizes[@]}"; do
  for name in opaque opaque-unshadowed filters filters-unshadowed no-slab no-slab-unshadowed; do
    scene="$here/scenes/filters.json"
    [[ "$name" == opaque* ]] && scene="$here/scenes/bench-filters-opaque.json"
    [[ "$name" == no-slab* ]] && scene="$here/scenes/bench-filters-no-slab.json"
    common=(--set camera.width="$size" --set camera.height="$size" --frames 6 --timings)
    [[ "$name" == *unshadowed ]] && common+=(--set lights.0.shadows=false)
    cube="$("$metamer" render "$scene" --out "$work/$name" --write cube --compression none "${common[@]}" 2>&1)"
    display="$("$metamer" render "$scene" --out "$work/$name-png" --write png "${common[@]}" 2>&1)"
    upload="$(grep -oE 'upload [0-9.]+' <<<"$cube" | head -1 | grep -oE '[0-9.]+')"
    shading="$(field "$cube" shading)"
    dshading="$(field "$display" shading)" dtonemap="$(field "$display" tonemap)"
    dtotal="?"
    [[ "$dshading" != "?" && "$dtonemap" != "?" ]] && dtotal="$(python3 -c "print(f'{$dshading + $dtonemap:.1f}')")"
    printf "%-20s %6s %10s %10s %12s %12s\n" "$name" "${size}²" "$shading" "$upload" "$dtotal" "($dtonemap)"
    [ "$shading" != "?" ] || echo "$cube" >&2
    [ "$dtotal" != "?" ] || echo "$display" >&2
  done
done
if [ -n "${CEILING:-}" ]; then
  echo "lavapipe ceiling ($CEILING):"
  (cd "$(dirname "$CEILING")" && XDG_RUNTIME_DIR="${TMPDIR:-/tmp}" MODES=b "./$(basename "$CEILING")" 2>/dev/null)
fi
