#!/usr/bin/env bash
# --pixel-filter and the scene's PixelFilter statement (src/render/pixel_filter.c): a bad
# name is a usage error naming the choices; the box reproduces the default image pixel for
# pixel (the film sample is used as before); a scene's PixelFilter "gaussian" renders as
# --pixel-filter gaussian does, and differently from the box; --pixel-filter overrides it.
set -euo pipefail
: "${WEDGE:?}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
cat > "$tmp/s.pbrt" <<'PBRT'
LookAt 0 1 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 12 ]
Integrator "path" "integer maxdepth" [ 1 ]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
  Shape "trianglemesh" "point3 P" [ -0.5 2 -0.5  0.5 2 -0.5  0.5 2 0.5  -0.5 2 0.5 ] "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
Shape "trianglemesh" "point3 P" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ] "integer indices" [ 0 2 1  0 3 2 ]
Shape "sphere" "float radius" [ 0.4 ]
PBRT
{ sed -n '1,4p' "$tmp/s.pbrt"; echo 'PixelFilter "gaussian"'; sed -n '5,$p' "$tmp/s.pbrt"; } > "$tmp/g.pbrt"
render() { "$WEDGE" render "$@" --spp 16 --filter none --quiet; }
set +e; "$WEDGE" render "$tmp/s.pbrt" --pixel-filter lanczos -o "$tmp/x.exr" > "$tmp/out.txt" 2>&1; rc=$?; set -e
[ "$rc" = 1 ] || fail "bad --pixel-filter exited $rc, expected 1"
grep -q -- "--pixel-filter wants box, gaussian, triangle, mitchell or sinc, got 'lanczos'" "$tmp/out.txt" || { cat "$tmp/out.txt"; fail "message"; }
render "$tmp/s.pbrt" -o "$tmp/default.exr"
render "$tmp/s.pbrt" -o "$tmp/box.exr" --pixel-filter box
render "$tmp/g.pbrt" -o "$tmp/scene-gauss.exr"
render "$tmp/s.pbrt" -o "$tmp/cli-gauss.exr" --pixel-filter gaussian
render "$tmp/g.pbrt" -o "$tmp/override-box.exr" --pixel-filter box
mse() { "$WEDGE" compare "$1" "$2" --json | sed 's/.*"mse": *\([^,]*\),.*/\1/'; }
[ "$(mse "$tmp/default.exr" "$tmp/box.exr")" = 0 ] || fail "box differs from the default image"
[ "$(mse "$tmp/scene-gauss.exr" "$tmp/cli-gauss.exr")" = 0 ] || fail "PixelFilter gaussian differs from --pixel-filter gaussian"
[ "$(mse "$tmp/default.exr" "$tmp/override-box.exr")" = 0 ] || fail "--pixel-filter box does not override the scene's gaussian"
[ "$(mse "$tmp/default.exr" "$tmp/scene-gauss.exr")" != 0 ] || fail "the gaussian renders the box's image"
echo "pixel filters: CLI and PixelFilter statement OK"
