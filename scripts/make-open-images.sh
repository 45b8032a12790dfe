#!/usr/bin/env bash
# The open-surface picture of docs/usage.md (Open surfaces): CGAL's head.off in its default view, the tests'
# open hemisphere from 60° below and CGAL's one-sided hippo scan from behind, each drawn by an earlier inkwell
# (BEFORE, e.g. one built at a commit before two-sided drawing; left) and by build/inkwell (right). CGAL's data is
# Debian's libcgal-dev (skipped with a note when it is not installed). Needs ImageMagick's convert.
# Usage: scripts/make-open-images.sh BEFORE_INKWELL (512² each)
set -euo pipefail
cd "$(dirname "$0")/.."
before=${1:?usage: make-open-images.sh BEFORE_INKWELL}
after=build/inkwell
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
data=/usr/share/doc/libcgal-dev/data.tar.gz
[ -f "$data" ] || { echo "make-open-images: libcgal-dev's data is not installed" >&2; exit 1; }
tar -xzf "$data" -C "$work" data/meshes/head.off data/points_3/hippo1.ply
row() {  # row NAME MODEL [options...]: before | after
  local name=$1 model=$2
  shift 2
  "$before" -q render "$model" --size 512 512 -o "$work/$name-before.png" "$@"
  "$after" -q render "$model" --size 512 512 -o "$work/$name-after.png" "$@"
  convert "$work/$name-before.png" "$work/$name-after.png" +append "$work/$name.png"
}
row head "$work/data/meshes/head.off"
row hemisphere tests/models/hemisphere.obj --camera 30,-60,1.4
row hippo "$work/data/points_3/hippo1.ply" --camera 210,15,1.7
convert "$work/head.png" "$work/hemisphere.png" "$work/hippo.png" -append docs/images/open-surfaces-before-after.png
echo "docs/images/open-surfaces-before-after.png"
