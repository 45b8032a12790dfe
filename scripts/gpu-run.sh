#!/usr/bin/env bash
# Runs on a lent GPU machine what scripts/gpu-pack.sh packed (as .dev/run.sh, from the repository root, with .dev
# and .gl carried): validate, the GPU, golden and CLI tests (the viewer's need Xvfb), bench, the contour and the
# cross field on four models both ways, and ../shared/tools/targets.sh; results under $OUT. Steps as arguments
# (default: all): validate tests bench contour field targets.
set -u
t0=$(date +%s); say() { echo "[$(($(date +%s) - t0))s] $*"; }
root=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p "$OUT"
for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
mkdir -p /tmp/pk && tar -C /tmp/pk -xJf .dev/pack.tar.xz && tar -C "$root" -xf /tmp/pk/build.tar
origin=$(cat /tmp/pk/origin)
if [ "$root" != "$origin" ]; then mkdir -p "$(dirname "$origin")"; rm -rf "$origin"; ln -sfn "$root" "$origin"; fi
S=/tmp/pk/shared
export LD_LIBRARY_PATH=/tmp/pk/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} VK_LAYER_PATH=/tmp/pk/layers
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; [ -f $icd ] && export VK_DRIVER_FILES=$icd
nvidia-smi -L 2>/dev/null; say setup done
cd "$origin"; I=build/inkwell; M=.dev/models  # CGAL's knot1, fandisk, elephant (.off), copied there by hand
models() { echo "$S/models/bunny.obj"; for m in knot1 fandisk elephant; do [ -f $M/$m.off ] && echo $M/$m.off; done; }
for s in ${*:-validate tests bench contour field targets}; do case $s in
validate) say validate; timeout 60 $I validate 2>&1 | tail -4 ;;
tests) say tests
  (cd build && timeout 330 ctest -L 'gpu|golden|cli' -LE viewer -j16 --output-on-failure) > "$OUT/ctest.log" 2>&1
  grep -E "tests passed|tests failed|\*\*\*Failed|\(Failed\)|Timeout" "$OUT/ctest.log" | head -30
  grep -h "^SKIPPED: " build/Testing/Temporary/LastTest.log | head ;;
bench) say bench
  timeout 150 $I bench --repeat 3 --frames 30 --json "$OUT/bench.json" 2>&1 | grep -v "^note:" | tail -30
  timeout 40 $I bench --workload bunny-684 --no-screen-spacing --repeat 3 --frames 30 --json "$OUT/bench-nospacing.json" 2>&1 | tail -1 ;;
contour) say contour
  for m in $(models); do n=$(basename "${m%.*}")
    timeout 60 $I render "$m" --style contours -q -o /tmp/$n-c.png --stats /tmp/$n-c.json > /dev/null 2>&1
    python3 -c "import json,sys; c=json.load(open(sys.argv[1]))['lines']['contours']; print(sys.argv[2], {k: c[k] for k in ('seconds','device_ms','device_passes_ms','cusps','vertices') if k in c})" /tmp/$n-c.json $n
  done ;;
field) say field
  for m in $(models); do n=$(basename "${m%.*}")
    for f in cpu device; do
      timeout 60 $I render "$m" --style contours+hatching --hatch-field $f -q -o /tmp/$n-h.png --stats /tmp/$n-h.json > /dev/null 2>&1
      python3 -c "import json,sys; h=json.load(open(sys.argv[1]))['lines']['hatching']; print(sys.argv[2], {k: h[k] for k in h if k.startswith('field') or k == 'strokes'})" /tmp/$n-h.json "$n $f"
    done
  done ;;
targets) say targets
  TARGETS_DIR=/tmp/tg timeout 200 bash $S/tools/targets.sh $I contours hatching stipples 2>&1 | tee "$OUT/targets.txt" ;;
esac; done
say end
