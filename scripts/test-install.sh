#!/usr/bin/env bash
# Installs the library from build/ into a temporary prefix, builds examples/ against the installed package
# (outside the source tree, as an application would), and renders the bundled bunny with it. CI runs it after
# scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=$(mktemp -d)
work=$(mktemp -d)
trap 'rm -rf "$prefix" "$work"' EXIT
cmake --install build --prefix "$prefix" >/dev/null
cp -r examples "$work/src"
cmake -S "$work/src" -B "$work/build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS="-Wall -Wextra -Werror" >/dev/null
cmake --build "$work/build" -j"$(nproc)" >/dev/null
out=$("$work/build/render" assets/bunny.obj "$work/bunny.png" 2>/dev/null)
echo "$out"
drawn=$(echo "$out" | sed -n 's/.* \([0-9]*\) drawn .*/\1/p')
[ "${drawn:-0}" -gt 1000 ] || { echo "test-install: the example drew ${drawn:-no} dots" >&2; exit 1; }
# A real drawing: a PNG of the asked size with ink in it (the example says how many dots it drew).
python3 - "$work/bunny.png" <<'PY'
import struct, sys, zlib
data = open(sys.argv[1], 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
w, h = struct.unpack('>II', data[16:24])
assert (w, h) == (800, 800), f'size {w}x{h}'
print(f'test-install: the installed library rendered a {w}x{h} PNG ({len(data)} bytes)')
PY
echo "test-install: headers installed: $(cd "$prefix/include" && find . -type f | sort | tr '\n' ' ')"
