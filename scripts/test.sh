#!/usr/bin/env bash
# The README's second command (and CI's): build and run every test. Set INKWELL_WERROR=ON to make compiler
# warnings errors (CI does).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DINKWELL_WERROR="${INKWELL_WERROR:-OFF}" >/dev/null
cmake --build build -j"$(nproc)"
cd build
ctest --output-on-failure -j"$(nproc)"
