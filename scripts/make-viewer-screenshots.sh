#!/usr/bin/env bash
# The viewer's screenshots in docs/viewer.md (docs/images/viewer-*.png): the window with its panel, taken in a
# virtual X server with ImageMagick's `import`, the panel set with xdotool as a user would. Needs xvfb-run,
# xdotool and imagemagick (scripts/install-deps.sh installs them) and the build (build/inkwell).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" != "--in-xvfb" ]; then
  exec xvfb-run -a -s "-screen 0 1280x1024x24" "$0" --in-xvfb
fi
ink=$PWD/build/inkwell
out=$PWD/docs/images
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

# Starts the viewer with `args`, waits for its frames, and sets $wid.
start() {
  "$ink" view "$@" > log.txt 2>&1 &
  pid=$!
  wid=$(timeout 120 xdotool search --sync --onlyvisible --name 'inkwell view')
  timeout 120 xdotool search --sync --onlyvisible --name ' ms$' > /dev/null
  xdotool windowfocus --sync "$wid"
  sleep 1
}
hold() { xdotool keydown "$1"; sleep 0.5; xdotool keyup "$1"; sleep 0.5; }
quit() { hold q; wait "$pid"; }

# The default look, the panel beside it.
start "$OLDPWD/assets/bunny.obj" --control-points 684
xdotool mousemove --window "$wid" 300 700
sleep 1
import -window "$wid" "$out/viewer-panel.png"
# The help over the drawing.
hold F1
sleep 1
import -window "$wid" "$out/viewer-help.png"
quit

# The engraving preset loaded from the panel: typed into its preset field, then "load preset".
cp "$OLDPWD/assets/presets/engraving.json" .
start "$OLDPWD/assets/bunny.obj" --control-points 684
xdotool mousemove --window "$wid" 780 688 click 1
sleep 0.5
hold ctrl+a
xdotool type --delay 50 engraving.json
hold Return
xdotool mousemove --window "$wid" 754 708 click 1
timeout 120 bash -c 'until grep -q "refined both" log.txt; do sleep 0.2; done'
xdotool mousemove --window "$wid" 300 700
sleep 2
import -window "$wid" "$out/viewer-engraving.png"
quit
# Pen lines ticked in the panel: contours, then hatching (traced on the worker thread), with hidden lines.
start "$OLDPWD/assets/bunny.obj" --control-points 684
xdotool mousemove --window "$wid" 722 108 click 1
timeout 120 bash -c 'until grep -q "pen lines: contours" log.txt; do sleep 0.2; done'
xdotool mousemove --window "$wid" 805 108 click 1
timeout 120 bash -c 'until grep -q "hatching traced" log.txt; do sleep 0.2; done'
xdotool mousemove --window "$wid" 300 700
sleep 1
hold h
sleep 2
import -window "$wid" "$out/viewer-lines.png"
quit
echo "make-viewer-screenshots: docs/images/viewer-panel.png, viewer-help.png, viewer-engraving.png, viewer-lines.png"
