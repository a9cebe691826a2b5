#!/usr/bin/env bash
# A process pays only for the libraries it uses: SDL2 (wedge preview's window) and MPI (a frame
# on several ranks) are opened at run time when a command needs them, not linked. Checked with
# the dynamic loader's own log (LD_DEBUG=files names every object it maps):
#   * --help, --version, info, compare and a --filter none render map neither SDL2 (nor what it
#     brings: PulseAudio, X11) nor MPI;
#   * wedge preview does map SDL2 (with a display that cannot be reached it stops right after
#     SDL_Init), and a rank under mpirun maps MPI: the log can tell, so the absences mean
#     something;
#   * a library that cannot be loaded (its name pointed at a file that does not exist:
#     WEDGE_SDL_LIBRARY, WEDGE_MPI_LIBRARY) gives exit 3 and a message that says what to
#     install, before anything is rendered.
# The SDL2 parts skip in a build without SDL2 and the MPI parts in one without MPI; mpirun
# missing in a build with MPI fails (tools/setup installs openmpi-bin).
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
make_temp_dir
scene=${WEDGE_SOURCE_DIR:-../..}/scenes/bench/soft_shadows.pbrt
fail=0

# maps FILE WHAT: whether the loader's log FILE shows an object whose name starts with WHAT mapped
maps() { grep -q "file=$2[^ ]*  *\[[0-9]*\]; *\(needed by\|dynamically loaded by\)" "$1"; }

# loader_log NAME CMD...: runs CMD with the loader's log in $T/NAME.ld (its own stderr apart)
loader_log() {
    local name=$1
    shift
    LD_DEBUG=files LD_DEBUG_OUTPUT="$T/$name.ld" "$@" >"$T/$name.out" 2>"$T/$name.err"
    local rc=$?
    cat "$T/$name.ld".* >"$T/$name.ld" 2>/dev/null
    rm -f "$T/$name.ld".*
    return $rc
}

has_sdl=1
DISPLAY= WAYLAND_DISPLAY= "$WEDGE" preview "$scene" --res 8x8 2>&1 | grep -q "built without SDL2" && has_sdl=0
has_mpi=0
"$WEDGE" --version | grep -q "MPI: yes" && has_mpi=1

# 1. commands that need neither library map neither
"$WEDGE" render "$scene" --res 16x16 --spp 1 --filter none --quiet -o "$T/ref.exr" || { echo "FAIL: reference render"; fail=1; }
loader_log help "$WEDGE" --help || { echo "FAIL: --help"; fail=1; }
loader_log version "$WEDGE" --version || { echo "FAIL: --version"; fail=1; }
loader_log info "$WEDGE" info "$scene" || { echo "FAIL: info"; fail=1; }
loader_log render "$WEDGE" render "$scene" --res 16x16 --spp 2 --filter none --quiet -o "$T/out.exr" ||
    { echo "FAIL: render: $(cat "$T/render.err")"; fail=1; }
loader_log compare "$WEDGE" compare "$T/ref.exr" "$T/out.exr" || { echo "FAIL: compare"; fail=1; }
for run in help version info render compare; do
    # the log is there and names what was mapped (libc at least): an empty log proves nothing
    maps "$T/$run.ld" libc || { echo "FAIL: $run: no loader log ($T/$run.ld)"; fail=1; continue; }
    for lib in libSDL2 libpulse libX11 libwayland libmpi libopen-rte libopen-pal libhwloc; do
        maps "$T/$run.ld" $lib && { echo "FAIL: $run maps $lib, which it does not use"; fail=1; }
    done
done

# 2. the commands that need them do map them
if [ $has_sdl = 1 ]; then
    DISPLAY=:9753 WAYLAND_DISPLAY= loader_log preview timeout 60 "$WEDGE" preview "$scene" --res 8x8
    rc=$?
    check "preview, unreachable display" 3 $rc
    maps "$T/preview.ld" libSDL2 || { echo "FAIL: wedge preview did not load SDL2: $(cat "$T/preview.err")"; fail=1; }
else
    echo "skip (SDL2 parts): wedge was built without SDL2"
fi
if [ $has_mpi = 1 ]; then
    command -v mpirun >/dev/null || { echo "FAIL: wedge has MPI but mpirun is missing (tools/setup installs openmpi-bin)"; exit 1; }
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    # Open MPI's start-up state is never freed (see mpi_render.sh)
    export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
    # only the rank's loader log: mpirun itself links Open MPI
    timeout 120 mpirun -np 1 env LD_DEBUG=files LD_DEBUG_OUTPUT="$T/rank.ld" "$WEDGE" render "$scene" --res 16x16 \
        --spp 1 --filter none --quiet -o "$T/rank.exr" >"$T/rank.out" 2>&1
    rc=$?
    cat "$T/rank.ld".* >"$T/rank.ld" 2>/dev/null
    check "mpirun -np 1 render" 0 $rc
    maps "$T/rank.ld" libmpi || { echo "FAIL: a rank under mpirun did not load MPI: $(cat "$T/rank.out")"; fail=1; }
else
    echo "skip (MPI parts): wedge was built without MPI"
fi

# 3. a library that cannot be loaded: exit 3, what to install, nothing rendered
if [ $has_sdl = 1 ]; then
    DISPLAY=:9753 WAYLAND_DISPLAY= WEDGE_SDL_LIBRARY=libwedge-no-such-sdl.so.0 timeout 60 "$WEDGE" preview "$scene" \
        --res 8x8 2>"$T/err.txt"
    check "preview without SDL2" 3 $?
    grep -q "^error: cannot load SDL2, which wedge preview needs for its window (libwedge-no-such-sdl.so.0: .*install it (Debian and Ubuntu: apt-get install libsdl2-2.0-0" "$T/err.txt" ||
        { echo "FAIL: message without SDL2: $(cat "$T/err.txt")"; fail=1; }
fi
if [ $has_mpi = 1 ]; then
    # what mpirun puts in a rank's environment, without mpirun: the load is tried and fails
    OMPI_COMM_WORLD_SIZE=2 WEDGE_MPI_LIBRARY=libwedge-no-such-mpi.so.40 timeout 60 "$WEDGE" render "$scene" \
        --res 8x8 --spp 1 --filter none -o "$T/nompi.exr" 2>"$T/err.txt"
    check "render under mpirun without MPI" 3 $?
    grep -q "^error: started by mpirun, but the MPI library cannot be loaded (libwedge-no-such-mpi.so.40: .*apt-get install libopenmpi3" "$T/err.txt" ||
        { echo "FAIL: message without MPI: $(cat "$T/err.txt")"; fail=1; }
    [ ! -e "$T/nompi.exr" ] || { echo "FAIL: an image was written without the MPI library"; fail=1; }
fi
exit $fail
