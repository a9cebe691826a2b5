#!/usr/bin/env bash
# The PLY, EXR and PNG readers under libFuzzer for a few seconds each (CI smoke run of
# tools/fuzz-readers; longer runs: tools/fuzz-readers READER 600). Skipped without clang.
set -uo pipefail
command -v clang >/dev/null || { echo "clang not found: skipping"; exit 77; }
src=${WEDGE_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}
fail=0
leftovers() { ls /tmp/wedge-fuzz-*.bin 2>/dev/null | wc -l; }
before=$(leftovers)
for reader in ply exr png; do
    work=${WEDGE_BUILD_DIR:-/tmp}/fuzz-smoke-$reader
    mkdir -p "$work"
    WEDGE_FUZZ_DIR="$work" "$src/tools/fuzz-readers" $reader "${WEDGE_FUZZ_SECONDS:-8}" >"$work/log" 2>&1
    rc=$?
    echo "$reader: $(grep -E 'stat::number_of_executed_units' "$work/log")"
    if [ $rc -ne 0 ]; then
        echo "FAIL: the $reader fuzzer failed (exit $rc); reproducers in $work:" >&2
        ls "$work" | grep -E '^(crash|leak|timeout|oom)-' >&2 || true
        grep -E 'ERROR|SUMMARY' "$work/log" | head -5 >&2
        fail=1
    fi
done
# the harness writes each input to /tmp/wedge-fuzz-PID.bin and must remove it
after=$(leftovers)
[ "$after" -le "$before" ] || { echo "FAIL: the fuzzers left $((after - before)) input file(s) in /tmp" >&2; fail=1; }
exit $fail
