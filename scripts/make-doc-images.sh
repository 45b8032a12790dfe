#!/usr/bin/env bash
# Regenerates the pictures in docs/images from the current build (build/inkwell).
set -euo pipefail
cd "$(dirname "$0")/.."
ink=build/inkwell
out=docs/images
mkdir -p "$out"
$ink -q render assets/bunny.obj --control-points 684 --size 640 640 -o $out/bunny-stipple.png
$ink -q render assets/bunny.obj --control-points 684 --size 640 640 --distribution refinement \
  -o $out/bunny-stipple-refinement.png
$ink -q render assets/bunny.obj --control-points 684 --size 640 640 --hidden-lines --camera 120,25,1.6 --light-follows-camera \
  -o $out/bunny-hidden-lines.png
$ink -q render assets/bunny.obj --control-points 684 --preset assets/presets/engraving.json --size 640 640 \
  -o $out/bunny-engraving.png
$ink -q render assets/bunny.obj --control-points 684 --style direction --levels 5 --size 640 640 \
  --camera 150,20,1.6 -o $out/bunny-direction.png
$ink -q render assets/bunny.obj --control-points 684 --style direction --direction curvature-max --levels 5 \
  --size 640 640 -o $out/bunny-curvature.png
# Vector output for plotters: the bunny with hidden lines on an A5 page, as rsvg-convert (librsvg2-bin) draws
# the SVG: the whole page, and a detail at 8x (the paths a pen draws).
svg=$(mktemp --suffix=.svg)
trap 'rm -f "$svg"' EXIT
$ink -q render assets/bunny.obj --control-points 684 --size 640 640 --hidden-lines --page A5 --margin 10 -o "$svg" \
  > /dev/null
rsvg-convert -h 640 -b white -o $out/bunny-plot.png "$svg"
rsvg-convert -z 8 --left=-3150 --top=-2656 --page-width 452 --page-height 640 -b white \
  -o $out/bunny-plot-detail.png "$svg"
# The stipples on the page (docs/algorithm.md §4): a torus mesh (R 1, r 0.42, 64 × 32 quads, as the issue targets
# make it), the ranked prefix alone and spaced on the page.
torus=$(mktemp --suffix=.obj)
trap 'rm -f "$svg" "$torus"' EXIT
python3 scripts/make-torus-mesh.py "$torus"
$ink -q render "$torus" --camera 30,15,1.6 --no-screen-spacing -o $out/stipples-before.png
$ink -q render "$torus" --camera 30,15,1.6 -o $out/stipples-after.png
# Pen lines (docs/lines.md): contours alone, hatching (one family), cross-hatching with stipples, and the presets.
$ink -q render assets/bunny.obj --control-points 684 --style contours --hidden-lines --size 640 640 \
  -o $out/bunny-contours.png
$ink -q render assets/bunny.obj --control-points 684 --style contours+hatching --hatch-families 1 --size 640 640 \
  -o $out/bunny-hatching.png
$ink -q render assets/bunny.obj --control-points 684 --preset assets/presets/crosshatch-stipple.json --size 640 640 \
  -o $out/bunny-crosshatch-stipple.png
$ink -q render assets/bunny.obj --control-points 684 --preset assets/presets/pen.json --size 640 640 \
  --camera 120,25,1.6 -o $out/bunny-pen.png
# Refinement levels 0-4 as the report makes them (ρ/3 a level), each level alone, without tone, for stippling
# and direction sampling: every point facing the eye a round dot (τ 0: no silhouette strokes).
for level in 0 1 2 3 4; do
  for style in stipple direction; do
    $ink -q render assets/bunny.obj --control-points 312 --passes 1 --style $style --levels $level \
      --distribution refinement --keep-levels last --tone 0 --tau 0 --no-occlusion --size 320 320 \
      -o $out/levels-$style-$level.png
  done
done
