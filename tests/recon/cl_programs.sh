#!/usr/bin/env bash
# A filtered frame builds the OpenCL programs of its methods and no other (one program per
# kernel source, src/recon/cl/cl_runtime.h), from source with an empty program cache and from
# the cached binaries the next time, and both give the same image value for value. The
# programs built are read from the $WEDGE_CL_LOG=1 lines on stderr.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
if ! "$WEDGE" info --cl 2>/dev/null | grep -q "device 0"; then echo "skip: no OpenCL device"; exit 77; fi
make_temp_dir
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-${HOME:-$T}/.cache/pocl}" # the driver's own cache stays warm
scenes=${WEDGE_SOURCE_DIR:-../..}/scenes/bench
fail=0
# built FILTER SCENE RUN: the sorted "program:how" list of one render's builds
built() {
    WEDGE_CL_LOG=1 "$WEDGE" render "$scenes/$2.pbrt" --res 24x16 --spp 2 --filter "$1" --seed 5 -o "$T/$1-$3.exr" \
        --quiet 2>"$T/log" || { echo "FAIL: --filter $1 on $2 ($3): $(cat "$T/log")" >&2; return 1; }
    sed -n 's/^wedge: cl program \([a-z0-9_.]*\) built from \(source\|the cached binary\) in .*/\1:\2/p' "$T/log" |
        sed 's/:the cached binary/:cached/' | sort | tr '\n' ' '
}
expect() { # FILTER SCENE PROGRAMS...
    local f=$1 sc=$2; shift 2
    local cold="" warm=""
    export XDG_CACHE_HOME="$T/xdg-$f" # an empty wedge program cache
    for p in "$@"; do cold+="$p:source "; warm+="$p:cached "; done
    got=$(built "$f" "$sc" cold) || { fail=1; return; }
    [ "$got" = "$cold" ] || { echo "FAIL: --filter $f, empty cache: built '$got', expected '$cold'"; fail=1; }
    got=$(built "$f" "$sc" warm) || { fail=1; return; }
    [ "$got" = "$warm" ] || { echo "FAIL: --filter $f, cached: built '$got', expected '$warm'"; fail=1; }
    "$WEDGE" compare "$T/$f-cold.exr" "$T/$f-warm.exr" --json | grep -q '"relmse": 0,' ||
        { echo "FAIL: --filter $f: the cached programs' image differs from the first"; fail=1; }
}
expect aaf soft_shadows aaf.cl
expect fsf soft_shadows fsf.cl
expect maaf combined maaf.cl
expect lr motion_defocus_soft lr.cl
# two methods in one frame: lr asked for the motion, auto's table for the rest (aaf: on this 24x16
# frame the blur is under lr's threshold, and the fallback would leave every effect to Monte Carlo)
WEDGE_AUTO_FALLBACK=0 expect motion=lr all_effects aaf.cl lr.cl
[ "$(find "$T/xdg-motion=lr/wedge" -name 'cl-*.bin' | wc -l)" = 2 ] ||
    { echo "FAIL: --filter motion=lr: expected two cached programs: $(ls "$T/xdg-motion=lr/wedge")"; fail=1; }
# no OpenCL at all for an unfiltered frame
got=$(built none soft_shadows plain) || fail=1
[ -z "$got" ] || { echo "FAIL: --filter none built '$got'"; fail=1; }
[ $fail = 0 ] && echo "each filter built its own programs"
exit $fail
