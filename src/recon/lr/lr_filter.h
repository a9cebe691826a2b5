/* LR's per-partition 5D filter (LR section 5, eqs. 8-14, Appendix B and C): from the range of
 * circle-of-confusion slopes and motion slopes of the samples of one partition (a tile's depth
 * layer) to the scale, two shears and the primal product of Gaussians
 *
 *     w(x, y, u, v, t) = w(x + eta u + xi t; sigma_x) w(y + rho v; sigma_y) w(u) w(v) w(t)
 *
 * in the partition's rotated frame (x along its mean motion). Coordinates and signs are ours
 * (docs/algorithms.md, "Layered reconstruction"): a static point of the layer is seen at
 *     x = x0 + c u + d (t - 1/2),   y = y0 + c v
 * with x, y in pixels, u, v on the unit lens disk, t in [0, 1] (the shutter interval),
 * c in px per unit u (signed circle of confusion) and d in px per unit t (motion along x). */
#ifndef WEDGE_RECON_LR_FILTER_H
#define WEDGE_RECON_LR_FILTER_H

#include <stdbool.h>

/* Which band limit clips the spectrum first along the partition's corner ray (Appendix B). */
typedef enum { LR_CLIP_X = 0, LR_CLIP_U = 1, LR_CLIP_T = 2 } LrClip;

typedef struct {
    float sigma_pixel_px; /* the pixel's band limit, as a primal Gaussian (LR: 1/3 px) */
    float sigma_pixel_still_px; /* the same for a layer filtered without motion (its slopes'
                                 * motion range 0): lr_still_sigma_pixel_px of the frame's
                                 * samples per pixel (docs/algorithms.md 8.36); default 1/3 */
    float sigma_lens;     /* the aperture, unit-disk lens units (LR: sigma_a = 1/3; ours 1/2,
                           * the renderer's uniform disk's per-axis std) */
    float sigma_shutter;  /* the shutter, in units of the shutter interval t in [0, 1]
                           * (LR: 2/3 on their shutter [-1, 1], i.e. 1/3 here) */
    float sigma_clamp_px; /* largest primal screen sigma: (N_s - N) / 4 (LR Appendix C) */
    bool flat_lens_time;  /* weight samples flat in u, v, t (the renderer's uniform disk and
                           * box shutter) instead of by the Gaussian aperture and shutter; the
                           * Gaussians still shape the screen filter (docs/algorithms.md 8.15) */
    bool shaped_screen;   /* with flat weights: the screen filter's share that stands for the
                           * lens disk and the shutter box in their own shapes (the
                           * aperture_* and shutter_* fields below), not Gaussian (8.18) */
    bool round_screen;    /* with shaped_screen: a layer blurred by the lens alone (no motion
                           * share) gets one isotropic 2D screen filter, the lens disk itself,
                           * instead of the separable product of its two projections, a rounded
                           * square (lr_taps.h: lr_screen_round; docs/algorithms.md 8.28) */
} LrFilterConfig;

/* The paper's constants, with sigma_clamp for a 16-pixel tile in a 32-pixel window. */
LrFilterConfig lr_filter_config_default(void);

/* The pixel band's primal sigma (px) of a layer without motion in a frame filtered from spp
 * samples per pixel: LR's 1/3 px from LR_PIXEL_BAND_SPP samples up, (1/3) (LR_PIXEL_BAND_SPP /
 * spp)^(1/4) below (0.396 px at 8 spp, 0.471 at 4): the width of the smoothing a still layer
 * near focus gets on top of its pixel's box, chosen for the error at the frame's sample count,
 * the variance falling as 1 / (spp sigma^2) and the bias rising with sigma (docs/algorithms.md
 * 8.36). Layers with motion keep 1/3 px. */
enum { LR_PIXEL_BAND_SPP = 16 };
float lr_still_sigma_pixel_px(int spp);

/* The slopes of one partition: ranges may be degenerate (min == max) and may straddle 0. */
typedef struct {
    float c_min_px, c_max_px; /* circle-of-confusion slope dx/du (= dy/dv), px per unit u */
    float d_min_px, d_max_px; /* motion slope along the rotated x axis, px per unit t */
} LrSlopes;

/* The primal filter, stored as Fourier scales (1/sigma): 0 means a flat weight in that
 * dimension (sigma infinite), which is how the reductions appear (no motion: inv_sigma_t = 0). */
typedef struct {
    LrClip clip_x;         /* case of the xut subspace */
    LrClip clip_y;         /* case of the yv subspace (LR_CLIP_X or LR_CLIP_U) */
    bool clamped;          /* sigma_x or sigma_y hit sigma_clamp_px (Appendix C) */
    float inv_sigma_x_px;  /* 1/sigma_x, 1/px */
    float eta_px;          /* shear of x by u, px per unit u (eq. 11) */
    float xi_px;           /* shear of x by t, px per unit t (eq. 11: xi = beta) */
    float inv_sigma_u;     /* 1/sigma_u, per unit u */
    float inv_sigma_t;     /* 1/sigma_t, per unit t */
    float inv_sigma_y_px;  /* 1/sigma_y, 1/px */
    float rho_px;          /* shear of y by v, px per unit v */
    float inv_sigma_v;     /* 1/sigma_v */
    /* In the flat-weight filter, the share of the screen filter's variance that stands for
     * the lens disk and the shutter box (what the reprojection took out of the samples and
     * the screen filter puts back), in their own shapes (lr_taps.h): the disk's radius along
     * and across the motion (its projection on an axis is a semicircle, variance R^2 / 4)
     * and the box's length along it (variance L^2 / 12). 0 in the Gaussian design. */
    float aperture_x_px, shutter_x_px, aperture_y_px;
} LrFilter;

/* Appendix B + C as the paper has them: the filter of one partition. Its blur at the
 * layer's central slopes is only the band it was clipped by (the aperture's in case U, the
 * shutter's in case T, docs/algorithms.md 8.3). */
LrFilter lr_filter_make_paper(const LrSlopes *s, const LrFilterConfig *cfg);

/* What LR uses: with cfg->sigma_pixel_still_px as the band of a layer without motion (s's
 * motion range 0), lr_filter_make_paper convolved with the Gaussian aperture and shutter it does
 * not already contain (both blurs at the central slopes), the excess over sigma_clamp taken
 * back by reprojecting less (docs 8.4); with cfg->flat_lens_time, the sample weights in u, v
 * and t flat (inv_sigma_u = inv_sigma_v = inv_sigma_t = 0). Never produces NaN or Inf for
 * finite input. */
LrFilter lr_filter_make(const LrSlopes *s, const LrFilterConfig *cfg);

/* Whether a layer of slopes s has no motion and a lens blur within the still layers' pixel
 * band: the uniform disk's per-axis std at its largest slope, |c| / 2 px, at most
 * cfg->sigma_pixel_still_px (its whole slope range is then clipped by the band, case X: the
 * screen filter only smooths it, 8.36). docs/algorithms.md 8.49. */
bool lr_blur_within_band(const LrSlopes *s, const LrFilterConfig *cfg);

/* The Fourier-domain warp of eq. 8 (the case's scale then two shears, in the order
 * (Omega_x, Omega_u, Omega_t)) before the x-only rewrite, for tests of eqs. 10-11. */
void lr_filter_warp(const LrSlopes *s, const LrFilterConfig *cfg, double S[3][3]);

/* The primal weight of eq. 13 in the xut subspace (unnormalised, 1 at the origin), for an
 * offset (dx_px, du, dt) from the evaluation point. */
double lr_filter_weight_xut(const LrFilter *f, double dx_px, double du, double dt);

#endif
