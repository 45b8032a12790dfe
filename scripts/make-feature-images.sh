#!/usr/bin/env bash
# The crease and boundary pictures of docs/lines.md and the README (issue 25): three of CGAL's test meshes and a scan
# (Debian's libcgal-dev data, unpacked to a temporary folder; skipped with a note when it is not installed), as
# rsvg-convert draws the SVGs render writes, with the time and line counts render's --stats gives.
set -euo pipefail
cd "$(dirname "$0")/.."
ink=build/inkwell
out=docs/images
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
draw() {  # draw MODEL NAME STYLE [options...]
  local model=$1 name=$2 style=$3
  shift 3
  /usr/bin/time -f "$name: %e s" $ink -q render "$model" --style "$style" --size 640 640 --page 120x120mm \
    --margin 5 -o "$work/$name.svg" --stats "$work/$name.json" "$@" > /dev/null
  rsvg-convert -w 480 -b white -o "$out/$name.png" "$work/$name.svg"
  python3 -c "import json,sys; l=json.load(open(sys.argv[1]))['lines']; print(sys.argv[2], 'creases', l['creases'], 'boundaries', l['boundaries'])" "$work/$name.json" "$name"
}
data=/usr/share/doc/libcgal-dev/data.tar.gz
if [ -f "$data" ]; then
  tar -xzf "$data" -C "$work" data/meshes/fandisk.off data/meshes/elephant-with-holes.off data/meshes/mech-holes-shark.off \
    data/points_3/hippo1.ply
  draw "$work/data/meshes/fandisk.off" fandisk-creases contours --camera 30,25,1.6
  draw "$work/data/meshes/elephant-with-holes.off" elephant-holes contours+stipple
  draw "$work/data/meshes/mech-holes-shark.off" shark-creases contours
  draw "$work/data/points_3/hippo1.ply" hippo1-rims contours+stipple
else
  echo "make-feature-images: libcgal-dev's data is not installed: the fandisk, elephant, shark and hippo are not redrawn" >&2
fi
