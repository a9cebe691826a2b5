#!/usr/bin/env bash
# The built OpenCL program is kept between runs (src/recon/cl/program_cache.h): the first
# filtered render stores the driver's binary in the wedge cache folder, the next builds from
# it and gives the same image value for value; a damaged file is not used (the render is
# still right) and is replaced by a good one; $WEDGE_CL_PROGRAM_CACHE=0 stores nothing.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
if ! "$WEDGE" info --cl 2>/dev/null | grep -q "device 0"; then echo "skip: no OpenCL device"; exit 77; fi
make_temp_dir
export XDG_CACHE_HOME="$T/xdg"
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-${HOME:-$T}/.cache/pocl}" # the driver's own cache stays warm
scene=${WEDGE_SOURCE_DIR:-../..}/scenes/bench/defocus.pbrt
render() { "$WEDGE" render "$scene" --res 24x16 --spp 4 --filter aaf --seed 3 -o "$1" --quiet; }
same() { "$WEDGE" compare "$1" "$2" --json | grep -q '"relmse": 0,' || { echo "FAIL: $3: images differ: $("$WEDGE" compare "$1" "$2" --json)"; exit 1; }; }
bins() { find "$XDG_CACHE_HOME/wedge" -name 'cl-*.bin' 2>/dev/null; }

WEDGE_CL_PROGRAM_CACHE=0 render "$T/off.exr" || { echo "FAIL: render with the cache off"; exit 1; }
[ -z "$(bins)" ] || { echo "FAIL: WEDGE_CL_PROGRAM_CACHE=0 stored $(bins)"; exit 1; }

render "$T/first.exr" || { echo "FAIL: first render"; exit 1; }
[ "$(bins | wc -l)" = 1 ] || { echo "FAIL: expected one cached program, found: $(bins)"; exit 1; }
bin=$(bins)
size=$(stat -c %s "$bin")
same "$T/off.exr" "$T/first.exr" "built from source, stored"

render "$T/cached.exr" || { echo "FAIL: render from the cached program"; exit 1; }
same "$T/off.exr" "$T/cached.exr" "built from the cached binary"

cp "$bin" "$T/good"
# damaged: the header (magic, key, size: 32 bytes) kept, the driver's binary replaced by as
# many random bytes (the driver refuses it); then a file cut short
head -c 32 "$T/good" > "$bin" && head -c $((size - 32)) /dev/urandom >> "$bin"
render "$T/damaged.exr" || { echo "FAIL: render with a damaged cached program"; exit 1; }
same "$T/off.exr" "$T/damaged.exr" "damaged cache file"
cmp -s "$bin" "$T/good" || { echo "FAIL: the damaged file was not replaced by the good binary"; exit 1; }
head -c 100 "$T/good" > "$bin"
render "$T/truncated.exr" || { echo "FAIL: render with a truncated cached program"; exit 1; }
same "$T/off.exr" "$T/truncated.exr" "truncated cache file"
cmp -s "$bin" "$T/good" || { echo "FAIL: the truncated file was not replaced by the good binary"; exit 1; }
ls "$XDG_CACHE_HOME/wedge"/.cl-* >/dev/null 2>&1 && { echo "FAIL: temporary files left: $(ls -a "$XDG_CACHE_HOME/wedge")"; exit 1; }
echo "cached program: $(basename "$bin"), $size bytes"
