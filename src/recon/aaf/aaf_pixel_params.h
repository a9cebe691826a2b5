/* Per-pixel AAF parameter maps: from the pass-1 statistics of every pixel to a filter width
 * and a sample count per pixel, for each effect (formulas in aaf_params.h).
 *
 * Pixels whose own pass-1 rays saw no occluder (shadows) or no reflector (indirect) borrow
 * the average statistics of the pixels within borrow_radius_px that did (AAF-shadow Sec. 6:
 * "average values of d1 and d2 in a 5 pixel radius"). If none did, the pixel gets far_spp
 * samples and the width far_beta_px (0: not filtered), narrowed to (dist - 1)/2 pixels where
 * dist is the Chebyshev distance to the nearest pixel that saw an occluder: visibility is 1
 * over the whole light there, so only the smooth unshadowed irradiance is noisy, and a filter
 * whose radius (2 beta) ends before that pixel lets no shadow leak in. Same for indirect
 * light with "reflector" for "occluder". */
#ifndef WEDGE_RECON_AAF_PIXEL_PARAMS_H
#define WEDGE_RECON_AAF_PIXEL_PARAMS_H

#include "recon/aaf/aaf_params.h"

/* Pass-1 statistics, one value per pixel, row-major width x height. Any pointer may be NULL
 * when its effect is not present. */
typedef struct {
    int width, height;
    const unsigned char *hit;       /* 1 when the pixel's primary rays hit a surface */
    const float *pixel_world;       /* world size d of the pixel at its receiver */
    /* soft shadows (AAF-shadow Sec. 3): distances along the shadow rays */
    const float *d1_world;          /* light -> receiver (mean) */
    const float *d2min_world;       /* light -> occluder, min over occluded rays; */
    const float *d2max_world;       /*   both 0 when no ray was occluded */
    const float *sigma_light_world; /* std of the light as a Gaussian: sqrt(area)/2 */
    /* indirect (AAF-GI Sec. 5): receiver -> reflector distances along the receiver normal */
    const float *zmin_world;        /* +inf / 0 when no bounce ray hit anything */
    const float *zmax_world;
    const float *blinn_phong_m;     /* NULL: diffuse receivers everywhere; m <= 0: diffuse pixel */
    /* defocus: signed CoC slopes, pixels per unit lens coordinate (min > max: no data) */
    const float *coc_min_px;
    const float *coc_max_px;
} AafPixelStats;

typedef struct {
    int borrow_radius_px;    /* neighbourhood for pixels without occluder/reflector (5) */
    int spp_min;             /* samples already taken in pass 1 */
    float spp_cap;           /* upper bound on n (100 mu) */
    float far_beta_px;       /* largest width for pixels with no occluder/reflector nearby (0: none) */
    int far_spp;             /* their sample count (<= spp_min: spp_min) */
} AafImageConfig;

/* The sample count of a pixel with no occluder (reflector) nearby, filtered at a width that
 * shrinks like 1/mu past mu 2: pass1 * max(1, mu/2)^3, so that the samples under its filter
 * grow like mu and its filtered variance falls as a budget raises mu (with mu/2 they fell like
 * 1/mu, as the indirect cap's did: docs/algorithms.md 2.6). At mu <= 2: pass1. */
int aaf_far_spp(int pass1, float mu);

/* Output maps: beta in world units (shadows, indirect) or pixels (defocus); spp per pixel.
 * Each returns the number of pixels that were filtered (beta > 0). */
int aaf_shadow_params_image(const AafPixelStats *st, const AafShadowConfig *c, const AafImageConfig *ic,
                            float *beta_world, int *spp);
int aaf_indirect_params_image(const AafPixelStats *st, const AafIndirectConfig *c, const AafImageConfig *ic,
                              float scene_size_world, float *beta_world, int *spp);
int aaf_defocus_params_image(const AafPixelStats *st, const AafDefocusConfig *c, const AafImageConfig *ic,
                             float *beta_px, int *spp);

#endif
