#!/usr/bin/env bash
# Mitsuba 3 renders two bench scenes (soft shadows: area light, MIS; defocus: thin lens,
# point and distant lights, checkerboard texture) as wedge does, up to noise (issue 23).
# tools/peer-bench agree renders two wedge images and two Mitsuba images of other seeds and
# checks that D(Mitsuba, wedge) / ((D(Mitsuba, Mitsuba') + D(wedge, wedge')) / 2) is in
# [0.8, 1.25] (D = the relMSE-weighted squared difference; the ratio is 1 in expectation when
# the renderers agree; tools/peer/agree.py derives it). The bounds: at 64x64 and 256 spp the
# ratio scatters by about 5% between seeds (measured 0.91-1.05); a 2% brightness error or a
# mirrored image (printed as "mirrored image") gives 2 and over 100.
# Skipped (77) where the Python environment or LLVM 19 is missing (tools/peer-bench setup).
set -euo pipefail
: "${WEDGE:?}" "${WEDGE_SOURCE_DIR:?}"
bench="$WEDGE_SOURCE_DIR/tools/peer-bench"
if ! why=$("$bench" check); then
  echo "SKIP: $why"
  exit 77
fi
"$bench" agree "$WEDGE_SOURCE_DIR/scenes/bench/soft_shadows.pbrt" "$WEDGE_SOURCE_DIR/scenes/bench/defocus.pbrt" \
  --wedge "$WEDGE" --res 64x64 --spp 256 --check --lo 0.8 --hi 1.25
