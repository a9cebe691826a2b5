#!/usr/bin/env bash
# Mixed pixels' first surface filtered (gbuffer.h, docs/algorithms.md "Mixed pixels: the first
# surface filtered"): on foreground_bars a defocused fence covers most of the frame, so most
# pixels' lens samples see a bar and the scene behind. maaf and aaf (which also filter the lens)
# must filter those pixels' first surface: `--report`'s pixels_filtered for soft shadows is
# most of the frame (before the split: 23% for maaf, 18% for aaf at this size; after: 83%).
# Beside lr's lens filter (which does not read a split composite) nothing is split and the
# count stays at the unsplit pixels' (18%).
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
require_cl_device
make_temp_dir
scene=${WEDGE_SOURCE_DIR:-../..}/scenes/bench/foreground_bars.pbrt
fail=0
filtered() { # filter -> soft shadows' pixels_filtered
    "$WEDGE" render "$scene" --res 64x64 --spp 8 --seed 3 --threads 1 --filter "$1" --quiet -o "$T/out.exr" \
        --report "$T/r.json" || { echo "FAIL: render --filter $1"; exit 1; }
    grep -o '"pixels_filtered[^}]*}' "$T/r.json" | grep -o '"soft_shadows": [0-9][0-9]*' | grep -o '[0-9]*$'
}
for f in maaf aaf; do
    n=$(filtered $f)
    # 60% of 4096 pixels
    [ "${n:-0}" -ge 2458 ] || { echo "FAIL: --filter $f: $n of 4096 pixels shadow-filtered, expected at least 2458"; fail=1; }
done
n=$(filtered soft_shadows=maaf,defocus=lr)
[ -n "$n" ] && [ "$n" -le 1200 ] || { echo "FAIL: maaf beside lr: $n of 4096 pixels shadow-filtered, expected the unsplit count (at most 1200)"; fail=1; }
exit $fail
