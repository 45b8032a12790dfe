#!/usr/bin/env bash
# The README's first command: install what is missing, build the inkwell program (and its shaders and the
# engine library; not the tests: scripts/test.sh builds those), and render the bundled bunny headless on
# lavapipe (or a GPU, when there is one) to out/bunny.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target inkwell
mkdir -p out
build/inkwell render assets/bunny.obj -o out/bunny.png
echo "wrote $(pwd)/out/bunny.png"
