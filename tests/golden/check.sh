#!/usr/bin/env bash
# One golden test (run by CTest): render NAME from tests/golden/goldens.txt on the GPU and compare
# every output with its golden (made by the CPU reference), within the tolerance beside it, edge
# pixels masked. On failure the heat map and the statistics stay in OUT/NAME/.
#
#   tests/golden/check.sh NAME METAMER_BINARY OUT_DIR
set -euo pipefail
name="$1" metamer="$2" outroot="$3"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
golden="$here/tests/golden"
line="$(awk -v n="$name" '$1 == n' "$golden/goldens.txt")"
[ -n "$line" ] || { echo "check.sh: no golden named '$name' in tests/golden/goldens.txt" >&2; exit 2; }
read -r _ scene outputs flags <<<"$line"
out="$outroot/$name"
rm -rf "$out"
# shellcheck disable=SC2086
"$metamer" render "$here/$scene" --out "$out" --write "$outputs" --validation $flags
status=0
for g in "$golden/$name"/*; do
  base="$(basename "$g")"
  [[ "$base" == *.tolerance.json || "$base" == *.edges.png ]] && continue
  stem="${base%%.*}"
  echo "== $name/$base"
  if ! "$metamer" compare "$out/$base" "$g" --tolerance "$g.tolerance.json" --mask "$golden/$name/$stem.edges.png" \
       --heatmap "$out/$base.heatmap.png" --json "$out/$base.stats.json"; then
    status=1
    echo "FAILED: $name/$base (heat map and statistics in $out)"
  fi
done
exit $status
