/* LR's screen filter along one axis of a partition's rotated frame (Algorithm 2): its radius
 * and its tap weights, computed once per partition on the host and shared by the C passes
 * (lr_reconstruct.c) and the kernels (lr.cl reads them), so both weight every tap with the
 * same value. */
#ifndef WEDGE_RECON_LR_TAPS_H
#define WEDGE_RECON_LR_TAPS_H

#include <stdbool.h>

#include "recon/lr/lr_partition.h"

/* The kernels' tap tables hold radii up to this. */
enum { LR_MAX_RADIUS_PX = 32 };

/* Screen-filter radius for a primal sigma: 3 sigma, at least 0, at most half the window and
 * at most LR_MAX_RADIUS_PX. */
int lr_filter_radius_px(float inv_sigma_px, const LrConfig *cfg);

/* The screen passes' radii for a partition's filter (along its motion, across it): the
 * Gaussian's 3 sigma plus the lens disk's radius and half the shutter box's length of the
 * flat-weight filter (lr_filter.h), capped as above; 0 for a layer with neither blur (no
 * shear, both sigmas at most sigma_pixel_still: a static layer seen through a pinhole), whose
 * samples stay in their pixels: the pixel filter alone would only spread each pixel by 1.1%
 * into its neighbours, which around a light source is a visible ring (docs 8.11). */
void lr_screen_radii_px(const LrFilter *f, const LrConfig *cfg, int *rx, int *ry);

/* The taps w[0..r] along (across = false) or across the motion. A filter with no disk or box
 * share is the Gaussian exp(-(k / sigma)^2 / 2) at the taps; otherwise the profile
 *     Gauss(sigma_rest) (x) semicircle of radius R (x) box of length L
 * (R the disk's radius: a uniform disk projected on an axis; L the shutter's length;
 * sigma_rest^2 = sigma^2 - R^2 / 4 - L^2 / 12, so the variance stays sigma^2) integrated over
 * each tap's pixel; shares under 2 px, and what reaches past the window's margin, go to the
 * Gaussian. docs/algorithms.md 8.18. */
void lr_screen_taps(const LrFilter *f, const LrConfig *cfg, bool across, int r, float *w);

/* The round screen filter (docs/algorithms.md 8.28). A uniform disk is not separable: the product
 * of its two projections (the semicircles of lr_screen_taps) is a rounded square, whose spectrum
 * differs from the disk's along the diagonals, where a checkerboard's fundamental lies. A layer
 * blurred by the lens alone (psi = 0, no shutter share) whose disk share survives along both axes
 * is therefore filtered by one 2D table over the squared offset d2 = dx^2 + dy^2 of a grid cell
 * from the pixel, |d| <= r: the disk of radius R with its rim softened by the Gaussian rest,
 * 0.5 erfc((|d| - R) / (s sqrt 2)), with R set so that the table's variance along an axis is the
 * screen variance sigma^2 of the separable filter it replaces. Returns false (table untouched)
 * for any other layer; else r (both screen radii) and table[0 .. r^2], normalised to sum 1 over
 * the disk of radius r. */
enum { LR_ROUND_MAX_PX = 16, LR_ROUND_TABLE = LR_ROUND_MAX_PX * LR_ROUND_MAX_PX + 1 };
bool lr_screen_round(const LrFilter *f, const LrConfig *cfg, float cos_psi, float sin_psi, int *r, float *table);

/* A partition's whole screen filter as the passes read it: the round filter (round, its radius
 * in rx and ry, table) or the two passes' radii and taps. Entries past a radius are 0. */
typedef struct {
    int rx, ry;
    bool round;
    float taps_x[LR_MAX_RADIUS_PX + 1], taps_y[LR_MAX_RADIUS_PX + 1];
    float table[LR_ROUND_TABLE];
} LrScreen;

/* The screen filter of filter f (rotated by psi): lr_screen_round's, else lr_screen_radii_px's
 * radii and lr_screen_taps' taps. */
void lr_screen_make(const LrFilter *f, const LrConfig *cfg, float cos_psi, float sin_psi, LrScreen *s);

/* Whether two screen filters weight every tap alike. */
bool lr_screen_same(const LrScreen *a, const LrScreen *b);

#endif
