#!/usr/bin/env bash
# Rewrites the golden images of tests/golden/ after an intended change to what Inkwell draws: builds, then
# runs the golden tests with INKWELL_UPDATE_GOLDENS=1 on lavapipe (docs/capture.md). Review the new
# pictures (git diff shows which changed) before committing them.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
# The goldens are lavapipe's pictures: make the Vulkan loader see only lavapipe, even beside a real GPU.
for icd in /usr/share/vulkan/icd.d/lvp_icd.*.json; do
    if [ -e "$icd" ]; then
        export VK_DRIVER_FILES="$icd" VK_ICD_FILENAMES="$icd"  # the loader's new and old names for it
        break
    fi
done
INKWELL_UPDATE_GOLDENS=1 build/inkwell_tests --test-case='capture: golden *'
git status --short tests/golden/ || true
