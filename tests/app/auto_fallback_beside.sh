#!/usr/bin/env bash
# --filter auto's shading filters beside camera filters it keeps (branch auto6; docs/algorithms.md,
# "a shading filter beside a kept camera filter"). On motion_defocus_soft (64x64, 16 spp) LR's
# defocus and motion average most of the penumbra's noise away: AAF's soft shadows would remove
# ~4% of what LR leaves for their own per-sample records and pass (AAF is not LR's method), so
# auto keeps LR and leaves the shadows to Monte Carlo, says so on stderr, and renders exactly
# --filter lr's image. (Before, the shadows were credited with the variance of every pixel they
# may touch and charged a pass alone: kept.) envlight's bounce beside MAAF's lens (96x96), whose
# filter shares the lens filter's method, stays kept, silently.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
require_cl_device
command -v python3 >/dev/null || { echo "FAIL: python3 not found (tools/setup installs it)"; exit 1; }
make_temp_dir
src=${WEDGE_SOURCE_DIR:-../..}
fail=0
unset WEDGE_AUTO_FALLBACK
args=(--res 64x64 --spp 16 --seed 3 --threads 2)

"$WEDGE" render "$src/scenes/bench/motion_defocus_soft.pbrt" "${args[@]}" --filter auto -o "$T/auto.exr" --report "$T/auto.json" \
    2>"$T/err.txt" >/dev/null; check "auto on motion_defocus_soft" 0 $?
"$WEDGE" render "$src/scenes/bench/motion_defocus_soft.pbrt" "${args[@]}" --filter lr -o "$T/lr.exr" --quiet; check "lr" 0 $?
want='^wedge render: --filter auto: soft_shadows: none, auto fell back to Monte Carlo: aaf predicted 0\.[0-9][0-9]x its'
want+=' equal-error speed, 1\.[0-9][0-9]x without \(error share [0-9]%, alpha [12]\.[0-9][0-9], gain probe\)$'
[ "$(wc -l < "$T/err.txt")" = 1 ] && grep -Eq "$want" "$T/err.txt" ||
    { echo "FAIL: not the one fallback line on stderr: $(cat "$T/err.txt")"; fail=1; }
"$WEDGE" compare "$T/lr.exr" "$T/auto.exr" --json > "$T/cmp.json"; check "compare" 0 $?
python3 - "$T/auto.json" "$T/cmp.json" <<'PY' || fail=1
import json, sys
r, c = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
a = r.get("auto_fallback", {})
cam, sp, share = a.get("camera", {}), a.get("speedup", {}), a.get("share", {})
bad = []
if r["filters"] != {"soft_shadows": "none", "defocus": "lr", "motion": "lr"}: bad.append("filters %s" % r["filters"])
if a.get("fell_back") != ["soft_shadows"] or a.get("asked") != "soft_shadows" or a.get("chosen") != "none":
    bad.append("auto_fallback %s" % a)
# beside the kept camera filters the speeds are absolute: the camera's own (kept) is none's
if not (cam.get("fell_back") is False and sp.get("none", 0) > sp.get("soft_shadows", 9) > 0
        and abs(cam.get("speedup", 0) - sp.get("none", 0)) < 1e-3 and cam.get("speedup", 0) > cam.get("speedup_without", 9)):
    bad.append("speeds %s, camera %s" % (sp, cam))
if not (0 < share.get("soft_shadows", -1) < 0.1): bad.append("share %s" % share)
rel = c.get("relMSE", c.get("relmse"))
if rel != 0: bad.append("the image is not --filter lr's: relMSE %s" % rel)
if bad: print("FAIL: motion_defocus_soft, auto: " + "; ".join(bad)); sys.exit(1)
print("motion_defocus_soft: lr kept, soft shadows left to Monte Carlo (aaf %.2fx, without %.2fx); the image is --filter lr's"
      % (sp["soft_shadows"], sp["none"]))
PY

"$WEDGE" render "$src/scenes/bench/envlight.pbrt" --res 96x96 --spp 16 --seed 3 --threads 2 --filter auto -o "$T/env.exr" \
    --report "$T/env.json" 2>"$T/err.txt" >/dev/null; check "auto on envlight" 0 $?
[ -s "$T/err.txt" ] && { echo "FAIL: a kept filter wrote to stderr: $(cat "$T/err.txt")"; fail=1; }
python3 - "$T/env.json" <<'PY' || fail=1
import json, sys
r = json.load(open(sys.argv[1])); a = r.get("auto_fallback", {})
ok = r["filters"] == {"defocus": "maaf", "indirect": "maaf"} and a.get("fell_back") == [] and a.get("chosen") == "indirect"
if not ok: print("FAIL: envlight, auto: filters %s, auto_fallback %s" % (r["filters"], a)); sys.exit(1)
print("envlight: maaf's bounce kept beside its lens (%.2fx, without %.2fx)" % (a["speedup"]["indirect"], a["speedup"]["none"]))
PY
exit $fail
