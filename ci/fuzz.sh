#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) with clang in build-fuzz/ and runs each for a bounded time,
# all at once (one process each), starting from the committed seed corpus in fuzz/corpus/<target>/.
# Exits non-zero on a finding: a crash, a sanitizer report (ASan, UBSan), an exception other than
# metamer::Error, a hang (> 10 s on one input) or more than 2 GiB of memory. The input that did it is
# kept under build-fuzz/findings/ and printed in the log; reproduce with
#   build-fuzz/<target>_fuzzer build-fuzz/findings/<file>
# Usage: ci/fuzz.sh [SECONDS per target, default $METAMER_FUZZ_SECONDS or 30] [TARGET ...]
# See docs/numerics.md, "Fuzzing and sanitizers".
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-${METAMER_FUZZ_SECONDS:-30}}"
shift || true
targets=("$@")
((${#targets[@]})) || targets=(scene spectrum envi_header)
build="$here/build-fuzz"

mkdir -p "$build"
# The main build's RGB up-sampling table, when there is one: the same sources fit the same table,
# so it is copied rather than fitted again (85 s on 2 cores).
table=()
[ -f "$here/build/rgb_upsampling_srgb_d65.bin" ] && table=(-DMETAMER_RGB_TABLE_FROM="$here/build/rgb_upsampling_srgb_d65.bin")
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DMETAMER_FUZZ=ON -DMETAMER_BUILD_TESTS=OFF "${table[@]}" >"$build/configure.log" 2>&1 \
  || { cat "$build/configure.log"; exit 1; }
cmake --build "$build" --target fuzzers -j "$(nproc)"

# Fresh working corpora (new inputs go there, never into fuzz/corpus/) and a private TMPDIR for the
# targets' scratch files.
rm -rf "$build/corpus" "$build/findings" "$build/tmp"
mkdir -p "$build/findings" "$build/tmp"
export TMPDIR="$build/tmp"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"

pids=()
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t"
  dict=()
  [ -f "$here/fuzz/$t.dict" ] && dict=(-dict="$here/fuzz/$t.dict")
  "$build/${t}_fuzzer" "$build/corpus/$t" "$here/fuzz/corpus/$t" "${dict[@]}" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$build/findings/$t-" >"$build/$t.log" 2>&1 &
  pids+=($!)
done

status=0
for i in "${!targets[@]}"; do
  t="${targets[$i]}"
  if wait "${pids[$i]}"; then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$build/$t.log")
    echo "fuzz: ${t}_fuzzer: no finding in ${seconds} s (${runs:-?} inputs; log build-fuzz/$t.log)"
  else
    status=1
    echo "fuzz: ${t}_fuzzer: FINDING (log build-fuzz/$t.log):"
    grep -v '^#[0-9]' "$build/$t.log" | tail -n 60
  fi
done
for f in "$build"/findings/*; do
  [ -e "$f" ] || continue
  echo "fuzz: kept $f ($(stat -c %s "$f") bytes); its bytes:"
  od -A d -c "$f" | head -n 40
done
exit "$status"
