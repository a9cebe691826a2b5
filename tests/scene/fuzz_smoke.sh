#!/usr/bin/env bash
# Runs the parser fuzzer for about 30 s (CI smoke run); skipped when clang is missing.
set -uo pipefail
command -v clang >/dev/null || { echo "clang not found: skipping"; exit 77; }
src=${WEDGE_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}
work=${WEDGE_BUILD_DIR:-/tmp}/fuzz-smoke
mkdir -p "$work"
WEDGE_FUZZ_DIR="$work" "$src/tools/fuzz-parser" "${WEDGE_FUZZ_SECONDS:-30}" >"$work/log" 2>&1
rc=$?
tail -5 "$work/log"
if [ $rc -ne 0 ]; then
    echo "fuzzer failed (exit $rc); reproducers in $work:" >&2
    ls "$work" | grep -E '^(crash|leak|timeout|oom)-' >&2 || true
    grep -E 'ERROR|SUMMARY' "$work/log" | head -5 >&2
    exit 1
fi
exit 0
