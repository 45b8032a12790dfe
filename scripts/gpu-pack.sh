#!/usr/bin/env bash
# Packs this machine's release build for a lent GPU machine that has a driver but no compiler or Vulkan SDK
# (docs/performance.md, "On an NVIDIA H200"): build/inkwell and build/inkwell_tests with the build's CTest files,
# their shared libraries (but glibc's and the Vulkan loader, which travels as Debian's .deb in .gl/), the
# validation layer, and ../shared/tools with the bunny, into .dev/pack.tar.xz (about 14 MB), beside
# scripts/gpu-run.sh as .dev/run.sh. Keep .dev/ and .gl/ out of git (.git/info/exclude). Then, on that machine, from
# the repository root: bash .dev/run.sh [validate tests bench contour field targets].
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
[ -x build/inkwell ] && [ -x build/inkwell_tests ] || { echo "gpu-pack: build first (cmake --build build)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/lib" "$work/layers" "$work/shared/tools" "$work/shared/models"
for b in build/inkwell build/inkwell_tests; do
  ldd "$b" | awk '$3 ~ /^\// {print $3}' | grep -v -E 'lib(c|m|dl|pthread|rt)\.so|ld-linux|libvulkan' |
    xargs -I{} cp -L {} "$work/lib/"
done
cp /usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so "$work/lib/"
cp /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json "$work/layers/"
cp ../shared/tools/* "$work/shared/tools/"
cp ../shared/models/bunny.obj "$work/shared/models/"
# The device's python3 is not /usr/bin/python3.
sed -i 's|PY=/usr/bin/python3|PY=python3|' "$work/shared/tools/targets.sh"
echo "$root" > "$work/origin"  # the build's CTest files name this path
tar -C "$root" -cf "$work/build.tar" --exclude=build/CMakeFiles --exclude=build/libinkwell.a build
mkdir -p .dev .gl
tar -C "$work" -cJf .dev/pack.tar.xz .
cp scripts/gpu-run.sh .dev/run.sh
if ! ls .gl/*.deb > /dev/null 2>&1; then  # the Vulkan loader and GL dispatch, as Debian packs them
  mkdir -p /tmp/amd64/partial
  o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
  apt-get $o update -qq && (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
fi
ls -la .dev .gl
