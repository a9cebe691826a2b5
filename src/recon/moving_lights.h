/* Whether a frame's area lights move during the shutter. The shadow filters once read each area
 * light's geometry at shutter open (renderer_light_info) alone, and a light that moved made them
 * biased (docs/benchmarks.md, held4). Since mlight1 AAF and MAAF take the light's poses over the
 * shutter (docs/algorithms.md 1.9 and 9.29) and are not warned about when asked for by name;
 * FSF takes the area the light sweeps as a uniform light, which it is not, and is. auto leaves
 * the soft shadows of such a frame to Monte Carlo whichever filter it chose
 * (recon_select_moving_light: its probe misjudges these frames). */
#ifndef WEDGE_RECON_MOVING_LIGHTS_H
#define WEDGE_RECON_MOVING_LIGHTS_H

#include <stdbool.h>

#include "render/renderer.h"

/* True when an emitting area light of r's scene is on a shape whose transform changes over
 * the shutter (its instance moves). */
bool recon_area_light_moves(const Renderer *r);

#endif
