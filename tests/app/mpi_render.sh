#!/usr/bin/env bash
# One frame on several MPI ranks (issue 21): `mpirun -np N wedge render` gives the image of a
# single process value for value, for 1, 2 and 3 ranks (oversubscribed on this machine), with
# --filter none, aaf, auto, fsf (under a --spp budget) and lr, on the default scene (every effect), and when pass 2's tiles
# change owner (balanced by their planned samples); the report says how many
# ranks and how many bytes each pass sent; a bad scene is reported once with exit 2; a rank
# that dies makes the job fail, not hang; the exchanges in small rounds give the same image;
# with each rank bound to a core, rank 0's OpenCL driver threads may use the node's cores and
# a rank starts one render thread per core it is bound to. Skipped for a build without MPI; a build with MPI
# and no mpirun fails (tools/setup installs Open MPI). WEDGE_DIST_LOG's per-rank rays add up to
# the report's.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
if ! "$WEDGE" --version | grep -q "MPI: yes"; then echo "skip: wedge was built without MPI (-DWEDGE_MPI=OFF)"; exit 77; fi
command -v mpirun >/dev/null || { echo "FAIL: wedge has MPI but mpirun is missing (tools/setup installs openmpi-bin)"; exit 1; }
command -v python3 >/dev/null || { echo "FAIL: python3 not found (tools/setup installs it)"; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# Open MPI's own start-up state is never freed; LeakSanitizer would report it at exit of every
# rank. wedge's leaks are checked by every other test, which runs the same code without MPI.
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
make_temp_dir
scene=${WEDGE_SOURCE_DIR:-../..}/scenes/default.pbrt
fail=0
for filter in none aaf auto fsf lr; do
    args=(--res 40x30 --threads 1 --seed 7 --filter "$filter" --quiet)
    [ "$filter" = none ] && args+=(--spp 6)
    # FSF under a budget: its pass-2 counts come from pass 1's variance on every rank's pixels
    [ "$filter" = fsf ] && args+=(--spp 12)
    "$WEDGE" render "$scene" "${args[@]}" -o "$T/one-$filter.exr" || { echo "FAIL: single process $filter"; fail=1; continue; }
    for np in 1 2 3; do
        timeout 300 mpirun -np $np "$WEDGE" render "$scene" "${args[@]}" -o "$T/mpi$np-$filter.exr" \
            --report "$T/mpi$np-$filter.json" >"$T/out.txt" 2>&1
        rc=$?
        if [ $rc != 0 ]; then echo "FAIL: mpirun -np $np --filter $filter: exit $rc"; cat "$T/out.txt"; fail=1; continue; fi
        # the same pixels, bit for bit: the MSE is exactly 0 and so is the largest difference
        "$WEDGE" compare "$T/one-$filter.exr" "$T/mpi$np-$filter.exr" --json > "$T/cmp.json" || { echo "FAIL: compare"; fail=1; continue; }
        python3 - "$T/cmp.json" "$T/mpi$np-$filter.json" $np "$filter" <<'PY' || fail=1
import json, sys
c, r, np, f = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), int(sys.argv[3]), sys.argv[4]
bad = []
if c["mse"] != 0 or c["relmse"] != 0: bad.append("image differs: mse %g" % c["mse"])
if r["ranks"] != np: bad.append("report ranks %s" % r["ranks"])
sent = r["bytes_communicated"]
if np == 1 and any(sent): bad.append("one rank sent %s bytes" % sent)
if np > 1 and not sent[0] > 0: bad.append("no bytes gathered after pass 1: %s" % sent)
# none and LR take every sample in pass 1; the others gather again after their pass 2
if np > 1 and f not in ("none", "lr") and not sent[1] > 0: bad.append("no bytes after pass 2: %s" % sent)
if np > 1 and f in ("none", "lr") and sent[1] != 0: bad.append("bytes after a pass 2 that %s has not: %s" % (f, sent))
if bad:
    print("FAIL: -np %d --filter %s: %s" % (np, f, "; ".join(bad))); sys.exit(1)
print("-np %d --filter %s: identical, bytes per pass %s" % (np, f, sent))
PY
    done
done
# pass 2 balanced by its predicted cost: tiles change owner and their state is handed over,
# and the image is still the single-process one. Checked on a bench scene whose plan is
# uneven, with the owners kept where the balance allows (the default; how many move depends
# on the measured times) and without keeping them (WEDGE_DIST_NO_KEEP: about half the tiles
# move, asserted, so that the test cannot pass with no tile moved).
scene2=${WEDGE_SOURCE_DIR:-../..}/scenes/bench/combined.pbrt
for filter in aaf maaf; do
    args=(--res 64x48 --threads 1 --seed 3 --filter "$filter" --quiet)
    "$WEDGE" render "$scene2" "${args[@]}" -o "$T/one2-$filter.exr" || { echo "FAIL: single process $filter (combined)"; fail=1; continue; }
    for np in 2 3; do
        for keep in 1 0; do
            if [ $keep = 1 ]; then unset WEDGE_DIST_NO_KEEP; else export WEDGE_DIST_NO_KEEP=1; fi
            WEDGE_DIST_LOG=1 timeout 300 mpirun -np $np "$WEDGE" render "$scene2" "${args[@]}" -o "$T/mpi2.exr" >"$T/out.txt" 2>&1
            rc=$?
            unset WEDGE_DIST_NO_KEEP
            if [ $rc != 0 ]; then echo "FAIL: combined -np $np --filter $filter keep $keep: exit $rc"; cat "$T/out.txt"; fail=1; continue; fi
            moved=$(sed -n 's/^dist: pass 2: \([0-9]*\) of \([0-9]*\) tiles changed owner$/\1/p' "$T/out.txt")
            # kept owners: how many move depends on the measured times (maybe none)
            if [ -z "$moved" ] || { [ $keep = 0 ] && ! [ "$moved" -gt 0 ]; }; then
                echo "FAIL: combined -np $np --filter $filter keep $keep: no tile changed owner in pass 2"; cat "$T/out.txt"; fail=1; continue
            fi
            "$WEDGE" compare "$T/one2-$filter.exr" "$T/mpi2.exr" --json > "$T/cmp.json" || { echo "FAIL: compare"; fail=1; continue; }
            python3 - "$T/cmp.json" "$np $filter keep $keep, $moved tiles moved" <<'PY' || fail=1
import json, sys
c = json.load(open(sys.argv[1]))
if c["mse"] != 0 or c["relmse"] != 0:
    print("FAIL: combined -np %s: image differs: mse %g" % (sys.argv[2], c["mse"])); sys.exit(1)
print("combined -np %s: identical" % sys.argv[2])
PY
        done
    done
done
# the exchanges stream each rank's tiles in rounds (4 MiB each; WEDGE_DIST_CHUNK makes them tiny,
# so that rounds cut rows, tiles and arrays anywhere): the gathers and the hand-over of moved
# tiles still give the single-process image, and the report still counts every byte once
for np in 2 3; do
    WEDGE_DIST_CHUNK=997 WEDGE_DIST_NO_KEEP=1 timeout 300 mpirun -np $np "$WEDGE" render "$scene2" --res 64x48 --threads 1 \
        --seed 3 --filter aaf --quiet -o "$T/chunk.exr" --report "$T/chunk.json" >"$T/out.txt" 2>&1
    rc=$?
    if [ $rc != 0 ]; then echo "FAIL: small rounds -np $np: exit $rc"; cat "$T/out.txt"; fail=1; continue; fi
    timeout 300 mpirun -np $np "$WEDGE" render "$scene2" --res 64x48 --threads 1 --seed 3 --filter aaf --quiet \
        -o "$T/whole.exr" --report "$T/whole.json" >"$T/out.txt" 2>&1 || { echo "FAIL: -np $np (one round)"; fail=1; continue; }
    "$WEDGE" compare "$T/one2-aaf.exr" "$T/chunk.exr" --json > "$T/cmp.json" || { echo "FAIL: compare"; fail=1; continue; }
    python3 - "$T/cmp.json" "$T/chunk.json" "$T/whole.json" $np <<'PY' || fail=1
import json, sys
c, r, w, np = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), json.load(open(sys.argv[3])), sys.argv[4]
if c["mse"] != 0 or c["relmse"] != 0:
    print("FAIL: small rounds -np %s: image differs: mse %g" % (np, c["mse"])); sys.exit(1)
# pass 1's gather is the same tiles whatever the rounds (pass 2 moves other tiles without keeping owners)
if r["bytes_communicated"][0] != w["bytes_communicated"][0] or not r["bytes_communicated"][0] > 4 * 997:
    print("FAIL: small rounds -np %s: pass 1 sent %s bytes, in one round %s" % (np, r["bytes_communicated"], w["bytes_communicated"]))
    sys.exit(1)
print("small rounds -np %s: identical, %d bytes in pass 1" % (np, r["bytes_communicated"][0]))
PY
done
# WEDGE_DIST_LOG prints each rank's own rays (the work its tiles took, tools/bench-mpi): every
# rank traced some, and over the ranks they add up to the report's totals, once each
for np in 2 3; do
    WEDGE_DIST_LOG=1 timeout 300 mpirun -np $np "$WEDGE" render "$scene2" --res 64x48 --threads 1 --seed 3 --filter aaf \
        --quiet -o "$T/rays.exr" --report "$T/rays.json" >"$T/out.txt" 2>&1 || { echo "FAIL: rays -np $np"; cat "$T/out.txt"; fail=1; continue; }
    python3 - "$T/out.txt" "$T/rays.json" $np <<'PY' || { cat "$T/out.txt"; fail=1; }
import json, re, sys
out, rep, np = open(sys.argv[1]).read(), json.load(open(sys.argv[2])), int(sys.argv[3])
ranks = {int(m.group(1)): [int(v) for v in m.groups()[1:]] for m in
         re.finditer(r"dist-rays rank (\d+): primary (\d+) shadow (\d+) indirect (\d+) bsdf (\d+)", out)}
if sorted(ranks) != list(range(np)) or any(r[0] <= 0 for r in ranks.values()):
    print("FAIL: rays -np %d: per-rank lines %s" % (np, ranks)); sys.exit(1)
for k, name in enumerate(["rays_primary", "rays_shadow", "rays_indirect", "rays_bsdf"]):
    if sum(r[k] for r in ranks.values()) != rep[name]:
        print("FAIL: rays -np %d: %s per rank %s, report %d" % (np, name, [r[k] for r in ranks.values()], rep[name])); sys.exit(1)
print("rays -np %d: per rank %s, summing to the report's" % (np, [r[0] for r in ranks.values()]))
PY
done
# the ranks wait for each other in a nonblocking barrier with naps (every run above); MPI's
# own blocking wait (WEDGE_DIST_WAIT=spin, kept for measuring) gives the same image
WEDGE_DIST_WAIT=spin timeout 300 mpirun -np 2 "$WEDGE" render "$scene2" --res 64x48 --threads 1 --seed 3 --filter aaf \
    --quiet -o "$T/spin.exr" >"$T/out.txt" 2>&1 || { echo "FAIL: WEDGE_DIST_WAIT=spin"; cat "$T/out.txt"; fail=1; }
"$WEDGE" compare "$T/one2-aaf.exr" "$T/spin.exr" --json | python3 -c '
import json, sys
c = json.load(sys.stdin)
if c["mse"] != 0: print("FAIL: WEDGE_DIST_WAIT=spin: image differs: mse %g" % c["mse"]); sys.exit(1)' || fail=1
# progressive steps are shared like passes: rank 0 decides, every rank follows, nothing hangs.
# The target lies above the first frame's samples (auto has lr for motion here, whose 8-px
# overscan band makes that frame about 142 samples per visible pixel at 40x30), so steps follow.
timeout 200 mpirun -np 2 "$WEDGE" render "$scene" --res 40x30 --threads 1 --spp 200 --checkpoint 0.001 \
    -o "$T/prog.exr" --report "$T/prog.json" --quiet >"$T/out.txt" 2>&1
rc=$?
if [ $rc != 0 ]; then echo "FAIL: progressive under mpirun: exit $rc (124: hung)"; cat "$T/out.txt"; fail=1
else
    python3 - "$T/prog.json" <<'PY' || fail=1
import json, sys
r = json.load(open(sys.argv[1]))
if abs(r["spp_avg"] - 200) > 1.0 / 1200 or r["steps"] < 2 or r["ranks"] != 2:
    print("FAIL: progressive under mpirun: %s" % {k: r[k] for k in ("spp_avg", "steps", "ranks")}); sys.exit(1)
PY
fi
# mpirun binds each rank to a core: rank 0's OpenCL driver threads (started while it checks
# the device) may still use every core of the node's ranks, which wait while it reconstructs,
# and its own thread keeps to its core; the image is the same. Needs two cores to bind to.
if [ "$(nproc)" -ge 2 ]; then
    args=(--res 40x30 --threads 1 --seed 7 --filter aaf --quiet)
    WEDGE_DIST_LOG=1 timeout 300 mpirun -np 2 --bind-to core "$WEDGE" render "$scene" "${args[@]}" -o "$T/bind.exr" \
        >"$T/out.txt" 2>&1 || { echo "FAIL: mpirun --bind-to core"; cat "$T/out.txt"; fail=1; }
    "$WEDGE" compare "$T/one-aaf.exr" "$T/bind.exr" --json > "$T/cmp.json" || { echo "FAIL: compare"; fail=1; }
    python3 - "$T/out.txt" "$T/cmp.json" <<'PY' || { cat "$T/out.txt"; fail=1; }
import json, re, sys
def cores(text):  # "0-2,5" -> {0, 1, 2, 5}
    out = set()
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out |= set(range(int(lo), int(hi or lo) + 1))
    return out
lines = [l for l in open(sys.argv[1]) if l.startswith("dist-cpus rank 0:")]
m = re.match(r"dist-cpus rank 0: own (\S+) node (\S+) driver(( \S+)*)$", lines[0].strip()) if lines else None
if not m:
    print("FAIL: --bind-to core: no dist-cpus line of rank 0"); sys.exit(1)
own, node, driver = cores(m.group(1)), cores(m.group(2)), [cores(t) for t in m.group(3).split()]
bad = []
if not (own < node): bad.append("the node's cores %s do not extend rank 0's own %s" % (sorted(node), sorted(own)))
if not driver: bad.append("no driver thread seen")
if any(t != node for t in driver): bad.append("driver threads on %s, not the node's %s" % ([sorted(t) for t in driver], sorted(node)))
if json.load(open(sys.argv[2]))["mse"] != 0: bad.append("image differs")
if bad:
    print("FAIL: --bind-to core: " + "; ".join(bad)); sys.exit(1)
print("--bind-to core: rank 0 on %s, its %d driver threads on %s, identical" % (sorted(own), len(driver), sorted(node)))
PY
    # without --threads a bound rank starts one render thread per core it is bound to (here
    # one), not one per core of the machine on that core; the image is the same
    timeout 300 mpirun -np 2 --bind-to core "$WEDGE" render "$scene" --res 40x30 --seed 7 --filter aaf --quiet \
        -o "$T/bind-threads.exr" --report "$T/bind-threads.json" >"$T/out.txt" 2>&1 || { echo "FAIL: mpirun --bind-to core without --threads"; cat "$T/out.txt"; fail=1; }
    "$WEDGE" compare "$T/one-aaf.exr" "$T/bind-threads.exr" --json > "$T/cmp.json" || { echo "FAIL: compare"; fail=1; }
    python3 - "$T/bind-threads.json" "$T/cmp.json" <<'PY' || fail=1
import json, sys
r, c = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
if r["threads"] != 1 or c["mse"] != 0:
    print("FAIL: --bind-to core without --threads: %s render threads (expected 1), mse %g" % (r["threads"], c["mse"])); sys.exit(1)
print("--bind-to core without --threads: 1 render thread, identical")
PY
fi
# a bad scene: one message (rank 0's), exit 2
printf 'WorldBegin\nShape "sphere" "float radius" [ oops ]\n' > "$T/bad.pbrt"
timeout 120 mpirun -np 3 "$WEDGE" render "$T/bad.pbrt" -o "$T/bad.exr" >"$T/out.txt" 2>&1
rc=$?
[ $rc = 2 ] || { echo "FAIL: bad scene under mpirun: exit $rc, expected 2"; cat "$T/out.txt"; fail=1; }
n=$(grep -c "bad.pbrt:2:" "$T/out.txt")
[ "$n" = 1 ] || { echo "FAIL: the bad scene was reported $n times, expected once:"; cat "$T/out.txt"; fail=1; }
# a bad OpenCL device: only rank 0 loads the driver, yet every rank stops with one process's
# exit code and one message
"$WEDGE" render "$scene" --res 16x16 --filter aaf --cl-device no-such-device -o "$T/dev1.exr" --quiet >"$T/out.txt" 2>&1
rc1=$?
timeout 120 mpirun -np 3 "$WEDGE" render "$scene" --res 16x16 --filter aaf --cl-device no-such-device -o "$T/dev.exr" \
    --quiet >"$T/out.txt" 2>&1
rc=$?
[ $rc1 != 0 ] && [ $rc = $rc1 ] || { echo "FAIL: bad --cl-device under mpirun: exit $rc, one process $rc1"; cat "$T/out.txt"; fail=1; }
n=$(grep -c "no OpenCL device matches" "$T/out.txt")
[ "$n" = 1 ] || { echo "FAIL: the bad device was reported $n times, expected once:"; cat "$T/out.txt"; fail=1; }
# Ctrl-C: mpirun passes it on (as SIGTERM), the ranks stop together and rank 0 writes the
# samples taken, as one process does
ranks_of() { pgrep -f -- "-o $1" | while read -r pid; do [ "$(cat /proc/$pid/comm 2>/dev/null)" = wedge ] && echo "$pid"; done; }
timeout 200 mpirun -np 2 "$WEDGE" render "$scene" --res 200x150 --spp 4096 --filter none --threads 1 \
    -o "$T/int.exr" --report "$T/int.json" --quiet >"$T/out.txt" 2>&1 &
job=$!
for _ in $(seq 1 100); do [ "$(ranks_of "$T/int.exr" | wc -l)" = 2 ] && break; sleep 0.2; done
# Ctrl-C once both ranks have rendered for a while: 1.5 s of CPU time each (utime + stime in
# /proc, clock ticks), not a fixed wall time, which a loaded machine can spend on anything
cpu_ticks() { awk '{ print $14 + $15 }' "/proc/$1/stat" 2>/dev/null || echo 0; }
tck=$(getconf CLK_TCK)
for _ in $(seq 1 600); do
    busy=0
    for pid in $(ranks_of "$T/int.exr"); do [ "$(cpu_ticks "$pid")" -ge $((tck * 3 / 2)) ] && busy=$((busy + 1)); done
    [ $busy = 2 ] && break
    sleep 0.2
done
pkill -INT -P $job mpirun # mpirun itself, not the timeout around it
wait $job
python3 - "$T/int.json" <<'PY' || { cat "$T/out.txt"; fail=1; }
import json, sys
try:
    r = json.load(open(sys.argv[1]))
except OSError:
    print("FAIL: Ctrl-C under mpirun wrote no report"); sys.exit(1)
if not r["interrupted"] or not 0 < r["spp_avg"] < 4096:
    print("FAIL: Ctrl-C under mpirun: interrupted %s, spp_avg %s" % (r["interrupted"], r["spp_avg"])); sys.exit(1)
print("Ctrl-C under mpirun: %.1f spp kept" % r["spp_avg"])
PY
[ -s "$T/int.exr" ] || { echo "FAIL: Ctrl-C under mpirun wrote no image"; fail=1; }
# a rank that dies: the job ends with a failure in bounded time, it does not hang
timeout 200 mpirun -np 2 "$WEDGE" render "$scene" --res 400x300 --spp 4096 --filter none --threads 1 \
    -o "$T/long.exr" --quiet >"$T/out.txt" 2>&1 &
job=$!
victim=""
for _ in $(seq 1 100); do
    victim=$(ranks_of "$T/long.exr" | tail -1)
    [ -n "$victim" ] && break
    sleep 0.2
done
if [ -z "$victim" ]; then
    echo "FAIL: no rank of the long render found"; fail=1; kill $job 2>/dev/null
else
    sleep 1
    kill -9 "$victim"
    wait $job
    rc=$?
    if [ $rc = 0 ] || [ $rc = 124 ]; then echo "FAIL: a killed rank left the job with exit $rc (124: hung until the timeout)"; cat "$T/out.txt"; fail=1; fi
fi
exit $fail
