/* The defocus side of MAAF (seeds/003 Sec. 6, the 4D (x, u) case): the lens-factors of eq. 20
 * for a disk aperture, the per-pixel x-filter from a signed slope range, and the screen-space
 * guides that let the soft-shadow image pass (maaf.cl) filter along pixel rows and columns.
 * docs/algorithms.md 9.8.
 *
 * 4D = two 2D designs, screen x with lens u and screen y with lens v. In raster pixels a point at
 * camera depth z is seen at x = x0 + coc u and y = y0 - coc v (coc = recon_coc_slope_px: raster y
 * runs down, camera y up), so with v' = -v the radiance is T(x - coc u, y - coc v'): a function
 * of x + s u with s = -coc on both axes, the shadow convention of 9.2. The caller passes
 * (u, -v) and slopes -coc.
 *
 * The lens-factor of component (p, q) is the component integrated over the aperture (as the
 * light's y-factor, 9.6):
 *     c_pq(u, v) = int_{unit disk} exp(j (C^p (u' - u) + C^q (v' - v))) g(u' - u; su) g(v' - v; su) du' dv'
 * with C^q = Omega_u_max 2q / (2N - 1) (negative for q < 0) and su = Omega_u_max / (2N - 1). The
 * disk does not separate into a product of per-axis factors (the light's box does), so each
 * component of the half set has its own 2D table over [-1, 1]^2. */
#ifndef WEDGE_RECON_MAAF_DEFOCUS_H
#define WEDGE_RECON_MAAF_DEFOCUS_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/maaf/maaf_design.h"
#include "recon/maaf/maaf_filter.h"

/* Table entries per lens axis (bilinear interpolation between them). */
#define MAAF_LENS_TABLE 129
/* Entries stored per axis (index 0 .. 65 of 129, the quadrant u, v <= 0): c_pq(-u, -v) =
 * conj c_pq(u, v) and c_pq(u, -v) = c_{p,-q}(u, v) give the rest (maaf_lens_factors). The entry
 * past the middle keeps the interpolation of u = 0 and v = 0 inside the quadrant. A quarter of
 * the table (0.45 MB at N = 3 instead of 1.7; the half of "MAAF frames, cheaper again" in
 * docs/benchmarks.md was 0.9 MB) leaves most of a 1 MB L2 cache to the sums. */
#define MAAF_LENS_ROWS ((MAAF_LENS_TABLE + 1) / 2 + 1)

/* The unit disk's per-axis standard deviation (docs/algorithms.md 3.2: sigma_u = 1/2); the lens
 * band is Omega_u_max = kappa 2 / sigma_u, as the light's 2 / sigma_light (9.2). */
#define MAAF_LENS_SIGMA 0.5f
/* The defocus knob's default (--mu; docs/algorithms.md 9.8 has the measurement). */
#define MAAF_DEFOCUS_KAPPA_DEFAULT 3.0f

typedef struct {
    int pairs, comps;
    float omega_u_max;  /* radians per unit lens coordinate */
    float *table;       /* [iu < MAAF_LENS_ROWS][iv < MAAF_LENS_ROWS][c] (re, im): a sample reads one cell for
                         * every component */
    signed char vflip[MAAF_COMPS_MAX]; /* component (p, -q)'s index; -1 - c at p = 0: conj of c itself */
    float mean[MAAF_COMPS_MAX]; /* direction tables only: maaf_direction_mean per component */
} MaafLens;

/* Fills the tables for the knob kappa (Omega_u_max = kappa 2 / MAAF_LENS_SIGMA). False when out
 * of memory (l->table NULL). */
bool maaf_lens_design(float kappa, int pairs, MaafLens *l);
void maaf_lens_free(MaafLens *l);
/* The table's builders store cell (iu, iv) of component c with this (cells outside the stored
 * quadrant are dropped), and fill vflip with maaf_lens_flips. */
void maaf_lens_store(MaafLens *l, int c, int iu, int iv, float re, float im);
void maaf_lens_flips(MaafLens *l);

/* Band centre of band q (q may be negative) and the bands' Fourier std, radians per unit u. */
float maaf_lens_band_centre(const MaafLens *l, int q);
float maaf_lens_band_std(const MaafLens *l);

/* c_pq(u, v) of component c (half-set order of maaf.cl), interpolated from the table. */
void maaf_lens_factor(const MaafLens *l, int c, float u, float v, float out[2]);

/* Adds one sample's value f4 (r, g, b, 1) at lens point (u, v) (the design's orientation:
 * the caller flips v, see above) to a pixel's sums (8 floats per component). */
void maaf_lens_accumulate(const MaafLens *l, float u, float v, const float f4[4], float *ysum);
/* The same in two steps, for a caller that adds several values with one lens point's factors:
 * w (2 comps floats: every component's c_pq (re, im), maaf_lens_factor's values) once, then
 * maaf_factors_accumulate (maaf_filter.h) per value. */
void maaf_lens_factors(const MaafLens *l, float u, float v, float *w);

/* A pixel's x-filter for the signed slope range [s_min, s_max] (shadow convention: the signal
 * is a function of x + s u; for defocus s = -coc): slopes of one sign use maaf_pixel_param's
 * design, mirrored (C_x negated) when negative; a range that straddles 0 (the focal plane) has
 * a wedge reaching every Omega_x of the pixel band and gets no filter (returns 0, radius 0).
 * x is in pixels (pixel_world 1). Returns the central component's std in pixels. */
float maaf_pixel_param_signed(float s_min, float s_max, float omega_u_max, int pairs, float *param);
/* Its truncation radius, in central stds (maaf_pixel_param's is 2): on the defocus bench at
 * 256x256 (equal samples, 2 seeds, 8-32 spp) 1.5 and 1.25 had 5-10% lower relMSE than 2 (the
 * filter blurs less), 1 about 2's; the soft shadows' error rose at 1.5, so they keep 2
 * (docs/benchmarks.md, "MAAF's image pass, faster"). The pass's cost is about linear in it. */
#define MAAF_DEFOCUS_RADIUS_STD 1.5f

/* Pixel (x, y)'s filter from pass 1's circle-of-confusion ranges (coc_min, coc_max: signed px
 * per unit lens coordinate, recon_coc_slope_px, w x h): the design slopes s = -coc of the pooled
 * ranges (pool_min, pool_max: maaf_coc_pool) averaged over the 5 x 5 window around it (seeds/003
 * Sec. 6.2, pre-filtering), no filter when the pixel's own range or the averaged one straddles
 * the focal plane. *side: the sign of s (0: not filtered). Returns the central std in pixels (0:
 * not filtered). */
#define MAAF_DEFOCUS_WINDOW_PX 2
/* The lens filter's sharpness rule (MaafFilterInput.sharp_factor): a neighbour takes part only
 * if its central std is at least 0.8 of the centre's (sx^2 ratio 1/0.8^2), i.e. its sharpest
 * slope is at least 0.8 of the centre's. The filter reprojects every neighbour's lens samples
 * along the centre's slope (seeds/003 assumes the centre's wedge holds over the footprint), but
 * the wedge is measured over 5 x 5 pixels and the footprint reaches 2 stds (18 px on
 * bokeh_bright): a small emitter's samples, at a slope 0.7 of the black background's, were
 * moved up to 0.3 coc past its disk (halos). Measured (docs/algorithms.md 9.8): 0.5 (the light
 * filter's rule) / 0.7 / 0.8 / 0.9 gave bokeh_bright 7.1 / 1.6 / 0.49 / 0.28 and the defocus
 * bench 1.91e-4 / 1.90e-4 / 1.94e-4 / 2.17e-4 at 16 spp; 0.8 keeps the bench. */
#define MAAF_LENS_SHARP_FACTOR 1.5625f
float maaf_defocus_pixel(const float *coc_min, const float *coc_max, const float *pool_min, const float *pool_max,
                         int width, int height, int x, int y, float omega_u_max, int pairs, float *param, float *side);

/* A pixel's range as its neighbourhood's pass-1 samples see it: per pixel the least coc_min and
 * the greatest coc_max over itself and its 4 neighbours that have a range (a pixel without one
 * keeps its own). One pixel's few pass-1 samples miss a surface seen through a small part of the
 * lens (a small bright emitter's bokeh: the emitter's slope is in a disk pixel's range only if
 * one of its samples hit it); its neighbours see the same surface through nearby parts of the
 * lens, so 5 pixels' samples find it far more often. The averaged range of maaf_defocus_pixel
 * then holds that slope, and the filter does not spread the emitter's light along the
 * background's slope (docs/algorithms.md 9.21: bokeh_bright at 8 / 16 spp relMSE 5.8 / 1.2 ->
 * 0.45 / 0.20; the 3 x 3 window: 0.38 / 0.25, and 1-2% more error than the 4 neighbours on the
 * smooth defocus scenes). pool_min, pool_max: w x h each. */
void maaf_coc_pool(const float *coc_min, const float *coc_max, int width, int height, float *pool_min, float *pool_max);

/* Scenes with shading effects (docs/algorithms.md 9.8): a pixel's lens sums hold the rest of the
 * radiance (rest) and, with the same factors, the albedo (alb); this adds one shading light back
 * to o (per floats, a copy of rest): where it was filtered (value4 usable) as factor x value x
 * the albedo sums, where it was passed through as value4's raw light x the weight sums, and
 * where no method filtered it (value4 NULL) as the pixel's raw mean mean3 x the weight sums. */
void maaf_defocus_add_light(const float *value4, float factor, const float mean3[3], const float *rest, const float *alb,
                            size_t per, float *o);

/* The guides of pixel (x, y) for the screen-space pass: position (x, y, 0) in pixels, normal
 * +z with the slope's side of the focal plane (side: -1, +1) as the object id (neighbours on the
 * other side are rejected as another object), axes +x and +y. usable 0: left out. */
void maaf_screen_guides(int x, int y, float side, bool usable, float pos4[4], float nrm4[4], float frame4[4],
                        float axis2[4]);

#endif
