#!/usr/bin/env bash
# The viewer's frame time with its panel and without (docs/performance.md, "The viewer's panel"): ROUNDS rounds
# (default 8) of three runs, alternated so that a busy machine slows all three alike, each `inkwell view
# --frames 300 --stats`, in a virtual X server:
#   none:   --no-panel, a 1024 x 768 window: the drawing alone, 1024 x 768
#   beside: the panel, a 1344 x 768 window: the same 1024 x 768 drawing, and the panel beside it
#   default: the panel, the default 1024 x 768 window: a 704 x 768 drawing, and the panel
# Prints each run's median frame time and its 10th percentile (the frames least slowed by other work on a busy
# machine), then for each the median over the rounds and of the ratios to `none`.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" != "--in-xvfb" ]; then
  exec xvfb-run -a -s "-screen 0 1600x1024x24" "$0" --in-xvfb "$@"
fi
shift
rounds=${1:-8}
ink=$PWD/build/inkwell
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$ink" -q fit assets/bunny.obj --control-points 684 -o "$work/bunny.hrbf" > /dev/null
for r in $(seq "$rounds"); do
  "$ink" view "$work/bunny.hrbf" --frames 300 --no-panel --size 1024 768 --stats "$work/none-$r.json" > /dev/null
  "$ink" view "$work/bunny.hrbf" --frames 300 --size 1344 768 --stats "$work/beside-$r.json" > /dev/null
  "$ink" view "$work/bunny.hrbf" --frames 300 --size 1024 768 --stats "$work/default-$r.json" > /dev/null
done
/usr/bin/python3 - "$work" "$rounds" <<'PY'
import json, statistics, sys
work, rounds = sys.argv[1], int(sys.argv[2])
def stats(path):
    frames = sorted(json.load(open(path))["frame_ms"][1:])  # the first frame also makes the swapchain
    return statistics.median(frames), frames[len(frames) // 10]
runs = {k: [stats(f"{work}/{k}-{r}.json") for r in range(1, rounds + 1)] for k in ("none", "beside", "default")}
for i, what in enumerate(("median", "10th percentile")):
    print(what)
    for k, v in runs.items():
        x = [s[i] for s in v]
        print(f"  {k:8s} " + " ".join(f"{t:6.2f}" for t in x) + f"   median {statistics.median(x):.2f} ms")
    for k in ("beside", "default"):
        ratios = [a[i] / b[i] for a, b in zip(runs[k], runs["none"])]
        print(f"  {k}/none: median ratio {statistics.median(ratios):.3f} (" + " ".join(f"{x:.2f}" for x in ratios) + ")")
PY
