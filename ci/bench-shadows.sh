#!/usr/bin/env bash
# The cost of shadows and the environment (docs/performance.md, "Shadows and hemisphere lights"):
# scenes/spheres.json with and without its shadows and its sky and ground, at 512² and 1024²,
# `metamer render --frames 6 --timings` each (medians of the frames after the first; the shadow
# maps are drawn once per scene, in the upload). One run per row: compare ratios within a run.
#
#   bash ci/bench-shadows.sh [SIZES...]    default: 512 1024
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
metamer="${METAMER:-$here/build/metamer}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(512 1024)
# Variants in the scenes folder's tree (library spectra resolve the same way): lights 2 and 3 are
# the sky and the ground; without them the shader has no hemisphere loop at all.
python3 - "$here/scenes/spheres.json" "$here/scenes" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
for name, keep_env, shadows in [("plain", False, False), ("shadows", False, True), ("environment", True, False), ("both", True, True)]:
    d = json.loads(json.dumps(scene))
    d["lights"] = [dict(l, shadows=shadows) if l["type"] in ("directional", "point") else l
                   for l in d["lights"] if keep_env or l["type"] != "hemisphere"]
    json.dump(d, open(f"{sys.argv[2]}/.bench-spheres-{name}.json", "w"))
PY
trap 'rm -rf "$work" "$here"/scenes/.bench-spheres-*.json' EXIT
printf "%-12s %6s %12s %12s %12s\n" variant size "shading ms" "upload ms" "shadow ms"
for size in "${sizes[@]}"; do
  for name in plain shadows environment both; do
    out="$("$metamer" render "$here/scenes/.bench-spheres-$name.json" --out "$work/$name" --write cube --compression none \
           --set camera.width="$size" --set camera.height="$size" --frames 6 --timings 2>&1)"
    shading="$(grep -oE "median of the other [0-9]+: shading [0-9.]+" <<<"$out" | grep -oE "[0-9.]+$" || true)"
    upload="$(grep -oE 'upload [0-9.]+' <<<"$out" | grep -oE '[0-9.]+')"
    shadow="$(grep -oE 'shadow maps: [0-9.]+' <<<"$out" | grep -oE '[0-9.]+' || echo 0)"
    printf "%-12s %6s %12s %12s %12s\n" "$name" "${size}²" "${shading:-?}" "$upload" "$shadow"
    [ -n "$shading" ] || echo "$out" >&2
  done
done
