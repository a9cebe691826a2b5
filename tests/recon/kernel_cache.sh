#!/usr/bin/env bash
# The filter kernels are compiled once, whatever the image size (cl_launch_2d's fixed work
# group): with a fresh PoCL kernel cache, a filtered render at one odd size fills the cache,
# and renders at three other sizes add no compiled kernel to it. (Left to choose, PoCL picked
# a work-group size dividing each image size and compiled every kernel again per size, about
# 0.5 s per new size.) Needs PoCL, whose cache this reads; other drivers are skipped.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
if ! "$WEDGE" info --cl 2>/dev/null | grep -q "Portable Computing Language"; then
    echo "skip: the OpenCL device is not PoCL's"; exit 77
fi
make_temp_dir
export POCL_CACHE_DIR="$T/cache"
export WEDGE_AUTO_FALLBACK=0 # auto's lens filter on these tiny frames (its fallback would leave defocus to Monte Carlo)
scene=${WEDGE_SOURCE_DIR:-../..}/scenes/bench/defocus.pbrt
compiled() { find "$POCL_CACHE_DIR" -name '*.so' | wc -l; }
"$WEDGE" render "$scene" --res 31x17 --mu 0.5 -o "$T/a.exr" --quiet || { echo "FAIL: first render"; exit 1; }
first=$(compiled)
[ "$first" -gt 0 ] || { echo "FAIL: no compiled kernel in the PoCL cache ($POCL_CACHE_DIR)"; exit 1; }
for res in 37x23 64x48 97x131; do
    "$WEDGE" render "$scene" --res "$res" --mu 0.5 -o "$T/b.exr" --quiet || { echo "FAIL: render $res"; exit 1; }
    now=$(compiled)
    if [ "$now" != "$first" ]; then
        echo "FAIL: a render at $res compiled kernels again ($first -> $now):"; find "$POCL_CACHE_DIR" -name '*.so'
        exit 1
    fi
done
echo "kernels compiled once: $first"
# An unwritable home (no kernel cache): PoCL reported no device at all, and wedge said
# "install an OpenCL driver". Now the kernels go to a temporary cache, said on stderr and
# removed at exit.
unset POCL_CACHE_DIR XDG_CACHE_HOME
export TMPDIR="$T/tmp"
mkdir -p "$TMPDIR"
HOME=/dev/null "$WEDGE" render "$scene" --res 16x12 --mu 0.5 -o "$T/c.exr" --quiet 2>"$T/err.txt" ||
    { echo "FAIL: unwritable HOME: $(cat "$T/err.txt")"; exit 1; }
grep -q "^wedge: note: the OpenCL kernel cache /dev/null/.cache/pocl is not writable" "$T/err.txt" ||
    { echo "FAIL: no note about the kernel cache: $(cat "$T/err.txt")"; exit 1; }
[ -z "$(ls -A "$TMPDIR")" ] || { echo "FAIL: the temporary kernel cache was left behind: $(ls "$TMPDIR")"; exit 1; }
