#!/usr/bin/env bash
# The OpenCL driver opened ahead of the ICD loader (src/recon/cl/icd_preload.h): with the
# preload (the default) the driver's libraries look their symbols up in the driver's own
# scope first (glibc's LD_DEBUG=scopes: the driver's "scope 0" starts with the driver),
# without it (WEDGE_CL_PRELOAD=0) in wedge's global scope; both list the same devices and
# render the same image value for value, under --filter lr and auto.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
require_cl_device
make_temp_dir
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-${HOME:-$T}/.cache/pocl}"
unset OCL_ICD_VENDORS OCL_ICD_FILENAMES OPENCL_VENDOR_PATH LD_PRELOAD
scenes=${WEDGE_SOURCE_DIR:-../..}/scenes/bench
fail=0
sanitized=0
grep -q '^WEDGE_SANITIZE:BOOL=ON' "${WEDGE_BUILD_DIR:-/nonexistent}/CMakeCache.txt" 2>/dev/null && sanitized=1

# the devices, and the images of both filters, with and without the preload
for v in 0 1; do
    WEDGE_CL_PRELOAD=$v "$WEDGE" info --cl >"$T/info$v" 2>&1 || { echo "FAIL: info --cl (preload $v)"; fail=1; }
    for f in lr auto; do
        WEDGE_CL_PRELOAD=$v "$WEDGE" render "$scenes/motion_defocus_soft.pbrt" --res 48x36 --spp 4 --filter $f --seed 3 \
            -o "$T/$f$v.exr" --quiet || { echo "FAIL: --filter $f (preload $v)"; fail=1; }
    done
done
cmp -s "$T/info0" "$T/info1" || { echo "FAIL: the device lists differ:"; diff "$T/info0" "$T/info1"; fail=1; }
for f in lr auto; do
    "$WEDGE" compare "$T/${f}0.exr" "$T/${f}1.exr" --json | grep -q '"relmse": 0,' ||
        { echo "FAIL: --filter $f: the image with the preload differs from the one without"; fail=1; }
done

# which driver the preload opened (WEDGE_CL_LOG), and its scope
WEDGE_CL_LOG=1 "$WEDGE" render "$scenes/motion_defocus_soft.pbrt" --res 24x16 --spp 1 --filter lr -o "$T/log.exr" \
    --quiet 2>"$T/log" || { echo "FAIL: render with WEDGE_CL_LOG=1"; fail=1; }
driver=$(sed -n 's/^wedge: cl driver \(.*\) opened ahead of the ICD loader.*/\1/p' "$T/log" | head -1)
if [ $sanitized = 1 ]; then
    [ -z "$driver" ] || { echo "FAIL: a sanitizer build preloaded $driver (RTLD_DEEPBIND)"; fail=1; }
    echo "sanitizer build: preload off, images and devices checked"
    exit $fail
fi
[ -n "$driver" ] || { echo "FAIL: no driver preloaded: $(cat "$T/log")"; exit 1; }
base=$(basename "$driver")
# deep PRELOAD: how many loaded objects look up in a scope 0 that starts with the driver (with
# the preload: the driver and the libraries it brought; without: at most the driver itself,
# where it is linked -Bsymbolic, as PoCL is)
deep() {
    WEDGE_CL_PRELOAD=$1 LD_DEBUG=scopes "$WEDGE" render "$scenes/motion_defocus_soft.pbrt" --res 24x16 --spp 1 --filter lr \
        -o "$T/s.exr" --quiet 2>&1 | grep -c "scope 0: [^ ]*/$base "
}
with=$(deep 1)
without=$(deep 0)
[ "$with" -ge 2 ] || { echo "FAIL: with the preload, $with objects search $base's scope first (expected its libraries too)"; fail=1; }
[ "$without" -le 1 ] || { echo "FAIL: without the preload, $without objects search $base's scope first"; fail=1; }
echo "objects searching $base's scope first: $with with the preload, $without without"
exit $fail
