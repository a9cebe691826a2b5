/* The filter-gain estimate: how much of a frame's Monte Carlo error the shading filters can
 * remove, from a few pixels' samples (docs/algorithms.md, "auto's fallback to Monte Carlo").
 *
 * A shading filter replaces a pixel's light (direct light / diffuse albedo for soft shadows,
 * indirect light / albedo for the bounce) by a smooth value shared with its neighbours; it
 * keeps the albedo and everything else each sample saw. So what it can remove from a sample's
 * radiance L_i is the part that varies with the light sample, and what it cannot is the part
 * that varies over the pixel's area (texture, silhouettes, unfiltered light). Per pixel, with
 * the pixel's demodulated light v = sum(D_i) / sum(a_i) (the pipeline's demodulation, a ratio
 * of sums):
 *
 *   L_i(ideal filter) = L_i - D_i + a_i v        (direct; the same with I_i, b_i for indirect)
 *
 * and the variances of L_i and of L_i(ideal filter) over the pixel's samples are the per-sample
 * Monte Carlo variance and what an ideal filter leaves. Pixels the filters do not touch (mixed:
 * the G-buffer's rule) keep all of theirs. Each pixel's variance is weighted as relMSE weights
 * its error, 1 / (mean^2 + 0.01) (core/image_metrics.c).
 *
 * The totals also carry the frame's convergence rate under the renderer's sampler: two
 * independent sets of n samples per pixel give the variance of an n-sample mean,
 * E[(mean_A - mean_B)^2] / 2, against the per-sample variance: n^-alpha. */
#ifndef WEDGE_RECON_FILTER_GAIN_H
#define WEDGE_RECON_FILTER_GAIN_H

#include <stdbool.h>

/* The filtered configurations a frame's shading filters can form. */
typedef enum {
    FILTER_GAIN_NONE = 0,     /* neither shading effect filtered */
    FILTER_GAIN_DIRECT = 1,   /* soft shadows (direct light) filtered */
    FILTER_GAIN_INDIRECT = 2, /* indirect light filtered */
    FILTER_GAIN_BOTH = 3,
    FILTER_GAIN_CONFIGS = 4
} FilterGainConfig;

/* One sample as the estimate reads it (luminance). */
typedef struct {
    float radiance;          /* L */
    float direct_filterable; /* D: the direct light a soft-shadow filter demodulates and blurs
                              * (direct less its glossy and unfiltered parts) */
    float albedo_direct;     /* a: the diffuse albedo D is demodulated by */
    float indirect_filterable; /* I: the indirect light an indirect filter blurs */
    float albedo_indirect;   /* b: the albedo I is demodulated by */
} FilterGainSample;

typedef struct {
    /* sum over pixels of w * per-sample variance left with each configuration's ideal filter
     * (left[FILTER_GAIN_NONE]: Monte Carlo's own) */
    double left[FILTER_GAIN_CONFIGS];
    double var_mean_n;   /* sum of w * (mean_A - mean_B)^2 / 2: an n-sample mean's variance */
    double var_filterable; /* sum of w * per-sample variance over the pixels not mixed */
    int set_spp;         /* n, the samples of each of the two sets */
    int pixels;          /* pixels added */
    int pixels_filterable; /* of those, not mixed */
    /* With the camera filters kept (auto_fallback.h): sum of w * left(c) / F, each pixel's
     * variance left by configuration c's ideal shading filter over the camera filters'
     * footprint F there (camera_gain.h; the camera filters take mixed pixels too, which keep
     * left(none)); F = 1 where nothing is blurred. */
    double camera_left[FILTER_GAIN_CONFIGS];
    /* sum of w * left(c) / F^2: the part of camera_left[c] a pixel's own samples carry (of the
     * F samples' worth a camera filter averages, one is the pixel's; the rest are its
     * neighbours', whose error does not fall as the pixel's stratified samples' does:
     * filter_gain_camera_error_ratio_at) */
    double camera_left_own[FILTER_GAIN_CONFIGS];
    double camera_footprint_sum; /* sum of F over the pixels added (the report's mean) */
} FilterGainTotals;

/* Adds one pixel: n samples of set A then n of set B (n >= 2), mixed: whether the filters leave
 * it alone. Its camera footprint is 1. */
void filter_gain_add_pixel(FilterGainTotals *t, const FilterGainSample *samples, int n, bool mixed);

/* The same for n_a samples of set A then n_b of set B (each >= 2: a pixel that lost samples to
 * non-finite values; the two sets' difference is then read as an n_a-sample mean's, a small
 * bias on one pixel) and a camera footprint F >= 1 (camera_gain.h). */
void filter_gain_add_pixel_sets(FilterGainTotals *t, const FilterGainSample *samples, int n_a, int n_b, bool mixed,
                                double footprint);

/* Whether every value of a sample is finite: the probe skips the others (and counts them). */
bool filter_gain_sample_finite(const FilterGainSample *s);

/* A split pixel (docs/algorithms.md 4.6: a mixed pixel whose first surface the filters take)
 * made ready for filter_gain_add_pixel (as not mixed): a light the frame splits is kept only
 * on the samples of the first surface (off_first[i] false), the other samples keeping their
 * radiance as light no filter sees; a light it does not split is taken off every sample, as
 * in any mixed pixel. count samples. */
void filter_gain_split_pixel(FilterGainSample *samples, const bool *off_first, int count, bool split_direct,
                             bool split_indirect);

/* The share of Monte Carlo's weighted variance an ideal filter of configuration c removes
 * (0 when there is no variance). */
double filter_gain_share(const FilterGainTotals *t, FilterGainConfig c);

/* The share of Monte Carlo's weighted variance in pixels the shading filters may touch (not
 * mixed): with a camera filter beside them, whose lens or shutter filtering removes what
 * varies over the lens in those pixels, what the shading filters can reach there (0 when
 * there is no variance). */
double filter_gain_filterable_share(const FilterGainTotals *t);

/* The convergence exponent alpha of Monte Carlo's error (variance of the mean ~ N^-alpha),
 * measured between 1 and n samples, clamped to [FILTER_GAIN_ALPHA_MIN, FILTER_GAIN_ALPHA_MAX];
 * 1 (independent samples) when nothing was measured. */
#define FILTER_GAIN_ALPHA_MIN 1.0
#define FILTER_GAIN_ALPHA_MAX 2.0
double filter_gain_alpha(const FilterGainTotals *t);

/* The filtered frame's error over Monte Carlo's at equal samples for configuration c, when the
 * filter leaves 1 / footprint of the variance it can remove (footprint: the independent
 * samples its kernel averages, relative to one pixel's): (1 - s) + s / footprint. */
double filter_gain_error_ratio(const FilterGainTotals *t, FilterGainConfig c, double footprint);

/* The same at a sample count where the samples a filter borrows from neighbouring pixels have
 * neighbour_error times the error relative to Monte Carlo's they had where the footprint was
 * measured (auto_fallback.h, "the error ratio's growth with N"): (1 - s) + s neighbour_error /
 * footprint. neighbour_error 1 gives filter_gain_error_ratio. */
double filter_gain_error_ratio_at(const FilterGainTotals *t, FilterGainConfig c, double footprint,
                                  double neighbour_error);

/* The same with the camera filters kept: per pixel, the variance configuration c's ideal
 * shading filter leaves, plus 1 / footprint of what it removes, over that pixel's camera
 * footprint F; summed with relMSE's weights over Monte Carlo's:
 *   (sum w [left(c) + (left(none) - left(c)) / footprint] / F) / sum w sigma^2.
 * 1 when there is no variance. */
double filter_gain_camera_error_ratio(const FilterGainTotals *t, FilterGainConfig c, double footprint);

/* The same with neighbour_error as in filter_gain_error_ratio_at: of a pixel's variance left
 * by c over F, its own samples' part (left(c) / F^2) stays and the neighbours' part (left(c)
 * (F - 1) / F^2) is multiplied by neighbour_error; what the shading filter removes is its
 * neighbours' and multiplied by it too:
 *   (sum w [left(c) (1 + (F - 1) g) / F^2 + g (left(none) - left(c)) / (footprint F)]) / sum w sigma^2,
 * g = neighbour_error. g = 1 gives filter_gain_camera_error_ratio. */
double filter_gain_camera_error_ratio_at(const FilterGainTotals *t, FilterGainConfig c, double footprint,
                                         double neighbour_error);

#endif
