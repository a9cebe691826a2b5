/* A planar area light that moves during the shutter as MAAF's soft-shadow filter sees it: the
 * swept light (docs/algorithms.md 9.29).
 *
 * The scene does not move with the light, so a pixel's visibility is a function of the world
 * point y on the light's plane alone, and its samples' light points are spread over every
 * place the light covers during the shutter, with a density proportional to the time it covers
 * each. The light field is then that of a static light with this extent and this density, and
 * c_p(y) (maaf_shadow.h) integrates the kernel over the swept extent: the samples' density
 * cancels between the kernel estimate and the light's weight, as the uniform density does for
 * a static light. Coordinates y are measured from the centre's mean over the shutter along the
 * axes of the pose at shutter open (exact for a translating light; a turning light's axes turn,
 * and its extent is then projected on the first pose's axes). */
#ifndef WEDGE_RECON_MAAF_LIGHT_SWEEP_H
#define WEDGE_RECON_MAAF_LIGHT_SWEEP_H

#include "recon/maaf/maaf_shadow.h"
#include "render/renderer.h"

/* For light `light` of r (a triangle of a planar emitter, or a disk whose box of the same
 * area has half side disk_half), which moves: replaces l's centre and extent (its axes set) by
 * its swept light's from its poses at MAAF_SWEEP_NODES shutter times (the midpoints of equal
 * parts; recon_light_sweep, moving_lights.h, which FSF shares), writes each pose's extent to
 * poses and points l->sweep at them (the caller keeps them until l's design is made). Returns
 * false, l and poses untouched, when the light does not move or is not planar (or poses is
 * NULL). */
bool maaf_light_sweep(const Renderer *r, int light, float disk_half, MaafSweep *poses, MaafLight *l);

#endif
