#!/usr/bin/env bash
# The tests again, built with AddressSanitizer, LeakSanitizer and UndefinedBehaviorSanitizer in build-asan
# (CI runs this after scripts/test.sh, which installs the dependencies; docs/robustness.md). Warnings are
# errors. Leaks inside libraries we do not build (the validation layer) are suppressed by tests/lsan.supp;
# undefined behaviour in our code ends the program (-fno-sanitize-recover=undefined).
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DINKWELL_SANITIZE=ON -DINKWELL_WERROR=ON >/dev/null
cmake --build build-asan -j"$(nproc)"
# A sanitizer's report exits 86, never 1 (bad input) or 0, so that no test can mistake one for the other.
export ASAN_OPTIONS="detect_leaks=1:check_initialization_order=1:exitcode=86"
export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:print_suppressions=0:exitcode=86"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=86"
cd build-asan
ctest --output-on-failure -j"$(nproc)"
