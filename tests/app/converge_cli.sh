#!/usr/bin/env bash
# wedge converge end to end on a tiny scene: usage errors, the exact CSV header, one row per
# (method, spp), the images and reports, and the speedup table (the baseline against itself
# is exactly 1x: interpolating a curve at one of its own points returns that point).
set -euo pipefail
: "${WEDGE:?}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
expect_exit() { # CODE CMD...
  local want=$1; shift
  set +e; "$@" > "$tmp/out.txt" 2>&1; local got=$?; set -e
  [ "$got" = "$want" ] || { cat "$tmp/out.txt"; fail "'$*' exited $got, expected $want"; }
}
expect_exit 1 "$WEDGE" converge --spp 4 --methods mc
expect_exit 1 "$WEDGE" converge --spp 4 --methods nosuch --out "$tmp/x"
grep -q "unknown method 'nosuch'; known: mc mc-ld auto auto-ld aaf aaf-ld" "$tmp/out.txt" || fail "unknown-method message"
expect_exit 1 "$WEDGE" converge --spp 4,x --methods mc --out "$tmp/x"
expect_exit 1 "$WEDGE" converge --spp 4 --baseline-spp 16,0 --methods mc --out "$tmp/x"
grep -qx "wedge converge: bad spp '0' in --baseline-spp" "$tmp/out.txt" || fail "--baseline-spp message: $(cat "$tmp/out.txt")"
expect_exit 1 "$WEDGE" converge --spp 4 --methods mc --out "$tmp/x" --res 12
expect_exit 1 "$WEDGE" converge --spp 4 --methods mc --out "$tmp/x" --ref-seed -3
grep -qx "wedge converge: --ref-seed wants an integer in \[0, 2^30\], got '-3'" "$tmp/out.txt" || fail "--ref-seed message: $(cat "$tmp/out.txt")"
expect_exit 0 "$WEDGE" converge --help
expect_exit 2 "$WEDGE" converge "$tmp/missing.pbrt" --spp 4 --methods mc --out "$tmp/x"

cat > "$tmp/tiny.pbrt" <<'PBRT'
LookAt 0 1 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 12 ] "integer yresolution" [ 10 ]
Integrator "path" "integer maxdepth" [ 1 ]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
  Shape "trianglemesh" "point3 P" [ -0.5 2 -0.5  0.5 2 -0.5  0.5 2 0.5  -0.5 2 0.5 ] "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
Shape "trianglemesh" "point3 P" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ] "integer indices" [ 0 2 1  0 3 2 ]
Shape "sphere" "float radius" [ 0.4 ]
PBRT
# Plots only where gnuplot is installed (tools/setup installs it).
plots=--no-plots
command -v gnuplot > /dev/null && plots=
"$WEDGE" converge "$tmp/tiny.pbrt" --spp 2,8,32 --methods mc,mc-ld --ref-spp 64 --cache "$tmp/cache" \
  --out "$tmp/sweep" $plots > "$tmp/log" 2>&1 || { cat "$tmp/log"; fail "sweep failed"; }
if [ -z "$plots" ]; then
  for p in error_vs_spp error_vs_seconds; do
    [ "$(head -c 8 "$tmp/sweep/$p.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$p.png is not a PNG"
  done
fi
csv="$tmp/sweep/results.csv"
[ "$(head -1 "$csv")" = "scene,method,mu,spp_avg,seconds_total,seconds_trace,seconds_filter,relmse,mse,psnr,ssim,cpu_seconds_total" ] ||
  fail "results.csv header: $(head -1 "$csv")"
[ "$(tail -n +2 "$csv" | wc -l)" = 6 ] || fail "expected 6 rows"
awk -F, 'NR > 1 && (NF != 12 || $1 != "tiny" || $3 != "" || $8 <= 0 || $9 <= 0 || $5 <= 0 || $12 <= 0) { bad = 1 } END { exit bad }' "$csv" ||
  fail "malformed rows: $(cat "$csv")"
# spp_avg is what the renderer reports: uniform sampling gives exactly the requested spp.
[ "$(awk -F, 'NR > 1 { printf "%s ", $4 }' "$csv")" = "2 8 32 2 8 32 " ] || fail "spp_avg column"
# The runs alternate between the methods, budget by budget (so that a load that drifts during the
# sweep slows every method alike); results.csv keeps the method-by-method order checked above.
[ "$(awk '$1 == "mc" || $1 == "mc-ld" { if ($3 ~ /^[0-9]+$/) printf "%s:%s ", $1, $3 }' "$tmp/log")" = "mc:2 mc-ld:2 mc:8 mc-ld:8 mc:32 mc-ld:32 " ] ||
  fail "run order: $(cat "$tmp/log")"
# The metrics are those of wedge compare on the same images.
img="$tmp/sweep/images/tiny-mc-spp8.exr"
[ -f "$img" ] && [ -f "$tmp/sweep/images/tiny-mc-spp8.json" ] && [ -f "$tmp/sweep/reference.exr" ] || fail "images missing"
json=$("$WEDGE" compare "$tmp/sweep/reference.exr" "$img" --json)
want=$(printf '%s' "$json" | sed -E 's/.*"relmse": *([-0-9.eE+]+).*/\1/')
got=$(awk -F, '$2 == "mc" && $4 == 8 { print $8 }' "$csv")
awk -v a="$want" -v b="$got" 'BEGIN { exit !(a > 0 && (a - b) / a < 1e-5 && (b - a) / a < 1e-5) }' ||
  fail "relMSE $got differs from wedge compare's $want"
# Every run against each Monte Carlo baseline of the sweep: 6 runs x 2 baselines. A baseline
# against itself is 1 at every budget.
sp="$tmp/sweep/speedup.csv"
[ "$(head -1 "$sp")" = "scene,method,mu,baseline,spp_avg,seconds_total,relmse,base_spp,base_seconds,speedup_samples,speedup_time,extrapolated,cpu_seconds_total,base_cpu_seconds,speedup_cpu" ] || fail "speedup.csv header"
[ "$(tail -n +2 "$sp" | wc -l)" = 12 ] || fail "expected 12 speedup rows: $(cat "$sp")"
for b in mc mc-ld; do
  awk -F, -v b="$b" 'NR > 1 && $2 == b && $4 == b { n++; if ($10 < 0.9999 || $10 > 1.0001 || $11 < 0.9999 || $11 > 1.0001) bad = 1 } END { exit bad || n != 3 }' "$sp" ||
    fail "$b against itself is not 1x: $(cat "$sp")"
  # in CPU time too
  awk -F, -v b="$b" 'NR > 1 && $2 == b && $4 == b { n++; if ($15 < 0.9999 || $15 > 1.0001) bad = 1 } END { exit bad || n != 3 }' "$sp" ||
    fail "$b against itself is not 1x in CPU time: $(cat "$sp")"
done
grep -q "equal-error speedup against mc-ld" "$tmp/log" || fail "no mc-ld block in the printout: $(cat "$tmp/log")"
# A filter sets its own samples: one run per mu, whatever --spp lists (no repeated runs).
"$WEDGE" converge "$tmp/tiny.pbrt" --spp 2,8,32 --methods mc,aaf --mu 1,4 --ref-spp 64 --cache "$tmp/cache" \
  --out "$tmp/sweep2" --no-plots > "$tmp/log2" 2>&1 || { cat "$tmp/log2"; fail "sweep with aaf failed"; }
csv2="$tmp/sweep2/results.csv"
[ "$(awk -F, '$2 == "aaf" { printf "%s ", $3 }' "$csv2")" = "1 4 " ] || fail "aaf rows: $(cat "$csv2")"
[ "$(awk -F, '$2 == "mc"' "$csv2" | wc -l)" = 3 ] || fail "mc rows: $(cat "$csv2")"
[ -f "$tmp/sweep2/images/tiny-aaf-mu4.exr" ] || fail "aaf image missing: $(ls "$tmp/sweep2/images")"
# Only mc in that sweep: the speedups are against mc alone (2 aaf + 3 mc runs).
sp2="$tmp/sweep2/speedup.csv"
[ "$(awk -F, 'NR > 1 { printf "%s ", $4 }' "$sp2")" = "mc mc mc mc mc " ] || fail "sweep2 baselines: $(cat "$sp2")"
# --baseline-spp: the baselines run at their own counts (bracketing a filter's error), the
# filters at --spp; the speedup rows compare every run with the baselines' curve.
"$WEDGE" converge "$tmp/tiny.pbrt" --spp 2 --baseline-spp 4,16 --methods mc,aaf --ref-spp 64 --cache "$tmp/cache" \
  --out "$tmp/sweep3" --no-plots > "$tmp/log3" 2>&1 || { cat "$tmp/log3"; fail "sweep with --baseline-spp failed"; }
csv3="$tmp/sweep3/results.csv"
[ "$(awk -F, '$2 == "mc" { printf "%s ", $4 }' "$csv3")" = "4 16 " ] || fail "mc rows with --baseline-spp: $(cat "$csv3")"
[ "$(awk -F, '$2 == "aaf"' "$csv3" | wc -l)" = 1 ] || fail "aaf rows with --baseline-spp: $(cat "$csv3")"
[ -f "$tmp/sweep3/images/tiny-mc-spp16.exr" ] && [ -f "$tmp/sweep3/images/tiny-aaf-spp2.exr" ] ||
  fail "images with --baseline-spp: $(ls "$tmp/sweep3/images")"
# The CPU-time speedup of a run is its Monte Carlo CPU seconds at its error over its own CPU seconds,
# which are its report's cpu_seconds_total (the same number in results.csv and speedup.csv); the Monte
# Carlo curve's CPU seconds at that error lie between the two baseline runs' CPU seconds.
sp3="$tmp/sweep3/speedup.csv"
rep_aaf=$(sed -nE 's/.*"cpu_seconds_total": *([0-9.eE+-]+).*/\1/p' "$tmp/sweep3/images/tiny-aaf-spp2.json")
python3 - "$csv3" "$sp3" "$rep_aaf" <<'PY' || fail "CPU-time speedup: $(cat "$sp3")"
import csv, sys
res = list(csv.DictReader(open(sys.argv[1])))
sp = [r for r in csv.DictReader(open(sys.argv[2])) if r["method"] == "aaf" and r["baseline"] == "mc"][0]
aaf = [r for r in res if r["method"] == "aaf"][0]
mc = sorted(float(r["cpu_seconds_total"]) for r in res if r["method"] == "mc")
rep = float(sys.argv[3])
close = lambda a, b: abs(a - b) <= 1e-5 * max(abs(a), abs(b))
ok = close(float(aaf["cpu_seconds_total"]), rep) and close(float(sp["cpu_seconds_total"]), rep)
base = float(sp["base_cpu_seconds"])
ok = ok and close(float(sp["speedup_cpu"]), base / rep)
# inside the curve the base cost is bracketed by the runs; outside it is extrapolated
ok = ok and (sp["extrapolated"] == "1" or mc[0] <= base <= mc[-1])
sys.exit(0 if ok else 1)
PY
echo "converge_cli: ok"
