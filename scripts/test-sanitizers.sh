#!/usr/bin/env bash
# The tests that handle input and memory, again, built with AddressSanitizer, LeakSanitizer and
# UndefinedBehaviorSanitizer in build-asan at -O1 (CI runs this after scripts/test.sh, which installs the
# dependencies; docs/robustness.md). Warnings are errors. The unit and command-line tests run; the drawing-heavy
# ones (labels gpu, golden and viewer; the capture, vector and fidelity suites and the cube's SVG test, which
# draw large frames or fit and draw many times on lavapipe) run in the release build only. `--all` runs every
# test. Leaks inside libraries we do not build (the validation layer) are suppressed by tests/support/lsan.supp;
# undefined behaviour in our code ends the program (-fno-sanitize-recover=undefined).
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DINKWELL_SANITIZE=ON -DINKWELL_WERROR=ON >/dev/null
cmake --build build-asan -j"$(nproc)"
# A sanitizer's report exits 86, never 1 (bad input) or 0, so that no test can mistake one for the other.
export ASAN_OPTIONS="detect_leaks=1:check_initialization_order=1:exitcode=86"
export LSAN_OPTIONS="suppressions=$root/tests/support/lsan.supp:print_suppressions=0:exitcode=86"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=86"
cd build-asan
if [ "${1:-}" = --all ]; then
  ctest --output-on-failure -j"$(nproc)"
else
  # Left out besides: the fits and drawings that take a minute or more under the sanitizers (2-core CI machine, -j2)
  # and handle no input of their own: up-axis rules over seven fits (181 s), two-sided parts (98 s), crease lines by
  # style (72 s), the device's cross field and contour tracer against the CPU's (71 s, 40 s), the page spacing
  # (50 s), the cube's crease lines (49 s).
  heavy='^features: a mesh cut flat|^features: a mesh with an open part|^cli: the feature lines are found'
  heavy+='|^lines: --hatch-field device|^lines: --contour-tracer device|^first picture: the stipples are spaced'
  heavy+="|^features: a cube's twelve edges"
  ctest --output-on-failure -j"$(nproc)" -L 'unit|cli' -E "^(capture|vector|fidelity):|^cli: a cube|$heavy"
fi
