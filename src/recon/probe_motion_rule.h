/* Which of the gain probe's samples LR would blur along their motion (auto's judgement of its
 * camera filters, auto_fallback.h; docs/algorithms.md, "auto's fallback to Monte Carlo", the
 * motion LR cannot shear).
 *
 * The camera footprint (camera_gain.h) counts a sample's motion as blur a camera filter
 * averages over. LR's filter shears one layer of a tile with one mean motion, and gives the
 * layer no motion filter when its speeds disagree (lr_motion_filter_kept: no clear direction,
 * or too wide a range of speeds): a wheel or a ball spinning about its own axis, two objects
 * passing each other the opposite way. The probe asks the same of its own samples: per 16-px
 * tile of the frame, the moving samples (at least LR_MOVING_PX over the shutter) of the probe
 * pixels inside the tile's 32-px window, grouped by circle of confusion as LR's layers split by
 * depth (the sign and the octave of |c|: below 1 px, 1-4, 4-16, above), give each group's mean
 * direction, its speeds along it and its largest speed across; a tile's moving samples whose
 * group fails the rule have their motion left out of their blur. The groups stand in for LR's
 * layers, whose bounds lie in the gaps of each window's CoC histogram (docs/algorithms.md 8.22):
 * the probe has ~6-16 pixels a window, too few for that histogram. */
#ifndef WEDGE_RECON_PROBE_MOTION_RULE_H
#define WEDGE_RECON_PROBE_MOTION_RULE_H

#include <stdbool.h>

typedef struct {
    float x, y;         /* the probe pixel's centre, raster px */
    float motion_px[2]; /* screen motion over the shutter, px (0 for a miss) */
    float coc_slope_px; /* signed circle-of-confusion slope, px per unit lens (NaN for a miss) */
} ProbeMotionSample;

/* filterable[k] for each of the n samples of a width x height frame: false when sample k
 * moves and LR would give its group of its tile no motion filter; true otherwise (a static
 * sample or a miss, whose motion adds nothing to its blur anyway). False only when out of
 * memory. */
bool probe_motion_filterable(const ProbeMotionSample *s, int n, int width, int height, bool *filterable);

#endif
