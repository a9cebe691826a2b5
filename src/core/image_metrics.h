/* Error metrics of a test image against a reference (issue 5, "wedge compare").
 *
 * Images are interleaved linear rgb floats, width * height pixels. The definitions are
 * exact because other tools and tests depend on them:
 *   relMSE  = mean over pixels and the 3 channels of (t - r)^2 / (r^2 + 0.01)
 *   MSE     = mean over pixels and channels of (t - r)^2;  RMSE = sqrt(MSE)
 *   PSNR    = 10 log10(1 / MSE'), MSE' the MSE of both images clamped to [0, 1]
 *   SSIM    = mean SSIM (Wang et al. 2004) of the luma Y' = 0.2126 R' + 0.7152 G' + 0.0722 B'
 *             of the clamped, sRGB-encoded images (R' = srgb_encode(clamp(R))), data range 1
 *   nonfinite = number of TEST pixels with at least one NaN or infinite channel;
 *   nonfinite_ref the same for REF (a reference with NaN is no reference).
 * Choices the issue leaves open (documented here, tested in tests/core/test_metrics.c):
 *   - Non-finite values (either image) count as 0 in every other metric, which is what our
 *     writers store for them; nonfinite tells that it happened.
 *   - Identical images have MSE' = 0: PSNR is capped at 100 dB (MSE' floored at 1e-10) so
 *     that no infinity reaches any output.
 *   - SSIM border: only windows lying fully inside the image are evaluated and averaged
 *     ('valid' mode of Wang et al.'s reference code), so a W x H image has
 *     (W - 10) x (H - 10) windows. An image narrower (or lower) than 11 pixels uses, along
 *     that axis, the largest odd window that fits (same sigma, weights renormalised). */
#ifndef WEDGE_CORE_IMAGE_METRICS_H
#define WEDGE_CORE_IMAGE_METRICS_H

#include <stdbool.h>

typedef struct {
    double relmse, mse, rmse, psnr, ssim;
    long nonfinite, nonfinite_ref;
} ImageMetrics;

/* SSIM parameters (Wang et al. 2004, section III-C). */
#define SSIM_WINDOW 11
#define SSIM_SIGMA 1.5
#define SSIM_K1 0.01
#define SSIM_K2 0.03
/* relMSE regulariser: keeps dark reference pixels from dominating. */
#define RELMSE_EPSILON 0.01
#define PSNR_MAX_DB 100.0

/* All metrics at once. False only when memory for SSIM cannot be allocated. */
bool image_metrics_compute(const float *ref_rgb, const float *test_rgb, int width, int height,
                           ImageMetrics *out);

double metric_relmse(const float *ref_rgb, const float *test_rgb, int width, int height);
double metric_mse(const float *ref_rgb, const float *test_rgb, int width, int height);
double metric_psnr(const float *ref_rgb, const float *test_rgb, int width, int height);
long metric_nonfinite(const float *test_rgb, int width, int height);
/* Mean SSIM of the two images as defined above; NaN if out of memory. */
double metric_ssim(const float *ref_rgb, const float *test_rgb, int width, int height);
/* Mean SSIM of two single-channel images already in [0,1] (the luma step skipped). */
double metric_ssim_plane(const float *ref, const float *test, int width, int height);

/* Plain sRGB transfer functions (IEC 61966-2-1), per channel, defined on all reals
 * (negative values mirror, so callers clamp first when they need [0,1]). */
float srgb_encode(float linear);
float srgb_decode(float encoded);

/* Per-pixel relative error e = sqrt(mean over channels of (t - r)^2 / (r^2 + 0.01)), so
 * the mean of e^2 over the image is relMSE; and its false colour: log10(e) from -3
 * (black) to 0 (red) through blue, cyan, green and yellow; e >= 1 is red; pixels where
 * TEST is non-finite are magenta (1,0,1) (their e counts the value as 0). Either output
 * may be NULL. rgb_display holds display-encoded colours in [0,1]. */
void image_relerr_map(const float *ref_rgb, const float *test_rgb, int width, int height,
                      float *relerr, float *rgb_display);
void relerr_false_colour(double relerr, float rgb_display[3]);

/* Where the error comes from: relMSE split by the value of a per-pixel key (a filter width,
 * an spp count, ...). Bin b holds the pixels with edges[b-1] <= key < edges[b] (edges[-1] =
 * -inf, edges[edge_count] = +inf), so there are edge_count + 1 bins; edges must increase.
 * A non-finite key goes to the last bin (and counts as 0 in its sum). Per bin: the number of
 * pixels, the sum of the keys, and the sum of the pixels' relMSE terms (mean over channels of
 * (t - r)^2 / (r^2 + 0.01)), so the bins' sums add up to relMSE * width * height. */
typedef struct {
    long pixels;
    double key_sum;      /* sum of the (finite) keys, for the mean */
    double relmse_sum;   /* sum of the per-pixel relMSE terms */
} ErrorBin;

void image_relmse_by_key(const float *ref_rgb, const float *test_rgb, const float *key, int width, int height,
                         const double *edges, int edge_count, ErrorBin *bins);

#endif
