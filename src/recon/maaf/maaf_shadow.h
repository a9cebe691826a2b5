/* The soft-shadow side of MAAF (seeds/003 Sec. 6.1): where a light sample sits in the light's
 * plane (y), the per-pixel sums of eq. 20 in complex form, and each pixel's x-filter
 * parameters from its wedge (s_min, s_max). docs/algorithms.md 9.6.
 *
 * 4D filter = product of two 2D designs, one per axis (t1, t2) of the light's plane, along the
 * light's edges. A sample at y (uniform on the light) gets, per axis and band p, the y-factor
 *     c_p(y) = int_{light} exp(j C_y^p (y' - y)) g(y' - y; sy_p) dy'
 *            (C_y^p = Omega_y_max 2p/(2N-1), sy_p = Omega_y_max/(2N-1))
 * the primal component integrated over the light (docs/algorithms.md 9.6: it is what makes the
 * estimate converge to the light integral rather than to a weighted one; the phase sign is that
 * of 9.4). It depends only on the light, so it is applied while sampling, before the wedge of
 * the pixel is known. With C_y^p / sy = 2p it is c_p(y) = Phi_p(sy (hi - y)) - Phi_p(sy (lo - y))
 * for one function Phi_p of every light (maaf_band_cdf.h), so a light keeps its design and
 * extent, not a table. */
#ifndef WEDGE_RECON_MAAF_SHADOW_H
#define WEDGE_RECON_MAAF_SHADOW_H

#include "recon/maaf/maaf_design.h"
#include "recon/maaf/maaf_filter.h"

/* Nodes of the trapezoid rule over the light's extent that its mean c_p is taken with. */
#define MAAF_MEAN_NODES 129

/* Poses of a moving light over the shutter that its sample density is taken from. */
#define MAAF_SWEEP_NODES 32

/* A moving light's poses: each one's extent along the light's axes, as lo, hi (world units from
 * the swept light's centre). */
typedef struct {
    float lo[2][MAAF_SWEEP_NODES], hi[2][MAAF_SWEEP_NODES];
} MaafSweep;

/* One light as MAAF sees it: the centre of its whole emitter (all triangles of one shape), its
 * plane's axes (zero for spheres: the plane facing each receiver), its extent along them
 * relative to the centre, its y-design and its mean c_p. A planar light that moves
 * during the shutter is its swept light (maaf_light_sweep.h): the centre its mean over the
 * shutter, the extent the union of its poses', and each pose's extent read for the density of
 * its samples while its design is made. The poses are the caller's (a mesh light's triangles
 * share their shape's), not the light's: 152 bytes a light instead of 664, and a light of a
 * finished table (maaf_lights_from_renderer) holds none. */
typedef struct {
    float center[3];
    float t1[3], t2[3];       /* unit axes in the light's plane (planar emitters) */
    float lo[2], hi[2];       /* extent along t1, t2 from the centre, world units */
    int sweep_nodes;          /* a moving light: its poses at sweep_nodes shutter times; 0: static */
    const MaafSweep *sweep;   /* those poses while the design is made (NULL: static, or designed) */
    float omega_y_max;        /* 2 / sigma_light, radians per world unit (0: not an area light) */
    float sy;                 /* the y-Gaussians' Fourier std Omega_y_max / (2N - 1) (eq. 6; band p's
                               * centre C_y^p is 2p sy), radians per world unit */
    float mean[2][MAAF_PAIRS_MAX][2]; /* [axis][p] c_p averaged over the light's samples (re, im) */
} MaafLight;

/* Fills the y-design (Sec. 3: Omega_y_max = 2/sigma_light) and the means of c_p of a light whose
 * centre, axes and extent (and sweep, if it moves) are set. */
void maaf_light_design(float sigma_light_world, int pairs, MaafLight *l);
/* The same design copied from an earlier light (same pairs) when it is the one maaf_light_design
 * would make: the same band and extents, and for a moving light the same poses, both at hand (a
 * mesh light's triangles share their shape's). False, and l untouched, otherwise. */
bool maaf_light_design_copy(const MaafLight *from, float sigma_light_world, MaafLight *l);

/* The axes a receiver at p measures this light's samples along (planar: the light's; sphere:
 * a plane facing p, maaf_basis). */
void maaf_light_axes(const MaafLight *l, const float p_world[3], float t1[3], float t2[3]);

/* c_p(y) along axis a from the universal table (maaf_band_cdf.h), y from the centre in world
 * units, taken as the nearest point of the light's extent outside it (a disk's or sphere's
 * samples outside its box of the same area; NaN as lo). */
void maaf_light_factor(const MaafLight *l, int axis, int p, float y, float c[2]);

/* Adds one sample's value f4 (r, g, b, 1) at light coordinates (y1, y2) (world units from the
 * light's centre along t1, t2) to the pixel's sums ysum (8 floats per component): the products
 * of the per-axis factors c_p(y), except the central component (0, 0)'s, the product of c_0's
 * means over the light (flat: the light's samples weighted alike, docs/algorithms.md 9.20). */
void maaf_accumulate(int pairs, const MaafLight *l, float y1, float y2, const float f4[4], float *ysum);

/* The same for a sample whose light point is unknown (the receiver faces away from the light
 * point it drew, so no shadow ray was traced: f is 0 or the BSDF-sampled part): c_p averaged
 * over the light, its expectation. Leaving such samples out would raise the estimate by
 * spp / (samples with a shadow ray) near a terminator. */
void maaf_accumulate_unknown(int pairs, const MaafLight *l, const float f4[4], float *ysum);

/* A pixel's x-filter (param: MAAF_PARAM_STRIDE floats) for the wedge [s_min, s_max] of a light
 * with omega_y_max, filter knob kappa (>= 1 narrows: every x-width times kappa), pixel of
 * pixel_world at the receiver. Returns the central component's primal std in pixels (the
 * filter's scale, an AOV); 0 and radius 0 when it cannot filter. */
float maaf_pixel_param(float s_min, float s_max, float omega_y_max, int pairs, float kappa, float pixel_world,
                       float *param);
/* A pixel with no occluder near it: only the central component, a plain Gaussian of std_px. */
void maaf_pixel_param_plain(float std_px, float pixel_world, int pairs, float *param);

#endif
