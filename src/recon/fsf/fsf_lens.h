/* FSF for defocus: the lens in place of the light (docs/algorithms.md section 10,
 * "Defocus").
 *
 * The filter (fsf_filter.h) takes per sample a 2D coordinate y and per pixel a shear eta (y
 * units per pixel step along dir[a]) and widths; for defocus:
 *
 *   y        (u, -v): the sample's lens point in unit-lens coordinates (the unit disk; v is
 *            flipped so that both screen axes shear the same way); the grid's half extents are
 *            1, 1: the square hull of the disk
 *   dir      the screen axes +x, +y (one pixel per step)
 *   slope    k = 1 / c lens units per pixel, c = recon_coc_slope_px(depth) the signed film
 *            displacement per unit lens coordinate. A point seen at film x' through lens u'
 *            is seen at film x through u = u' + (x - x') / c (and v = v' - (y - y') / c), so
 *            the neighbour t steps away gives z = y' - k t: eta = -k
 *   range    [k_lo, k_hi] over the footprint's samples, windowed as for shadows
 *            (fsf_slope_window.h), over every object: a defocused object's samples reach its
 *            neighbours whatever surface these show
 *   shear    eta = -(k_lo + k_hi) / 2 on both axes; width sigma = sigma_u / (k_hi - k_lo) / mu
 *            (FSF eq. 4 with the disk's band at the pixel's samples, fsf_lens_sigma_u: 0.386 at
 *            16, falling as n^-1/3; the paper's Gaussian lens had a fixed 1/2), capped by the
 *            window
 *   straddle a range with k_lo < 0 < k_hi holds samples on both sides of the focal plane (k
 *            runs through +-inf there): no shear, sigma = (1/2) / max(|k_lo|, |k_hi|) / mu
 *            (FSF_LENS_STRADDLE_SIGMA_U)
 *   border   sigma <= (distance to the image border) / 2: every tap inside the image
 *   left out sigma < FSF_LENS_SIGMA_MIN_PX or |eta| > 2 (in focus): sigma 0, the pixel keeps
 *            its mean */
#ifndef WEDGE_RECON_FSF_LENS_H
#define WEDGE_RECON_FSF_LENS_H

#include <stdbool.h>

#include "recon/fsf/fsf_filter.h"
#include "recon/gbuffer.h"
#include "recon/sample_store.h"

/* |k| is clamped to this (lens units per pixel; c = 0 in the focal plane): a shear that moves
 * a neighbour one pixel away off the lens many times over. */
#define FSF_LENS_K_MAX 1.0e4f

/* The grid: samples over the disk's square hull [-1, 1]^2; the box profile over [-h, h]^2
 * with h = sqrt(pi) / 2, the square of the unit disk's area (its per-axis variance 0.26 is
 * near the disk's 1/4, so it blurs like the disk to second order). The separable passes
 * cannot weight by the disk itself; the full hull blurs with a square of twice the disk's
 * variance once the shear spreads samples over it. docs/algorithms.md section 10, "Defocus",
 * measures the hull, the equal-variance and the equal-area square. */
#define FSF_LENS_PROFILE_HALF 0.8862269f
FsfGrid fsf_lens_grid(void);

/* A slope range with samples on both sides of the focal plane (k runs through +-inf there):
 * no single shear fits it, so the filter falls back to axis-aligned and the plan gives the
 * pixel extra samples (FSF section 5, fsf_lens_plan.h). One test for both, so that the
 * pixels given samples are exactly the pixels filtered axis-aligned. */
static inline bool fsf_lens_straddles(float k_lo, float k_hi)
{
    return k_lo < 0.0f && k_hi > 0.0f;
}

/* The filter's coordinate of a lens point (unit disk): (u, -v). */
static inline void fsf_lens_coord(float lens_u, float lens_v, float y[2])
{
    y[0] = lens_u;
    y[1] = -lens_v;
}

/* The straddlers' sigma_u (unit lens): the paper's Gaussian lens, A / 2, at every sample count.
 * The band (fsf_lens_sigma_u) holds for their axis-aligned width too in a static scene, but the
 * straddlers of a moving defocused object (FSF does not model motion) rely on this width for the
 * only averaging they get: with the band, all_effects' error rose 10-17% (docs/algorithms.md
 * section 10, "The band of the lens and of the v-plane"). */
#define FSF_LENS_STRADDLE_SIGMA_U 0.5f

/* Narrower filters are left out (the pixel keeps its mean): at sigma 0.5 the first taps
 * weigh exp(-2) = 0.14 of the centre. */
#define FSF_LENS_SIGMA_MIN_PX 0.5f

/* Lens slope of a sample at camera depth depth_cam (+inf: a miss), lens units per pixel. */
float fsf_lens_slope(const ReconCamera *cam, float depth_cam);

/* The store's samples as the filter's input (slots as FsfSamples): y (2 per slot) the lens
 * point (u, -v), v (3 per slot) the sample's radiance scaled so that the pixel's samples
 * average to its composite value4 (fsf_match_pixel); usable: pixels with samples; *nonfinite
 * gains the values written as 0 (fsf_scale_samples). false when the store lacks the lens or
 * radiance field. */
bool fsf_lens_samples(const SampleStore *st, int width, int height, const float *value4, unsigned char *usable,
                      float *y, float *v, int *count, long long *nonfinite);

typedef struct {
    const GBuffer *g;            /* size and camera */
    const SampleStore *store;    /* with SAMPLE_FIELD_DEPTH */
    const unsigned char *usable;
    float mu;                    /* width divisor (> 0) */
    bool black_background;       /* an escaped ray sees black (recon/background.h): a pixel none
                                  * of whose samples hit is left out of the filter */
} FsfLensIn;

/* px and the AOVs k_lo, k_hi (0 where unknown) per pixel. false when out of memory or the
 * store lacks depth. */
bool fsf_lens_params(const FsfLensIn *in, FsfPixel *px, float *k_lo, float *k_hi);

#endif
