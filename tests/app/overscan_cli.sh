#!/usr/bin/env bash
# --overscan: with LR (motion_defocus_hard at 40x30, 4 spp) the outputs are the visible 40x30
# image: the EXR (compared against an --overscan off render of the same size; compare refuses
# a size mismatch), its AOV layers, and the report: width, height, overscan_px 8 (LR's window
# margin), spp_avg the samples traced per visible pixel, 4 (40+16)(30+16)/(40x30); with
# --overscan off, overscan_px 0 and spp_avg 4. Plain Monte Carlo has no band. Bad values and
# --overscan with --filter none are usage errors with their messages. Under a --spp budget the
# band gets no extra samples, also where the plans ask for none and the room is spread evenly
# (a moving, unoccluded plane at mu 0.05): every visible pixel then holds more than the budget.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
command -v python3 >/dev/null || { echo "FAIL: python3 not found (tools/setup installs it)"; exit 1; }
make_temp_dir
src=${WEDGE_SOURCE_DIR:-../..}
scene="$src/scenes/bench/motion_defocus_hard.pbrt"
fail=0
for ov in auto off; do
    "$WEDGE" render "$scene" --res 40x30 --spp 4 --filter lr --overscan $ov --aovs --quiet -o "$T/$ov.exr" \
        --report "$T/$ov.json" || { echo "FAIL: render --overscan $ov"; fail=1; }
done
"$WEDGE" render "$scene" --res 40x30 --spp 4 --filter none --quiet -o "$T/mc.exr" --report "$T/mc.json" ||
    { echo "FAIL: render --filter none"; fail=1; }
python3 - "$T" <<'PY' || fail=1
import json, sys
d = sys.argv[1]
on, off, mc = (json.load(open("%s/%s.json" % (d, k))) for k in ("auto", "off", "mc"))
ok = True
for name, r, band in (("auto", on, 8), ("off", off, 0), ("none", mc, 0)):
    spp = 4 * (40 + 2 * band) * (30 + 2 * band) / (40 * 30)
    if (r["width"], r["height"]) != (40, 30) or r["overscan_px"] != band or abs(r["spp_avg"] - spp) > 1e-4:
        print("FAIL: --overscan %s: %s (want 40x30, overscan_px %d, spp_avg %g)" %
              (name, {k: r[k] for k in ("width", "height", "overscan_px", "spp_avg")}, band, spp))
        ok = False
sys.exit(0 if ok else 1)
PY
# the budget's room spread evenly: 48x40 traced as 64x56, 32 spp a traced pixel, so the visible
# pixels average (32 * 64 * 56 - pass 1 in the band) / (48 * 40), above 51 (spread over the band
# too, they had 32)
cat > "$T/plane.pbrt" <<'EOF'
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float fov" [ 30 ]
Film "rgb" "integer xresolution" [ 48 ] "integer yresolution" [ 40 ]
Integrator "path" "integer maxdepth" [ 1 ]
WorldBegin
AttributeBegin
  Translate 0 0 -6
  Rotate 180 0 1 0
  AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
  Shape "trianglemesh" "point3 P" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] "integer indices" [ 0 2 1  0 3 2 ]
AttributeEnd
ActiveTransform StartTime
Translate -0.4 0 0
ActiveTransform EndTime
Translate 0.4 0 0
ActiveTransform All
Material "diffuse" "rgb reflectance" [ 0.7 0.6 0.5 ]
Shape "trianglemesh" "point3 P" [ -20 -20 1  20 -20 1  20 20 1  -20 20 1 ] "integer indices" [ 0 1 2  0 2 3 ]
EOF
"$WEDGE" render "$T/plane.pbrt" --filter auto --spp 32 --mu 0.05 --aovs --quiet -o "$T/plane.exr" \
    --report "$T/plane.json" || { echo "FAIL: render plane"; fail=1; }
"$WEDGE" compare "$T/plane.exr" "$T/plane.exr" --by spp --bins 51 --json > "$T/plane_by.json" ||
    { echo "FAIL: compare --by spp"; fail=1; }
python3 - "$T" <<'PY' || fail=1
import json, sys
d = sys.argv[1]
r, by = json.load(open(d + "/plane.json")), json.load(open(d + "/plane_by.json"))["by"]["bins"]
low = sum(b["pixels"] for b in by if b["lo"] is None)
if r["overscan_px"] != 8 or r["filters"].get("motion") != "lr" or low:
    print("FAIL: budget spread evenly: %d of 1920 visible pixels under 51 spp (%s), overscan_px %s, filters %s" %
          (low, by, r["overscan_px"], r["filters"]))
    sys.exit(1)
PY
# the same size as a plain render, for the image and for a layer of the method and of the frame
for ch in "" "--by lr.layers" "--by spp"; do
    "$WEDGE" compare "$T/off.exr" "$T/auto.exr" $ch --json > /dev/null || { echo "FAIL: auto vs off ($ch)"; fail=1; }
done
"$WEDGE" compare "$T/mc.exr" "$T/auto.exr" --json > /dev/null || { echo "FAIL: size differs from Monte Carlo's"; fail=1; }
"$WEDGE" render "$scene" --res 8x8 --overscan on -o "$T/x.exr" 2> "$T/err.txt"
[ $? -eq 1 ] && grep -q "auto or off" "$T/err.txt" || { echo "FAIL: --overscan on: $(cat "$T/err.txt")"; fail=1; }
"$WEDGE" render "$scene" --res 8x8 --filter none --overscan off -o "$T/x.exr" 2> "$T/err.txt"
[ $? -eq 1 ] && grep -q "^wedge render: --overscan off turns off the band a filter traces around the image and does nothing with --filter none; drop it, or choose a filter$" "$T/err.txt" ||
    { echo "FAIL: --overscan off with --filter none: $(cat "$T/err.txt")"; fail=1; }
[ $fail -eq 0 ] && echo "overscan_cli: all passed"
exit $fail
