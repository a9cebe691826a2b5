#!/usr/bin/env bash
# The filter kernels are compiled once, whatever the image size (cl_launch_2d's fixed work
# group): with a fresh PoCL kernel cache, a filtered render at one odd size fills the cache,
# and renders at three other sizes add no compiled kernel to it. (Left to choose, PoCL picked
# a work-group size dividing each image size and compiled every kernel again per size, about
# 0.5 s per new size.) Needs PoCL, whose cache this reads; other drivers are skipped.
set -u
if [ -z "${WEDGE:-}" ] || [ ! -x "$WEDGE" ]; then echo "skip: no wedge binary (WEDGE='${WEDGE:-}')"; exit 77; fi
if ! "$WEDGE" info --cl 2>/dev/null | grep -q "Portable Computing Language"; then
    echo "skip: the OpenCL device is not PoCL's"; exit 77
fi
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
export POCL_CACHE_DIR="$T/cache"
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
