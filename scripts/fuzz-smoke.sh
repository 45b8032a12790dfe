#!/usr/bin/env bash
# CI's short fuzzing run: builds the libFuzzer targets (fuzz/, clang) in build-fuzz and runs each for
# ${FUZZ_SECONDS:-10} seconds (one target per core at a time) from its seed corpus (copied, so the checked-in corpus is never modified).
# A crash, a leak, undefined behaviour or an unexpected exception fails it; the input that did is kept
# under build-fuzz/findings/. Longer runs: FUZZ_SECONDS=600 scripts/fuzz-smoke.sh (docs/robustness.md).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh clang-14 libclang-rt-14-dev >/dev/null
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Release -DINKWELL_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++-14 >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz >/dev/null
seconds="${FUZZ_SECONDS:-10}"
mkdir -p build-fuzz/findings
# One target per core at a time: each is single-threaded.
fuzz_one() {
  local target=$1 name corpus dict=() runs
  name=$(basename "$target" | sed 's/^fuzz_//')
  corpus=$(mktemp -d)
  cp -r "fuzz/corpus/$name/." "$corpus/" 2>/dev/null || true
  [ -f "fuzz/dict/$name.dict" ] && dict=(-dict="fuzz/dict/$name.dict")
  if ! "$target" "$corpus" "${dict[@]}" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
       -artifact_prefix="build-fuzz/findings/$name-" -print_final_stats=1 >"build-fuzz/findings/$name.log" 2>&1; then
    tail -30 "build-fuzz/findings/$name.log" >&2
    echo "fuzz-smoke: $name failed; the input is in build-fuzz/findings/" >&2
    rm -rf "$corpus"
    return 1
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "build-fuzz/findings/$name.log" | grep -o '[0-9]*$' || echo "?")
  echo "fuzz-smoke: $name: $runs runs in ${seconds} s, nothing found"
  rm -rf "$corpus"
}
jobs_max=$(nproc)
rm -f build-fuzz/findings/*.failed
for target in build-fuzz/fuzz/fuzz_*; do
  [ -x "$target" ] || continue
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  (fuzz_one "$target" || touch "build-fuzz/findings/$(basename "$target").failed") &
done
wait
if ls build-fuzz/findings/*.failed >/dev/null 2>&1; then exit 1; fi
