#!/usr/bin/env bash
# The tests that handle input and memory, again, built with AddressSanitizer, LeakSanitizer and
# UndefinedBehaviorSanitizer in build-asan at -O1 with clang (CI runs this after scripts/test.sh; it installs
# clang-14 if it is missing; docs/robustness.md). Clang, not GCC: GCC's UndefinedBehaviorSanitizer took 585 s to
# build what clang builds in about 400, and the tests run as fast. Warnings are errors. The unit and command-line
# tests run; the drawing-heavy ones (labels gpu, golden and viewer; the capture, vector and fidelity suites and the
# cube's SVG test, which draw large frames or fit and draw many times on lavapipe) run in the release build only.
# `--all` runs every test. Leaks inside libraries we do not build (the validation layer) are suppressed by
# tests/support/lsan.supp; undefined behaviour in our code ends the program (-fno-sanitize-recover=undefined).
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
scripts/install-deps.sh clang-14 libclang-rt-14-dev >/dev/null
# A build-asan configured with another compiler (GCC, before) starts again: CMake cannot switch a build's compiler.
grep -qs '^CMAKE_CXX_COMPILER:.*clang++-14$' build-asan/CMakeCache.txt || rm -rf build-asan
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DINKWELL_SANITIZE=ON -DINKWELL_WERROR=ON \
  -DCMAKE_CXX_COMPILER=clang++-14 >/dev/null
cmake --build build-asan -j"$(nproc)"
# A sanitizer's report exits 86, never 1 (bad input) or 0, so that no test can mistake one for the other.
export ASAN_OPTIONS="detect_leaks=1:check_initialization_order=1:exitcode=86"
export LSAN_OPTIONS="suppressions=$root/tests/support/lsan.supp:print_suppressions=0:exitcode=86"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=86"
cd build-asan
if [ "${1:-}" = --all ]; then
  ctest --output-on-failure -j"$(nproc)"
else
  # Left out besides: the fits and drawings that take 15 s or more under the sanitizers (clang, 2-core CI machine,
  # -j2; docs/robustness.md lists their seconds) and read no input of their own: they draw generated shapes or the
  # bunny, as many others that stay do in less time.
  heavy=(
    "features: a mesh cut flat" "features: a mesh with an open part" "cli: the feature lines are found"
    "lines: --hatch-field device" "lines: --contour-tracer device" "first picture: the stipples are spaced"
    "features: a cube.s twelve edges" "features: the far field.s stray sheets" "cli: an open mesh.s rim is drawn"
    "contours: closed curves too small" "fit: a coin a hundredth" "fit: a noisy point cloud is smoothed"
    "fit: a cloud without normals" "contours: the pieces a hole.s own wall" "features: a low-poly mesh.s own faces"
    "contours: fitted meshes have their true cusps" "hatching: a flat face is hatched"
    "pu: the bunny and a torus interpolate" "contours: swallowtails smaller" "features: an open hemisphere.s rim"
    "cli: render refines a level more"
  )
  skip="^(capture|vector|fidelity):|^cli: a cube"
  for name in "${heavy[@]}"; do skip+="|^$name"; done
  ctest --output-on-failure -j"$(nproc)" -L 'unit|cli' -E "$skip"
fi
