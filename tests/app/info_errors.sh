#!/usr/bin/env bash
# wedge info on bad input: exit 2 with the parser's exact message; bad usage exits 1.
set -uo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
expect() { # expect EXIT_CODE EXPECTED_STDERR -- ARGS...
    local code=$1 want=$2
    shift 3
    "$WEDGE" "$@" > "$tmp/out" 2> "$tmp/err"
    local rc=$?
    if [ "$rc" != "$code" ]; then echo "FAIL: wedge $* exited $rc, expected $code"; fail=1; fi
    if [ -n "$want" ] && [ "$(cat "$tmp/err")" != "$want" ]; then
        echo "FAIL: wedge $*: stderr"; cat "$tmp/err"; echo "expected"; echo "$want"; fail=1
    fi
}
printf 'WorldBegin\nShape "trianglemesh" "point3 P" [ 0 0 0 1 0 0 0 1 0 ] "integer indices" [ 0 1 3 ]\n' > "$tmp/bad.pbrt"
expect 2 "$tmp/bad.pbrt:2:55: error: trianglemesh: index 3 (value 3 of \"integer indices\") is out of range [0, 3)" -- info "$tmp/bad.pbrt"
printf 'WorldBegin\nInclude "inner.pbrt"\n' > "$tmp/outer.pbrt"
printf '\n  Film "rgb"\n' > "$tmp/inner.pbrt"
expect 2 "$tmp/inner.pbrt:2:3: error: Film is not allowed after WorldBegin
$tmp/outer.pbrt:2:9: note: included from here" -- info --json "$tmp/outer.pbrt"
expect 2 "$tmp/missing.pbrt: error: cannot open scene file: No such file or directory" -- info "$tmp/missing.pbrt"
# Binary bytes (all 256 values, starting at 0x00).
for i in $(seq 0 255); do printf "\\$(printf %03o "$i")"; done > "$tmp/binary.pbrt"
expect 2 "$tmp/binary.pbrt:1:1: error: unexpected byte 0x00" -- info "$tmp/binary.pbrt"
expect 1 "" -- info --nope "$tmp/bad.pbrt"
expect 1 "" -- info a.pbrt b.pbrt
for bad in 0 -3 12x ""; do
    expect 1 "wedge info: --spp wants a whole number in [1, 16777216], got '$bad'" -- info --spp "$bad"
done
expect 1 "wedge info: --spp wants a whole number in [1, 16777216], got ''" -- info --spp
expect 0 "" -- info --help
exit $fail
