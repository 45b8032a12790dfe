#!/usr/bin/env bash
# The contour pictures of docs/lines.md and the README (issue 24): the default fit's contours of the bundled bunny,
# of a generated 64 x 32 torus mesh, and of three of CGAL's test meshes (Debian's libcgal-demo, unpacked to a
# temporary folder; skipped with a note when it is not installed), as rsvg-convert draws the SVGs render writes.
set -euo pipefail
cd "$(dirname "$0")/.."
ink=build/inkwell
out=docs/images
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
draw() {  # draw MODEL NAME STYLE [options...]
  local model=$1 name=$2 style=$3
  shift 3
  $ink -q render "$model" --style "$style" --size 640 640 --page 120x120mm --margin 5 -o "$work/$name.svg" "$@" > /dev/null
  rsvg-convert -w 480 -b white -o "$out/$name.png" "$work/$name.svg"
}
draw assets/bunny.obj contours-bunny contours --hidden-lines
python3 - "$work/torus.obj" <<'PY'
import math, sys
R, r, nu, nv = 1.0, 0.42, 64, 32
with open(sys.argv[1], "w") as f:
    for i in range(nu):
        for j in range(nv):
            u, v = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            f.write("v %.7f %.7f %.7f\n" % ((R + r * math.cos(v)) * math.cos(u), (R + r * math.cos(v)) * math.sin(u), r * math.sin(v)))
    for i in range(nu):
        for j in range(nv):
            a, b, c, d = i * nv + j + 1, (i + 1) % nu * nv + j + 1, (i + 1) % nu * nv + (j + 1) % nv + 1, i * nv + (j + 1) % nv + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (a, b, c, a, c, d))
PY
draw "$work/torus.obj" contours-torus contours --hidden-lines --camera 30,35,1.6
data=/usr/share/doc/libcgal-dev/data.tar.gz
if [ -f "$data" ]; then
  tar -xzf "$data" -C "$work" data/meshes/elephant.off data/meshes/knot1.off data/meshes/mech-holes-shark.off
  draw "$work/data/meshes/elephant.off" contours-elephant contours+hatching
  draw "$work/data/meshes/knot1.off" contours-knot contours+hatching
  draw "$work/data/meshes/mech-holes-shark.off" contours-shark contours+hatching
else
  echo "make-contour-images: libcgal-demo is not installed: the elephant, knot and shark are not redrawn" >&2
fi
