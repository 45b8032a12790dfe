#!/usr/bin/env bash
# Cross-compiles the engine library (engine/**/*.cpp) for ARM64 (aarch64-linux-gnu) on an x86-64
# Debian 12 machine, to check that it builds off x86: no x86-only code outside guards, and no warnings (-Werror).
#
# What it builds: the library's object files and their static library, build-arm64/libinkwell_engine.a. It does
# not link an executable: that needs the arm64 builds of the libraries it links (Vulkan loader, OpenBLAS, GLFW)
# through a multiarch setup (dpkg --add-architecture arm64), which pulls a large part of an arm64 system onto
# the machine; compiling every object already catches what is architecture-specific in the sources.
#
# How: the host build is configured into build-arm64/host (it builds only its `shaders` target there, the SPIR-V
# headers the engine includes), and each engine source is compiled with the very command the host build uses
# for it (its compile_commands.json: the same defines, include paths, per-file options and warnings, -Werror
# as CI's), with aarch64-linux-gnu-g++ as the compiler. The host's arch-independent headers (Eigen, glm, Vulkan,
# nlohmann/json, tinyobjloader, stb) come from /usr/include, searched after the cross compiler's own headers.
#
# Installs the cross compiler (g++-aarch64-linux-gnu) with the host build's dependencies if they are missing
# (scripts/install-deps.sh; that needs root: run it with sudo, or as root).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
out=$root/build-arm64
cxx=aarch64-linux-gnu-g++

scripts/install-deps.sh g++-aarch64-linux-gnu >/dev/null

# The host configure: the shader headers, and the compile commands to reuse (a command a source: no unity build,
# so that each source is also checked to compile on its own).
cmake -S . -B "$out/host" -DCMAKE_BUILD_TYPE=Release -DINKWELL_WERROR=ON -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
  -DINKWELL_UNITY_BUILD=OFF >/dev/null
cmake --build "$out/host" --target shaders -j"$(nproc)" >/dev/null

# One line a source: "FILE<TAB>COMMAND", COMMAND the host's, shell-quoted, run from the host build's directory
# with its output path relative to it.
cat >"$out/commands.cmake" <<'EOF'
file(READ "${db}" json)
string(JSON n LENGTH "${json}")
math(EXPR last "${n} - 1")
set(lines "")
foreach(i RANGE ${last})
  string(JSON file GET "${json}" ${i} file)
  string(JSON command GET "${json}" ${i} command)
  cmake_path(IS_PREFIX engine "${file}" NORMALIZE in_engine)
  if(in_engine)
    string(APPEND lines "${file}\t${command}\n")
  endif()
endforeach()
file(WRITE "${list}" "${lines}")
EOF
cmake -Ddb="$out/host/compile_commands.json" -Dengine="$root/engine" -Dlist="$out/commands.txt" \
  -P "$out/commands.cmake"

# Every engine source must be one of the library's: a file the CMake target misses would go unchecked.
shopt -s nullglob
mapfile -t sources < <(find "$root/engine" -name "*.cpp" | sort)
for s in "${sources[@]}"; do
  if ! cut -f1 "$out/commands.txt" | grep -qxF "$s"; then
    echo "build-arm64: $s is not compiled by the host build (CMakeLists.txt's ENGINE_SOURCES)" >&2
    exit 1
  fi
done

# The host command with its compiler (the first word) replaced, run in build-arm64/obj instead of the host
# build's directory, so that the relative output path lands there.
rm -rf "$out/obj" "$out/libinkwell_engine.a"
compile() {
  local command=${1#* }
  mkdir -p "$(dirname "$(sed -E 's/.* -o ([^ ]+) .*/\1/' <<<"$command")")"
  eval "$cxx -idirafter /usr/include $command"
}
export -f compile
export cxx
mkdir -p "$out/obj"
cd "$out/obj"
cut -f2 "$out/commands.txt" | tr '\n' '\0' | xargs -0 -n1 -P"$(nproc)" bash -c 'compile "$1"' _
objects=$(find . -name '*.o' | sort)
aarch64-linux-gnu-ar rcs "$out/libinkwell_engine.a" $objects
echo "build-arm64: $(wc -l <"$out/commands.txt") sources compiled for aarch64 into build-arm64/libinkwell_engine.a"
