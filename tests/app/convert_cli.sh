#!/usr/bin/env bash
# wedge convert: a render's EXR converts to exactly the PNG the render wrote itself (same
# OpenColorIO view), EXR -> EXR keeps the pixels, and bad input fails with the documented
# exit codes and messages.
set -uo pipefail
. "$(dirname "$0")/../lib.sh"
require_wedge
make_temp_dir
fail=0

cat > "$T/s.pbrt" <<'PBRT'
LookAt 0 1 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 16 ]
WorldBegin
LightSource "point" "rgb I" [ 6 6 6 ] "point3 from" [ 0 3 -1 ]
Material "diffuse" "rgb reflectance" [ 0.7 0.4 0.2 ]
Shape "sphere" "float radius" [ 0.7 ]
Shape "trianglemesh" "point3 P" [ -3 -0.7 -3  3 -0.7 -3  3 -0.7 3  -3 -0.7 3 ] "integer indices" [ 0 2 1  0 3 2 ]
PBRT
"$WEDGE" render "$T/s.pbrt" --filter none --spp 4 -o "$T/r.exr" -o "$T/r.png" --quiet; check render 0 $?
"$WEDGE" convert "$T/r.exr" "$T/c.png"; check "exr -> png" 0 $?
cmp -s "$T/r.png" "$T/c.png" || { echo "FAIL: converted PNG differs from the render's own PNG"; fail=1; }
"$WEDGE" convert "$T/r.exr" "$T/f.png" --view Filmic; check "exr -> png, Filmic view" 0 $?
cmp -s "$T/r.png" "$T/f.png" && { echo "FAIL: --view Filmic gave the Standard view's PNG"; fail=1; }
"$WEDGE" convert "$T/r.exr" "$T/c.exr"; check "exr -> exr" 0 $?
json=$("$WEDGE" compare "$T/r.exr" "$T/c.exr" --json)
case "$json" in *'"mse": 0,'*|*'"mse": 0.0,'*|*'"mse": 0e+00,'*) ;; *) echo "FAIL: exr -> exr changed pixels: $json"; fail=1 ;; esac

"$WEDGE" convert "$T/r.exr" 2>/dev/null; check "one argument" 1 $?
"$WEDGE" convert "$T/r.exr" "$T/x.png" --bogus 2>/dev/null; check "unknown option" 1 $?
"$WEDGE" convert "$T/missing.exr" "$T/x.png" 2>"$T/err.txt"; check "missing input" 2 $?
grep -q "missing.exr" "$T/err.txt" || { echo "FAIL: missing-input message lacks the path: $(cat "$T/err.txt")"; fail=1; }
"$WEDGE" convert "$T/r.exr" "$T/x.png" --view NoSuchView 2>"$T/err.txt"; rc=$?
[ "$rc" != 0 ] || { echo "FAIL: an unknown view was accepted"; fail=1; }
grep -q "NoSuchView" "$T/err.txt" || { echo "FAIL: unknown-view message: $(cat "$T/err.txt")"; fail=1; }
[ ! -e "$T/x.png" ] || { echo "FAIL: a failed conversion left an output"; fail=1; }
exit $fail
