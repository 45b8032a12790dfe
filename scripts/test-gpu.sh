#!/usr/bin/env bash
# Runs the tests that draw on a Vulkan device — CTest labels gpu, golden, cli and viewer: every test but the
# unit ones — on whatever device is present (a GPU when there is one, else lavapipe, as the commands choose),
# after building what they need. Prints the device, the summary, and each skipped test with its reason (a test
# that cannot check something on this device says so and counts as skipped, never as passed; tests/support/skip.h).
# Extra arguments go to ctest (-R name, -j N, ...). Exit status: ctest's.
set -euo pipefail
cd "$(dirname "$0")/.."
# INKWELL_WERROR=ON/OFF when given; otherwise the build directory keeps its setting.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release ${INKWELL_WERROR:+-DINKWELL_WERROR=$INKWELL_WERROR} >/dev/null
cmake --build build -j"$(nproc)"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The device the commands (and the tests' GpuFixture) pick by default, from a tiny render's statistics.
build/inkwell render assets/bunny.obj --control-points 50 --levels 1 --size 64 64 -q -o "$tmp/probe.png" \
  --stats "$tmp/probe.json" >/dev/null
device=$(python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); print(d["device"], "|", d["driver"])' \
  "$tmp/probe.json")
echo "test-gpu: device: $device"

status=0
(cd build && ctest -L 'gpu|golden|cli|viewer' --output-on-failure -j"$(nproc)" "$@") || status=$?
echo "test-gpu: device: $device"
# The reasons, from the tests' output (a skipped test's output is not printed by ctest).
if grep -h "^SKIPPED: " build/Testing/Temporary/LastTest.log >"$tmp/skips" 2>/dev/null && [ -s "$tmp/skips" ]; then
  echo "test-gpu: $(wc -l <"$tmp/skips") skipped:"
  sed 's/^SKIPPED: /  /' "$tmp/skips"
else
  echo "test-gpu: none skipped"
fi
exit "$status"
