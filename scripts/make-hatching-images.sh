#!/usr/bin/env bash
# The hatching pictures of docs/lines.md and the README (issue 25): contours and hatching of the bundled bunny and
# of three of CGAL's test meshes (unpacked from libcgal-dev's data to a temporary folder; skipped with a note when
# it is not installed), as rsvg-convert draws the SVGs render writes.
set -euo pipefail
cd "$(dirname "$0")/.."
ink=build/inkwell
out=docs/images
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
draw() {  # draw MODEL NAME [options...]
  local model=$1 name=$2
  shift 2
  $ink -q render "$model" --style contours+hatching --size 640 640 --page 120x120mm --margin 5 -o "$work/$name.svg" \
    "$@" > /dev/null
  rsvg-convert -w 480 -b white -o "$out/$name.png" "$work/$name.svg"
}
draw assets/bunny.obj hatching-bunny
draw assets/bunny.obj hatching-bunny-two --hatch-families 2  # without the third, diagonal family of the darkest tones
data=/usr/share/doc/libcgal-dev/data.tar.gz
if [ -f "$data" ]; then
  tar -xzf "$data" -C "$work" data/meshes/fandisk.off data/meshes/elephant.off data/meshes/knot1.off
  draw "$work/data/meshes/fandisk.off" hatching-fandisk
  draw "$work/data/meshes/elephant.off" hatching-elephant
  draw "$work/data/meshes/knot1.off" hatching-knot
else
  echo "make-hatching-images: libcgal-dev's data is not installed: the fandisk, elephant and knot are not drawn" >&2
fi
