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
expect_exit 1 "$WEDGE" converge --spp 4 --methods mc --out "$tmp/x" --time gpu
grep -qx "wedge converge: --time wants wall or cpu, got 'gpu'" "$tmp/out.txt" || fail "--time message: $(cat "$tmp/out.txt")"
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
[ "$(head -1 "$sp")" = "scene,method,mu,baseline,spp_avg,seconds_total,relmse,base_spp,base_seconds,speedup_samples,speedup_time,extrapolated,clock" ] || fail "speedup.csv header"
# without --time the speedups are in wall seconds: each row's time is results.csv's seconds_total
awk -F, 'NR > 1 && $13 != "wall" { bad = 1 } END { exit bad }' "$sp" || fail "clock column: $(cat "$sp")"
[ "$(tail -n +2 "$sp" | wc -l)" = 12 ] || fail "expected 12 speedup rows: $(cat "$sp")"
for b in mc mc-ld; do
  awk -F, -v b="$b" 'NR > 1 && $2 == b && $4 == b { n++; if ($10 < 0.9999 || $10 > 1.0001 || $11 < 0.9999 || $11 > 1.0001) bad = 1 } END { exit bad || n != 3 }' "$sp" ||
    fail "$b against itself is not 1x: $(cat "$sp")"
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
# --time cpu: the same sweep's speedups in each render's CPU seconds, read from its report
"$WEDGE" converge "$tmp/tiny.pbrt" --spp 2 --baseline-spp 4,16 --methods mc,aaf --ref-spp 64 --cache "$tmp/cache" \
  --out "$tmp/sweep4" --no-plots --time cpu > "$tmp/log4" 2>&1 || { cat "$tmp/log4"; fail "sweep with --time cpu failed"; }
grep -q "equal-error speedup against mc (relMSE; baseline interpolated in log-log; CPU time)" "$tmp/log4" ||
  fail "--time cpu printout: $(cat "$tmp/log4")"
sp4="$tmp/sweep4/speedup.csv"
awk -F, 'NR > 1 && $13 != "cpu" { bad = 1 } END { exit bad }' "$sp4" || fail "clock column with --time cpu: $(cat "$sp4")"
cpu_aaf=$(awk -F, '$2 == "aaf" { print $12 }' "$tmp/sweep4/results.csv")
sp_aaf=$(awk -F, '$2 == "aaf" { print $6 }' "$sp4")
rep_aaf=$(sed -nE 's/.*"cpu_seconds_total": *([0-9.eE+-]+).*/\1/p' "$tmp/sweep4/images/tiny-aaf-spp2.json")
awk -v a="$cpu_aaf" -v b="$sp_aaf" -v c="$rep_aaf" 'BEGIN { exit !(a > 0 && (a - b) / a < 1e-5 && (b - a) / a < 1e-5 && (a - c) / a < 1e-5 && (c - a) / a < 1e-5) }' ||
  fail "aaf's CPU seconds: results.csv $cpu_aaf, speedup.csv $sp_aaf, report $rep_aaf"
echo "converge_cli: ok"
