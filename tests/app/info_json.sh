#!/usr/bin/env bash
# wedge info --json: the documented keys and values on small scenes whose answers are known
# by construction, and on the pbrt-v4 killeroo scene when ../shared is present.
set -euo pipefail
command -v python3 >/dev/null || { echo "python3 not found: skipping"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# All four effects: area light on a quad (soft shadows), lens (defocus), moving sphere
# (motion), maxdepth 5 (indirect); two point lights; 2 + 2 triangles; one unsupported shape.
cat > "$tmp/all.pbrt" <<'SCENE'
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float fov" 40 "float lensradius" 0.05 "float focaldistance" 5
Film "rgb" "integer xresolution" 64 "integer yresolution" 48
Sampler "zsobol" "integer pixelsamples" 8
WorldBegin
LightSource "point" "rgb I" [ 1 1 1 ]
LightSource "point" "rgb I" [ 1 1 1 ]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 2 2 2 ]
  Shape "trianglemesh" "point3 P" [ 0 0 0 1 0 0 1 1 0 0 1 0 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Shape "trianglemesh" "point3 P" [ 0 0 1 1 0 1 1 1 1 0 1 1 ] "integer indices" [ 0 1 2 0 2 3 ]
ActiveTransform EndTime
Translate 0.1 0 0
ActiveTransform All
Shape "sphere"
Shape "cylinder"
SCENE
# auto's table first (the fallback's probe off), then as render judges it: on this 64x48 frame
# the probe leaves effects to Monte Carlo (the camera effects together), and info says which
# and why
WEDGE_AUTO_FALLBACK=0 "$WEDGE" info --json "$tmp/all.pbrt" > "$tmp/all.json"
"$WEDGE" info --json "$tmp/all.pbrt" > "$tmp/all-judged.json"
python3 - "$tmp/all.json" "$tmp/all-judged.json" <<'PY'
import json, sys
table, judged = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
changed = [e for e in table["filters"] if table["filters"][e] != judged["filters"][e]]
assert changed, (table["filters"], judged["filters"])  # this dim frame: nothing for a shading filter to remove
# the camera effects the table filters (the motion, below lr's blur threshold, is left to Monte
# Carlo by the table itself) fall back together
camera = {"defocus", "motion"} & {e for e in table["filters"] if table["filters"][e] != "none"}
assert not (camera & set(changed)) or camera <= set(changed), (table["filters"], judged["filters"])
for e in changed:
    assert judged["filters"][e] == "none", judged["filters"]
    assert judged["reasons"][e].startswith("none, auto fell back to Monte Carlo: "), judged["reasons"][e]
for e in set(judged["filters"]) & {"soft_shadows", "indirect"} - set(changed):
    assert ", kept: predicted " in judged["reasons"][e], judged["reasons"][e]
PY
python3 - "$tmp/all.json" "$tmp/all.pbrt" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
assert j["effects"] == ["soft_shadows", "defocus", "motion", "indirect"], j["effects"]
assert j["filters"] == {"soft_shadows": "aaf", "defocus": "aaf", "motion": "none", "indirect": "aaf"}, j["filters"]
# a blur of 0.1 scene units at 64x48 is under lr's 3-px threshold: the motion is Monte Carlo's
assert j["reasons"]["motion"].startswith("none, auto fell back to Monte Carlo: median blur "), j["reasons"]["motion"]
assert (j["width"], j["height"], j["spp"]) == (64, 48, 8), j
# motion present: auto read the blur probe, whose value is a blur in pixels
assert isinstance(j["blur_probe_px"], float) and j["blur_probe_px"] >= 0, j["blur_probe_px"]
assert j["blur_probe_unbounded"] == 0, j["blur_probe_unbounded"]
assert j["triangles"] == 4, j["triangles"]
assert j["lights"] == {"area": 1, "point": 2}, j["lights"]
assert j["shapes"] == 3 and j["materials"] == 0, j
want = sys.argv[2] + ":17:1: warning: unsupported shape \"cylinder\" ignored"
assert j["warnings"] == [want], j["warnings"]
PY

# No effects at all: pinhole, static, maxdepth 1, point light only; pbrt-v4 defaults.
printf 'Integrator "path" "integer maxdepth" 1\nWorldBegin\nLightSource "point"\n' > "$tmp/none.pbrt"
"$WEDGE" info --json "$tmp/none.pbrt" > "$tmp/none.json"
python3 - "$tmp/none.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
assert j["effects"] == [], j["effects"]
assert (j["width"], j["height"], j["spp"], j["triangles"]) == (1280, 720, 16, 0), j
assert j["lights"] == {"point": 1} and j["warnings"] == [], j
assert j["blur_probe_px"] is None, j["blur_probe_px"]  # nothing moves: no probe
PY

# The human summary names the same things.
WEDGE_AUTO_FALLBACK=0 "$WEDGE" info "$tmp/all.pbrt" > "$tmp/all.txt"
grep -q '^effects     soft_shadows (filter: aaf) defocus (filter: aaf) motion (filter: none) indirect (filter: aaf)$' "$tmp/all.txt"
grep -q '^triangles   4$' "$tmp/all.txt"
grep -q '^lights      area 1 point 2$' "$tmp/all.txt"

# A real pbrt-v4 scene: two killeroos, each 8316 control triangles after one Loop level
# (4 x 8316 = 33264, README of the scene folder) plus two 2-triangle planes.
killeroo="${WEDGE_SOURCE_DIR:-.}/../shared/pbrt-v4-scenes/killeroos/killeroo-moving.pbrt"
if [ -f "$killeroo" ]; then
    "$WEDGE" info --json "$killeroo" > "$tmp/k.json"
    python3 - "$tmp/k.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
assert j["triangles"] == 2 * 4 * 8316 + 4, j["triangles"]
assert j["effects"] == ["soft_shadows", "motion", "indirect"], j["effects"]
assert (j["width"], j["height"], j["spp"]) == (1024, 1024, 512)
assert j["lights"] == {"area": 1}
PY
else
    echo "note: ../shared/pbrt-v4-scenes absent, killeroo check skipped"
fi
# without SCENE: the embedded default scene, which shows all four effects
"$WEDGE" info --json > "$tmp/default.json"
python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); assert j["scene"] == "<default>" and len(j["effects"]) == 4, j' "$tmp/default.json"
# a --spp budget of 48 or more leaves the lens to aaf where the blur alone gives lr both camera
# effects (select.h, RECON_LR_MAX_BUDGET_SPP; at the film's 256x192 its median blur is about
# 12 px); below it, lr keeps both
hard="${WEDGE_SOURCE_DIR:-../..}/scenes/bench/motion_defocus_hard.pbrt"
for spp in 47 48; do
    "$WEDGE" info "$hard" --spp $spp --json > "$tmp/budget$spp.json" || { echo "FAIL: info --spp $spp"; exit 1; }
done
python3 - "$tmp/budget47.json" "$tmp/budget48.json" <<'PY'
import json, sys
below, above = (json.load(open(p)) for p in sys.argv[1:3])
assert below["filters"] == {"defocus": "lr", "motion": "lr"}, below["filters"]
assert above["filters"] == {"defocus": "aaf", "motion": "lr"}, above["filters"]
assert above["reasons"]["defocus"].startswith("aaf: a budget of 48 spp >= 48"), above["reasons"]
PY
echo ok

# Warnings the scene build finds (not the parser) are shown by info as by render (issue 20
# item 12): a dielectric with eta 0, a mix material that names itself.
cat > "$tmp/build_warn.pbrt" <<'SCENE'
WorldBegin
Material "dielectric" "float eta" 0
Shape "sphere"
MakeNamedMaterial "m" "string type" "mix" "string materials" [ "m" "m" ]
NamedMaterial "m"
Shape "sphere"
SCENE
"$WEDGE" info "$tmp/build_warn.pbrt" > "$tmp/bw.txt"
grep -qx "warnings    2" "$tmp/bw.txt"
grep -qxF "  $tmp/build_warn.pbrt:2:23: warning: \"eta\" must be positive; using 1.5" "$tmp/bw.txt"
grep -qxF "  $tmp/build_warn.pbrt:4:1: warning: mix material: unknown material 'm'; using diffuse grey 0.5" "$tmp/bw.txt"

# Light values that would be dropped, dimmed or overflow silently are said (issue 20 item 6):
# negative values, a negative scale, radiance beyond what float sums hold.
cat > "$tmp/lights.pbrt" <<'SCENE'
WorldBegin
LightSource "point" "rgb I" [ 3e38 1 1 ] "float scale" 1e10
LightSource "point" "rgb I" [ 1 -1 1 ]
LightSource "distant" "float scale" -2
SCENE
"$WEDGE" info "$tmp/lights.pbrt" > "$tmp/lw.txt"
grep -qx "warnings    3" "$tmp/lw.txt"
grep -qxF "  $tmp/lights.pbrt:2:1: warning: \"I\" times \"scale\" reaches inf, beyond what float sums of it hold: pixels that see this light will come out infinite (set to 0 and counted in the report's nonfinite_pixels)" "$tmp/lw.txt"
grep -qxF "  $tmp/lights.pbrt:3:1: warning: negative \"I\" (1 -1 1) is clamped to 0: a light cannot remove light" "$tmp/lw.txt"
grep -qxF "  $tmp/lights.pbrt:4:1: warning: light \"scale\" -2 is negative or not finite: the light emits nothing" "$tmp/lw.txt"
