#!/usr/bin/env bash
# Installs Inkwell's build and test dependencies from Debian 12 packages. Idempotent: installs only what is
# missing. Needs root (apt-get); run it with sudo, or as root. What the tests run besides the build: xvfb-run,
# xauth and xdotool (the viewer tests), rsvg-convert (librsvg2-bin) and pdftoppm (poppler-utils) (the vector
# tests), the validation layers (every gpu test), python3 (scripts/check-layering.py, test-gpu.sh, test-install.sh).
# Packages named as arguments are wanted too: CI's other builds ask for theirs this way (clang-14 and
# libclang-rt-14-dev for the sanitizer and fuzzing builds, g++-aarch64-linux-gnu for the ARM64 one).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools glslang-tools spirv-tools
  libeigen3-dev libglm-dev libglfw3-dev doctest-dev libstb-dev libcli11-dev nlohmann-json3-dev
  libopenblas-dev libtinygltf-dev libnanoflann-dev libimgui-dev xvfb xauth xdotool imagemagick clang-format
  librsvg2-bin poppler-utils python3
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages are installed"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing packages: ${missing[*]}" >&2
  echo "install-deps: run as root to install them: sudo $0" >&2
  exit 1
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
