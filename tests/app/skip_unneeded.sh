#!/usr/bin/env bash
# Work a scene does not need is skipped (issue 18): a scene with no distribution effect
# renders under the default --filter auto without opening OpenCL (it renders with no OpenCL
# driver at all, and the report names no device), traces no bounce or MIS-BSDF rays with
# maxdepth 1 and point lights only, and stores no per-sample records; a scene with an effect
# does need the device (so the switch that hides the driver is shown to work).
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
command -v python3 >/dev/null || { echo "FAIL: python3 not found (tools/setup installs it)"; exit 1; }
make_temp_dir
fail=0
cat > "$T/plain.pbrt" <<'PBRT'
LookAt 0 1 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 24 ]
Integrator "path" "integer maxdepth" [ 1 ]
WorldBegin
LightSource "point" "rgb I" [ 5 5 5 ] "point3 from" [ 1 3 -1 ]
Shape "trianglemesh" "point3 P" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "sphere" "float radius" [ 0.5 ]
PBRT
cat > "$T/soft.pbrt" <<'PBRT'
LookAt 0 1 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 24 ]
Integrator "path" "integer maxdepth" [ 1 ]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 5 5 5 ]
  Shape "trianglemesh" "point3 P" [ -0.5 2 -0.5  0.5 2 -0.5  0.5 2 0.5  -0.5 2 0.5 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Shape "trianglemesh" "point3 P" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "sphere" "float radius" [ 0.5 ]
PBRT
# ocl-icd reads the drivers' list from OCL_ICD_VENDORS: an empty folder is a machine with none
mkdir "$T/no-drivers"
OCL_ICD_VENDORS="$T/no-drivers" "$WEDGE" render "$T/plain.pbrt" -o "$T/plain.exr" --report "$T/plain.json" --quiet
rc=$?; [ $rc = 0 ] || { echo "FAIL: a scene without effects needed OpenCL (exit $rc)"; fail=1; }
OCL_ICD_VENDORS="$T/no-drivers" "$WEDGE" render "$T/soft.pbrt" -o "$T/soft.exr" --quiet 2>"$T/soft.err"
rc=$?; [ $rc = 3 ] || { echo "FAIL: a soft-shadow scene with no OpenCL driver: exit $rc, expected 3"; fail=1; }
grep -q "install an OpenCL driver" "$T/soft.err" || { echo "FAIL: no-driver message: $(cat "$T/soft.err")"; fail=1; }
if [ -f "$T/plain.json" ]; then
python3 - "$T/plain.json" <<'PY' || fail=1
import json, sys
r = json.load(open(sys.argv[1]))
bad = []
if "cl_device" in r: bad.append("cl_device %r" % r["cl_device"])
if r["filters"] != {} or r["pixels_filtered"] != {}: bad.append("filters %r" % r["filters"])
if any(r["effects"].values()): bad.append("effects %r" % r["effects"])
if r["rays_indirect"] or r["rays_bsdf"]: bad.append("bounce/BSDF rays %d/%d" % (r["rays_indirect"], r["rays_bsdf"]))
if r["rays_primary"] != 32 * 24 * 16: bad.append("primary rays %d" % r["rays_primary"])
if bad: print("FAIL: plain scene: " + "; ".join(bad)); sys.exit(1)
PY
fi
exit $fail
