/* The soft-shadow side of MAAF (seeds/003 Sec. 6.1): where a light sample sits in the light's
 * plane (y), the per-pixel sums of eq. 20 in complex form, and each pixel's x-filter
 * parameters from its wedge (s_min, s_max). docs/algorithms.md 9.6.
 *
 * 4D filter = product of two 2D designs, one per axis of the light's plane (t1, t2 of
 * maaf_basis). The y-factor of band p along one axis is
 *     b_p(y) = g(y; sy_p) exp(-j C_y^p y)        (C_y^p = Omega_y_max 2p/(2N-1), sy_p = Omega_y_max/(2N-1))
 * with the minus sign of docs/algorithms.md 9.4; it depends only on the light, so it is applied
 * while sampling, before the wedge of the pixel is known. */
#ifndef WEDGE_RECON_MAAF_SHADOW_H
#define WEDGE_RECON_MAAF_SHADOW_H

#include "recon/maaf/maaf_design.h"
#include "recon/maaf/maaf_filter.h"

/* One light as MAAF sees it: the centre and normal of its whole emitter (all triangles of one
 * shape; a sphere has no fixed normal), and its y-design. */
typedef struct {
    float center[3];
    float normal[3];          /* planar emitters; zero for spheres (receiver -> centre) */
    float omega_y_max;        /* 2 / sigma_light, radians per world unit (0: not an area light) */
    float cy[MAAF_PAIRS_MAX], sy[MAAF_PAIRS_MAX];
} MaafLight;

/* The y-design of a light of Gaussian width sigma_light_world (Sec. 3: Omega_y_max = 2/sigma). */
void maaf_light_design(float sigma_light_world, int pairs, MaafLight *l);

/* The unit normal of the plane the light sample is measured in, seen from receiver p. */
void maaf_light_normal(const MaafLight *l, const float p_world[3], float n[3]);

/* Adds one sample's value f4 (r, g, b, 1) at light coordinates (y1, y2) (world units from the
 * light's centre along t1, t2) to the pixel's sums ysum (8 floats per component). */
void maaf_accumulate(int pairs, const MaafLight *l, float y1, float y2, const float f4[4], float *ysum);

/* A pixel's x-filter (param: MAAF_PARAM_STRIDE floats) for the wedge [s_min, s_max] of a light
 * with omega_y_max, filter knob kappa (>= 1 narrows: every x-width times kappa), pixel of
 * pixel_world at the receiver. Returns the central component's primal std in pixels (the
 * filter's scale, an AOV); 0 and radius 0 when it cannot filter. */
float maaf_pixel_param(float s_min, float s_max, float omega_y_max, int pairs, float kappa, float pixel_world,
                       float *param);
/* A pixel with no occluder near it: only the central component, a plain Gaussian of std_px. */
void maaf_pixel_param_plain(float std_px, float pixel_world, int pairs, float *param);

#endif
