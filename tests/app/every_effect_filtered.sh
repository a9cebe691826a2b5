#!/usr/bin/env bash
# Issue 18: under --filter auto no effect of a bench scene, of the embedded default scene or
# of the pbrt-v4 killeroo scenes (when ../shared is present) is left to plain Monte Carlo
# (but for an effect auto's fallback judged unable to pay, and motion below lr's blur threshold,
# each with its reason):
# `wedge info --json` names a method for every effect the scene has, at the film's resolution
# and at 64x64 (the blur probe reads the resolution; motion must get a filter below its
# threshold too).
set -euo pipefail
command -v python3 >/dev/null || { echo "python3 not found: skipping"; exit 77; }
src="${WEDGE_SOURCE_DIR:-../..}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

scenes=("$src"/scenes/bench/*.pbrt "$src"/scenes/default.pbrt)
for k in "$src"/../shared/pbrt-v4-scenes/killeroos/*.pbrt; do
    [ -f "$k" ] && scenes+=("$k")
done
checked=0
for scene in "${scenes[@]}"; do
    for res in "" "--res 64x64"; do
        # shellcheck disable=SC2086 # res is empty or two words
        "$WEDGE" info --json "$scene" $res > "$tmp/info.json"
        python3 - "$tmp/info.json" "$scene $res" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
assert j["effects"], sys.argv[2] + ": a bench scene without effects"
# auto's fallback may leave an effect to Monte Carlo where its probe predicts the filter cannot
# pay (recon/auto_fallback.h; the camera effects together), saying so; nothing else may be
# left unfiltered
fell_back = [e for e in j["effects"] if j["filters"][e] == "none"
             and j["reasons"][e].startswith("none, auto fell back to Monte Carlo: ")]
# the probe judges the camera effects auto filters together; the motion below lr's blur
# threshold is left to Monte Carlo by the table (select.c), the only effect that rule takes
by_blur = [e for e in fell_back if j["reasons"][e].startswith("none, auto fell back to Monte Carlo: median blur ")]
assert by_blur in ([], ["motion"]), (sys.argv[2], by_blur)
camera = {"defocus", "motion"} & set(j["effects"]) - set(by_blur)
assert not (camera & set(fell_back)) or camera <= set(fell_back), (sys.argv[2], fell_back)
unfiltered = [e for e in j["effects"] if j["filters"][e] == "none" and e not in fell_back]
assert not unfiltered, "%s: unfiltered %s (%s)" % (sys.argv[2], unfiltered, [j["reasons"][e] for e in unfiltered])
PY
        checked=$((checked + 1))
    done
done
# the thirty-three bench scenes and the default scene, each at two resolutions (a glob that
# matched nothing would pass vacuously)
[ "$checked" -ge 68 ] || { echo "only $checked scene/resolution pairs checked"; exit 1; }
echo "every effect filtered in $checked scene/resolution pairs"
