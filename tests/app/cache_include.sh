#!/usr/bin/env bash
# Reference cache (issue 5): the key covers included scene files and data files, so editing
# an included file invalidates the cached reference; an unchanged re-run reuses it (the log
# says so and the cached file is not rewritten).
set -euo pipefail
: "${WEDGE:?}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/main.pbrt" <<'PBRT'
LookAt 0 1 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
Integrator "path" "integer maxdepth" [ 1 ]
WorldBegin
LightSource "point" "rgb I" [ 5 5 5 ] "point3 from" [ 0 2 -1 ]
Include "inc.pbrt"
PBRT
write_inc() {
  printf 'Material "diffuse" "rgb reflectance" [ %s %s %s ]\nShape "sphere" "float radius" [ 0.5 ]\n' "$1" "$1" "$1" > "$tmp/inc.pbrt"
}
fail() { echo "FAIL: $*" >&2; exit 1; }

write_inc 0.5
k1=$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 4)
[[ $k1 =~ ^[0-9a-f]{32}$ ]] || fail "key '$k1' is not 32 hex digits"
k1b=$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 4)
[ "$k1" = "$k1b" ] || fail "the key is not deterministic"
write_inc 0.6
k2=$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 4)
[ "$k1" != "$k2" ] || fail "editing the included file did not change the key"
write_inc 0.5
k3=$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 4)
[ "$k1" = "$k3" ] || fail "restoring the included file did not restore the key"
# Every other ingredient of the key: resolution, spp, seed.
[ "$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 4 --res 9x8)" != "$k1" ] || fail "resolution not in the key"
[ "$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 8)" != "$k1" ] || fail "spp not in the key"
[ "$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 4 --seed 2)" != "$k1" ] || fail "seed not in the key"
# --ref-seed: the reference's seed alone decides the key, so sweeps of other seeds share it.
[ "$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 4 --seed 7 --ref-seed 1)" = "$k1" ] ||
  fail "--ref-seed 1 with --seed 7 does not give --seed 1's reference"
[ "$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 4 --ref-seed 2)" = \
  "$("$WEDGE" converge "$tmp/main.pbrt" --ref-key --ref-spp 4 --seed 2)" ] || fail "--ref-seed 2 is not seed 2's reference"

# Data files named by parameters (plymesh "filename", relative to the scene file) are in the
# key too: editing the mesh file alone changes it.
mkdir -p "$tmp/ply"
write_ply() {
  printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 %s 0\n3 0 1 2\n' "$1" > "$tmp/ply/tri.ply"
}
cat > "$tmp/ply/scene.pbrt" <<'PBRT'
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
WorldBegin
Shape "plymesh" "string filename" [ "tri.ply" ]
PBRT
write_ply 1
p1=$("$WEDGE" converge "$tmp/ply/scene.pbrt" --ref-key)
write_ply 2
p2=$("$WEDGE" converge "$tmp/ply/scene.pbrt" --ref-key)
[ "$p1" != "$p2" ] || fail "editing the PLY file did not change the key"

# Sweeps: the first renders the reference, an unchanged second run reuses it.
run() { "$WEDGE" converge "$tmp/main.pbrt" --spp 1,2 --methods mc --ref-spp 4 --cache "$tmp/cache" --out "$tmp/out" --no-plots; }
run > "$tmp/log1" 2>&1 || { cat "$tmp/log1"; fail "first sweep failed"; }
grep -q "^converge: rendering reference" "$tmp/log1" || fail "first sweep did not render the reference"
ref="$tmp/cache/ref-$k1.exr"
[ -f "$ref" ] || fail "no cached reference at $ref"
mtime1=$(stat -c %Y.%N "$ref" 2>/dev/null || stat -c %Y "$ref")
inode1=$(stat -c %i "$ref")
sleep 1
run > "$tmp/log2" 2>&1 || { cat "$tmp/log2"; fail "second sweep failed"; }
grep -q "^converge: reference cached: $ref" "$tmp/log2" || { cat "$tmp/log2"; fail "second sweep did not reuse the reference"; }
[ "$(stat -c %Y.%N "$ref" 2>/dev/null || stat -c %Y "$ref")" = "$mtime1" ] && [ "$(stat -c %i "$ref")" = "$inode1" ] ||
  fail "the cached reference was rewritten"
# A sweep of another seed with --ref-seed 1 reuses seed 1's reference.
"$WEDGE" converge "$tmp/main.pbrt" --spp 1,2 --methods mc --ref-spp 4 --seed 5 --ref-seed 1 --cache "$tmp/cache" \
  --out "$tmp/out5" --no-plots > "$tmp/log5" 2>&1 || { cat "$tmp/log5"; fail "--ref-seed sweep failed"; }
grep -q "^converge: reference cached: $ref" "$tmp/log5" || { cat "$tmp/log5"; fail "--ref-seed 1 did not reuse seed 1's reference"; }
# After an edit of the include the stale reference is not used: a new one is rendered.
write_inc 0.6
run > "$tmp/log3" 2>&1 || { cat "$tmp/log3"; fail "third sweep failed"; }
grep -q "^converge: rendering reference .*ref-$k2.exr" "$tmp/log3" || { cat "$tmp/log3"; fail "edited include did not trigger a new reference"; }
echo "cache_include: ok"
