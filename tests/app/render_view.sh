#!/usr/bin/env bash
# wedge render --view (issue 4): PNG output goes through an OpenColorIO view; an unknown view
# is a usage error (exit 1) with the OCIO message naming the available views, reported before
# any rendering; --help lists the views; EXR header attributes carry the wedge.* names.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
make_temp_dir
unset OCIO # the built-in config: display sRGB with views Standard, Filmic, Raw
fail=0

# --help lists the views of the active config
"$WEDGE" render --help >"$T/help.txt" 2>&1; check "--help" 0 $?
grep -q -- "--view NAME" "$T/help.txt" || { echo "FAIL: --help lacks --view"; fail=1; }
grep -q "views: Standard, Filmic, Raw" "$T/help.txt" || { echo "FAIL: --help lacks the view list"; fail=1; }

# PNG through named views; Standard and Raw differ (sRGB encoding vs none) on the default scene
for v in Standard Filmic Raw; do
    "$WEDGE" render --spp 1 --res 16x12 --seed 1 --view "$v" -o "$T/$v.png" --quiet; check "render --view $v" 0 $?
    head -c 8 "$T/$v.png" | grep -aq PNG || { echo "FAIL: --view $v wrote no PNG"; fail=1; }
done
cmp -s "$T/Standard.png" "$T/Raw.png" && { echo "FAIL: views Standard and Raw gave identical PNGs"; fail=1; }
"$WEDGE" render --spp 1 --res 16x12 --seed 1 -o "$T/default.png" --quiet; check "render PNG default view" 0 $?
cmp -s "$T/Standard.png" "$T/default.png" || { echo "FAIL: the default view is not Standard"; fail=1; }

# unknown view: the OCIO message, exit 1, no output file
"$WEDGE" render --spp 1 --res 8x8 --view Bogus -o "$T/bogus.png" >/dev/null 2>"$T/err.txt"; check "unknown view" 1 $?
grep -qF "error: unknown view 'Bogus' (display 'sRGB' has views: Standard, Filmic, Raw)" "$T/err.txt" ||
    { echo "FAIL: unknown view message: $(cat "$T/err.txt")"; fail=1; }
[ -e "$T/bogus.png" ] && { echo "FAIL: a PNG was written for an unknown view"; fail=1; }
"$WEDGE" render --view >/dev/null 2>&1; check "--view without value" 1 $?

# EXR header attribute names (issue 3)
"$WEDGE" render --spp 1 --res 8x8 -o "$T/a.exr" --quiet; check "render EXR" 0 $?
for at in wedge.spp wedge.seed wedge.seconds wedge.version wedge.scene; do
    grep -aq "$at" "$T/a.exr" || { echo "FAIL: EXR header lacks $at"; fail=1; }
done
grep -aq "wedgeSpp" "$T/a.exr" && { echo "FAIL: EXR header still has the old name wedgeSpp"; fail=1; }

exit $fail
