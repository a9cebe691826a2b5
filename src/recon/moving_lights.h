/* A frame's area lights that move during the shutter: whether any does, and a planar moving
 * light's poses and swept extent, shared by MAAF's swept light (maaf_light_sweep.h) and FSF's
 * (fsf_light.h).
 *
 * The shadow filters once read each area light's geometry at shutter open (renderer_light_info)
 * alone, and a light that moved made them biased (docs/benchmarks.md, held4). Since mlight1 AAF
 * and MAAF take the light's poses over the shutter (docs/algorithms.md 1.9 and 9.29); since
 * fsf13 FSF takes the swept light with the samples' density over it (docs/algorithms.md 10,
 * "The swept light's density"). auto leaves the soft shadows of such a frame to Monte Carlo
 * whichever filter it chose (recon_select_moving_light: its probe misjudges these frames). */
#ifndef WEDGE_RECON_MOVING_LIGHTS_H
#define WEDGE_RECON_MOVING_LIGHTS_H

#include <stdbool.h>

#include "render/renderer.h"

/* True when an emitting area light of r's scene is on a shape whose transform changes over
 * the shutter (its instance moves). */
bool recon_area_light_moves(const Renderer *r);

/* The pose at shutter time u (in [0, 1]) of the emitter shape that light `light` of r belongs
 * to (every triangle of that shape): its area-weighted centroid (world metres) and its extent
 * from that centroid along the unit axes axis1, axis2 (metres, lo < hi). A disk light stands
 * for its box of the same area: extent +-disk_half around its centre. false when the light is
 * not an area light, its shape has no area or the extent is empty. */
bool recon_light_pose(const Renderer *r, int light, float u, float disk_half, const float axis1[3],
                      const float axis2[3], double centre[3], double lo[2], double hi[2]);

/* The poses of a swept light: those at the midpoints of RECON_SWEEP_POSES equal parts of the
 * shutter (MAAF's design reads each; their mean centre is the swept light's) and the extent of
 * their union with the poses at the shutter's two ends (no sample falls outside it). */
enum { RECON_SWEEP_POSES = 32 };
typedef struct {
    double centre[3];                                      /* the poses' mean centroid (world) */
    float lo[2], hi[2];                                    /* the union's extent from centre */
    float pose_lo[2][RECON_SWEEP_POSES], pose_hi[2][RECON_SWEEP_POSES]; /* each pose's, from centre */
    bool ends_ok[2];                                       /* the pose at shutter open, close was read */
    double end_centre[2][3];                               /* and their centroids (world) */
    double end_lo[2][2], end_hi[2][2];                     /* and extents, from their own centroids */
} ReconLightSweep;

/* Fills s for light `light` (recon_light_pose's arguments) from its poses; false when any
 * midpoint pose cannot be read. */
bool recon_light_sweep(const Renderer *r, int light, float disk_half, const float axis1[3], const float axis2[3],
                       ReconLightSweep *s);

#endif
