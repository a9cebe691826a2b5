/* Error metrics of issue 5; definitions and open choices are in image_metrics.h. */
#include "core/image_metrics.h"

#include <math.h>
#include <stdlib.h>

/* Non-finite values enter every metric as 0 (what the writers store for them). */
static double finite_or_zero(float v)
{
    return isfinite(v) ? (double)v : 0.0;
}

static double clamp01(double v)
{
    return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
}

float srgb_encode(float linear)
{
    /* IEC 61966-2-1: linear segment below 0.0031308, a 1/2.4 power above. */
    float a = fabsf(linear);
    float e = a <= 0.0031308f ? 12.92f * a : 1.055f * powf(a, 1.0f / 2.4f) - 0.055f;
    return linear < 0.0f ? -e : e;
}

float srgb_decode(float encoded)
{
    float a = fabsf(encoded);
    float l = a <= 0.04045f ? a / 12.92f : powf((a + 0.055f) / 1.055f, 2.4f);
    return encoded < 0.0f ? -l : l;
}

double metric_relmse(const float *ref_rgb, const float *test_rgb, int width, int height)
{
    size_t n = (size_t)width * (size_t)height * 3;
    if (n == 0) return 0.0;
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double r = finite_or_zero(ref_rgb[i]), t = finite_or_zero(test_rgb[i]);
        sum += (t - r) * (t - r) / (r * r + RELMSE_EPSILON);
    }
    return sum / (double)n;
}

double metric_mse(const float *ref_rgb, const float *test_rgb, int width, int height)
{
    size_t n = (size_t)width * (size_t)height * 3;
    if (n == 0) return 0.0;
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double d = finite_or_zero(test_rgb[i]) - finite_or_zero(ref_rgb[i]);
        sum += d * d;
    }
    return sum / (double)n;
}

double metric_psnr(const float *ref_rgb, const float *test_rgb, int width, int height)
{
    size_t n = (size_t)width * (size_t)height * 3;
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double d = clamp01(finite_or_zero(test_rgb[i])) - clamp01(finite_or_zero(ref_rgb[i]));
        sum += d * d;
    }
    double mse_clamped = n ? sum / (double)n : 0.0;
    double floor_mse = pow(10.0, -PSNR_MAX_DB / 10.0);
    if (mse_clamped < floor_mse) mse_clamped = floor_mse;
    return 10.0 * log10(1.0 / mse_clamped);
}

long metric_nonfinite(const float *test_rgb, int width, int height)
{
    size_t n = (size_t)width * (size_t)height;
    long count = 0;
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(test_rgb[3 * i]) || !isfinite(test_rgb[3 * i + 1]) || !isfinite(test_rgb[3 * i + 2]))
            ++count;
    return count;
}

/* Window side along an axis of length dim: 11, or the largest odd size that fits. */
static int window_side(int dim)
{
    if (dim >= SSIM_WINDOW) return SSIM_WINDOW;
    return dim % 2 ? dim : dim - 1;
}

/* Normalised 1D Gaussian taps (sigma 1.5) for a window of the given odd side. The 2D
 * window of Wang et al. is the outer product, which is what makes the passes separable. */
static void gaussian_taps(int side, double *taps)
{
    int radius = side / 2;
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i) {
        taps[i + radius] = exp(-(double)(i * i) / (2.0 * SSIM_SIGMA * SSIM_SIGMA));
        sum += taps[i + radius];
    }
    for (int i = 0; i < side; ++i) taps[i] /= sum;
}

double metric_ssim_plane(const float *ref, const float *test, int width, int height)
{
    if (width <= 0 || height <= 0) return 1.0;
    int side_x = window_side(width), side_y = window_side(height);
    double taps_x[SSIM_WINDOW], taps_y[SSIM_WINDOW];
    gaussian_taps(side_x, taps_x);
    gaussian_taps(side_y, taps_y);
    int out_w = width - side_x + 1, out_h = height - side_y + 1; /* 'valid' windows */

    /* Horizontal pass: weighted sums of x, y, x^2, y^2, xy for every row and every valid
     * window column; the vertical pass then finishes each window. */
    enum { MOMENTS = 5 };
    double *rows = malloc(sizeof *rows * (size_t)MOMENTS * (size_t)out_w * (size_t)height);
    if (!rows) return NAN;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < out_w; ++x) {
            double m[MOMENTS] = {0};
            for (int k = 0; k < side_x; ++k) {
                size_t i = (size_t)y * (size_t)width + (size_t)(x + k);
                double a = finite_or_zero(ref[i]), b = finite_or_zero(test[i]), w = taps_x[k];
                m[0] += w * a;
                m[1] += w * b;
                m[2] += w * a * a;
                m[3] += w * b * b;
                m[4] += w * a * b;
            }
            for (int q = 0; q < MOMENTS; ++q)
                rows[((size_t)y * (size_t)out_w + (size_t)x) * MOMENTS + (size_t)q] = m[q];
        }

    const double c1 = (SSIM_K1 * 1.0) * (SSIM_K1 * 1.0), c2 = (SSIM_K2 * 1.0) * (SSIM_K2 * 1.0);
    double total = 0.0;
    for (int y = 0; y < out_h; ++y)
        for (int x = 0; x < out_w; ++x) {
            double m[MOMENTS] = {0};
            for (int k = 0; k < side_y; ++k)
                for (int q = 0; q < MOMENTS; ++q)
                    m[q] += taps_y[k] * rows[((size_t)(y + k) * (size_t)out_w + (size_t)x) * MOMENTS + (size_t)q];
            double mu_a = m[0], mu_b = m[1];
            double var_a = m[2] - mu_a * mu_a, var_b = m[3] - mu_b * mu_b, cov = m[4] - mu_a * mu_b;
            /* Wang et al. 2004, eq. 13: luminance x (contrast-structure) comparison. */
            total += ((2.0 * mu_a * mu_b + c1) * (2.0 * cov + c2)) /
                     ((mu_a * mu_a + mu_b * mu_b + c1) * (var_a + var_b + c2));
        }
    free(rows);
    return total / ((double)out_w * (double)out_h);
}

/* Luma of the clamped, sRGB-encoded image (Rec. 709 weights on encoded values). */
static void display_luma(const float *rgb, size_t n, float *luma)
{
    for (size_t i = 0; i < n; ++i) {
        double e[3];
        for (int c = 0; c < 3; ++c) e[c] = srgb_encode((float)clamp01(finite_or_zero(rgb[3 * i + (size_t)c])));
        luma[i] = (float)(0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2]);
    }
}

double metric_ssim(const float *ref_rgb, const float *test_rgb, int width, int height)
{
    if (width <= 0 || height <= 0) return 1.0;
    size_t n = (size_t)width * (size_t)height;
    float *luma = malloc(sizeof *luma * n * 2);
    if (!luma) return NAN;
    display_luma(ref_rgb, n, luma);
    display_luma(test_rgb, n, luma + n);
    double s = metric_ssim_plane(luma, luma + n, width, height);
    free(luma);
    return s;
}

bool image_metrics_compute(const float *ref_rgb, const float *test_rgb, int width, int height,
                           ImageMetrics *out)
{
    out->relmse = metric_relmse(ref_rgb, test_rgb, width, height);
    out->mse = metric_mse(ref_rgb, test_rgb, width, height);
    out->rmse = sqrt(out->mse);
    out->psnr = metric_psnr(ref_rgb, test_rgb, width, height);
    out->ssim = metric_ssim(ref_rgb, test_rgb, width, height);
    out->nonfinite = metric_nonfinite(test_rgb, width, height);
    out->nonfinite_ref = metric_nonfinite(ref_rgb, width, height);
    return !isnan(out->ssim);
}

void relerr_false_colour(double relerr, float rgb_display[3])
{
    /* Colour stops over log10(e) in [-3, 0]: brightness rises with the error so the map
     * also reads in grey. */
    static const float stops[6][3] = {
        {0.0f, 0.0f, 0.0f},   /* e <= 0.001: black */
        {0.15f, 0.1f, 0.6f},  /* blue */
        {0.0f, 0.55f, 0.8f},  /* cyan */
        {0.2f, 0.8f, 0.25f},  /* green */
        {1.0f, 0.9f, 0.1f},   /* yellow */
        {1.0f, 0.15f, 0.05f}, /* e >= 1: red */
    };
    double t = (isfinite(relerr) && relerr > 0.0) ? (log10(relerr) + 3.0) / 3.0 : (relerr > 0.0 ? 1.0 : 0.0);
    t = clamp01(t) * 5.0;
    int k = (int)t;
    if (k >= 5) { /* the top stop exactly, not an interpolation that rounds near it */
        for (int c = 0; c < 3; ++c) rgb_display[c] = stops[5][c];
        return;
    }
    float f = (float)(t - k);
    for (int c = 0; c < 3; ++c) rgb_display[c] = stops[k][c] + f * (stops[k + 1][c] - stops[k][c]);
}

/* Pixel i's share of relMSE: the mean over its channels of (t - r)^2 / (r^2 + 0.01). */
static double pixel_relmse_term(const float *ref_rgb, const float *test_rgb, size_t i)
{
    double sum = 0.0;
    for (int c = 0; c < 3; ++c) {
        double r = finite_or_zero(ref_rgb[3 * i + (size_t)c]), t = finite_or_zero(test_rgb[3 * i + (size_t)c]);
        sum += (t - r) * (t - r) / (r * r + RELMSE_EPSILON);
    }
    return sum / 3.0;
}

void image_relerr_map(const float *ref_rgb, const float *test_rgb, int width, int height,
                      float *relerr, float *rgb_display)
{
    size_t n = (size_t)width * (size_t)height;
    for (size_t i = 0; i < n; ++i) {
        double e = sqrt(pixel_relmse_term(ref_rgb, test_rgb, i));
        if (relerr) relerr[i] = (float)e;
        if (!rgb_display) continue;
        relerr_false_colour(e, rgb_display + 3 * i);
        /* A NaN/Inf pixel of TEST is a bug to spot, not an error level: magenta, a colour
         * the ramp never uses. */
        const float *t = test_rgb + 3 * i;
        if (!isfinite(t[0]) || !isfinite(t[1]) || !isfinite(t[2])) {
            rgb_display[3 * i] = 1.0f;
            rgb_display[3 * i + 1] = 0.0f;
            rgb_display[3 * i + 2] = 1.0f;
        }
    }
}

void image_relmse_by_key(const float *ref_rgb, const float *test_rgb, const float *key, int width, int height,
                         const double *edges, int edge_count, ErrorBin *bins)
{
    for (int b = 0; b <= edge_count; ++b) bins[b] = (ErrorBin){0, 0.0, 0.0};
    size_t n = (size_t)width * (size_t)height;
    for (size_t i = 0; i < n; ++i) {
        double term = pixel_relmse_term(ref_rgb, test_rgb, i);
        /* the first bin whose upper edge lies above the key (few edges: a linear scan) */
        int b = edge_count;
        if (isfinite(key[i]))
            for (int e = 0; e < edge_count; ++e)
                if (key[i] < edges[e]) {
                    b = e;
                    break;
                }
        bins[b].pixels += 1;
        if (isfinite(key[i])) bins[b].key_sum += key[i];
        bins[b].relmse_sum += term;
    }
}
