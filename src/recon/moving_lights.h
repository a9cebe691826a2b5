/* Whether a frame's area lights move during the shutter: the shadow filters (AAF, MAAF, FSF)
 * read each area light's geometry at shutter open (renderer_light_info) and derive their
 * widths and their unoccluded irradiance from that one pose, so a light that moves makes them
 * biased (docs/algorithms.md, "auto's fallback to Monte Carlo", a moving area light). */
#ifndef WEDGE_RECON_MOVING_LIGHTS_H
#define WEDGE_RECON_MOVING_LIGHTS_H

#include <stdbool.h>

#include "render/renderer.h"

/* True when an emitting area light of r's scene is on a shape whose transform changes over
 * the shutter (its instance moves). */
bool recon_area_light_moves(const Renderer *r);

#endif
