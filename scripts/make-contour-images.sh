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
python3 scripts/make-torus-mesh.py "$work/torus.obj"
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
