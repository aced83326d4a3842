#!/usr/bin/env bash
# The cost of interreflection (docs/performance.md, "Interreflection"): scenes/cornell-box.json,
# lit only through interreflection, at 512²:
#   start to PNG: the wall time of `metamer render --write png`, process start to exit, median of
#                 RUNS, with interreflection as shipped, with `refine` 1, and off (the light alone);
#   its parts:    from -v, the form factors, the solve and the gather at the vertices (view-
#                 independent: once per scene) and from --timings the frame;
#   a spectrum change: in one Python process, the first render and the median of those after it
#                 with another light scale (the form factors kept: radiosity/geometry_cache.h; the
#                 last solve rescaled), then with the red wall's reflectance swapped (a solve);
#   per band against Mitsuba 3: the stored reference's seconds (tests/data/cornell/mitsuba.json,
#                 its noise there) over Metamer's, each per band, both at 64² (Metamer ssaa 4).
# One run per row; compare within a run (the machine is shared). Prints figures, asserts nothing.
# The lavapipe ceiling (../shared/tools/lavapipe-ceiling, built by its build.sh) runs beside it
# when CEILING names its binary (proto).
#
#   bash ci/bench-interreflection.sh [RUNS]    default: 5
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
metamer="${METAMER:-$here/build/metamer}"
runs="${1:-5}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
scene="$here/scenes/cornell-box.json"

median() { python3 -c "import statistics, sys; print(f'{statistics.median(map(float, sys.argv[1:])):.2f}')" "$@"; }

wall() {  # ARGS...: the median wall time of `metamer render ARGS`, seconds
  local times=()
  for ((i = 0; i < runs; ++i)); do
    local t0 t1
    t0="$(date +%s.%N)"
    "$metamer" render "$scene" --out "$work/out" --write png "$@" >/dev/null 2>&1
    t1="$(date +%s.%N)"
    times+=("$(python3 -c "print($t1 - $t0)")")
  done
  median "${times[@]}"
}

echo "Cornell box, 512², start to PNG (median of $runs):"
printf "  %-34s %8s s\n" "interreflection as shipped" "$(wall)"
printf "  %-34s %8s s\n" "refine 1 (threshold 0.05)" "$(wall --set interreflection.refine=1)"
printf "  %-34s %8s s\n" "off (the light alone)" "$(wall --set interreflection=false)"

echo "its parts (one run, -v --timings):"
out="$("$metamer" render "$scene" --out "$work/out" --write png -v --timings 2>&1)"
grep -oE "interreflection: [0-9]+ elements.*in all" <<<"$out" | sed 's/^/  /'
grep -iE "^ *(timings|upload|shading|tonemap|frame|total)" <<<"$out" | sed 's/^/  /' || true

echo "a spectrum change in one process (Python, 64², the light's scale; form factors kept, geometry_cache.h):"
PYTHONPATH="$here/build/python" "${PYTHON:-$here/.venv/bin/python}" - "$scene" "$runs" <<'PY'
import statistics, sys, time
import metamer
scene, runs = sys.argv[1], int(sys.argv[2])
def render(scale):
    t = time.perf_counter()
    r = metamer.render(scene, overrides={"camera.width": 64, "camera.height": 64,
                                         "materials.light.emitted_radiance.scale": scale})
    return time.perf_counter() - t, r.timings_ms["upload"]
first = render(1.0)
after = [render(0.5 + 0.1 * k) for k in range(runs)]
print(f"  first render {first[0]:.2f} s (upload {first[1]:.0f} ms); each spectrum after it: median "
      f"{statistics.median(a for a, _ in after):.2f} s (upload {statistics.median(u for _, u in after):.0f} ms)")
# A reflectance change is not a scaling of the emission: a solve, from the last one.
def repaint(k):
    t = time.perf_counter()
    r = metamer.render(scene, overrides={"camera.width": 64, "camera.height": 64,
                                         "materials.red.diffuse": ["cornell/green", "cornell/red"][k % 2]})
    return time.perf_counter() - t, r.timings_ms["upload"]
swaps = [repaint(k) for k in range(runs)]
print(f"  the red wall's reflectance swapped (green, red, ...): median {statistics.median(a for a, _ in swaps):.2f} s "
      f"(upload {statistics.median(u for _, u in swaps):.0f} ms)")
PY

echo "per band against Mitsuba 3 (64², the stored reference):"
t0="$(date +%s.%N)"
"$metamer" render "$scene" --out "$work/small" --write cube --set camera.width=64 --set camera.height=64 --ssaa 4 >/dev/null 2>&1
t1="$(date +%s.%N)"
python3 - "$here/tests/data/cornell/mitsuba.json" "$(python3 -c "print($t1 - $t0)")" <<'PY'
import json, sys
info = json.load(open(sys.argv[1]))
ours = float(sys.argv[2])
bands_m = 59  # its film: 405-695 nm in 5 nm boxes
mitsuba = info["seconds"]
noise = ", ".join(f"{k} nm {v['median']:.3f}" for k, v in info["relative_standard_error"].items())
print(f"  Mitsuba {info['version']} {info['variant']}: {mitsuba:.0f} s for {info['spp_total']} spp, {bands_m} bands: "
      f"{mitsuba / bands_m:.2f} s per band (its relative noise per band, median: {noise})")
print(f"  Metamer (GPU, ssaa 4, 61 bands, start to exit): {ours:.2f} s: {ours / 61:.3f} s per band")
print(f"  ratio per band: {(mitsuba / bands_m) / (ours / 61):.0f}x")
PY

if [ -n "${CEILING:-}" ]; then
  echo "lavapipe ceiling ($CEILING):"
  (cd "$(dirname "$CEILING")" && MODES=b "./$(basename "$CEILING")" 2>/dev/null)
fi
