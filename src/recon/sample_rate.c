/* The sample allocation of sample_rate.h (docs/algorithms.md 9.14). */
#include "recon/sample_rate.h"

#include <math.h>
#include <stdlib.h>

/* relMSE's weight: (t - r)^2 / (r^2 + 0.01) (core/image metrics, `wedge compare`). */
#define REL_EPS 0.01
/* The variance is averaged over (2 R + 1)^2 pixels: nine samples alone give a variance whose
 * square root is off by a quarter; on combined.pbrt at 16 spp 3 x 3 was 2% better than 1 x 1
 * and 5 x 5 (MAAF). */
#define WINDOW_R 1

void sample_rate_add(float *moments4, float luminance)
{
    if (!isfinite(luminance)) return;
    moments4[0] += 1.0f;
    moments4[1] += luminance;
    moments4[2] += luminance * luminance;
}

float sample_rate_area_px(float var_a_px2, float var_b_px2)
{
    /* per axis sum w^2 = 1 / (2 sqrt(pi) s) for a unit-sum Gaussian of std s (the integral) */
    float a = 4.0f * (float)M_PI * sqrtf(var_a_px2 * var_b_px2);
    return a > 1.0f ? a : 1.0f;
}

bool sample_rate_rel_var(const float *moments4, int width, int height, float *rel_var)
{
    size_t n = (size_t)width * (size_t)height;
    float *v = malloc(n * sizeof(float));
    if (!v) return false;
    for (size_t i = 0; i < n; ++i) {
        const float *a = moments4 + 4 * i;
        double k = a[0], mean = k > 0.0 ? a[1] / k : 0.0;
        /* the unbiased sample variance of one sample */
        double var = k > 1.0 ? (a[2] - a[1] * mean) / (k - 1.0) : 0.0;
        v[i] = (float)(var > 0.0 ? var / (mean * mean + REL_EPS) : 0.0);
    }
    double total = 0.0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double s = 0.0;
            int c = 0;
            for (int yy = y - WINDOW_R; yy <= y + WINDOW_R; ++yy)
                for (int xx = x - WINDOW_R; xx <= x + WINDOW_R; ++xx)
                    if (xx >= 0 && yy >= 0 && xx < width && yy < height) s += v[(size_t)yy * width + xx], ++c;
            rel_var[(size_t)y * width + x] = (float)(s / c);
            total += s / c;
        }
    free(v);
    float mean_all = n ? (float)(total / (double)n) : 0.0f;
    for (size_t i = 0; i < n; ++i) rel_var[i] = mean_all > 0.0f ? rel_var[i] / mean_all : 1.0f;
    return true;
}

float sample_rate_factor(float rel_var, float area, float ref_area)
{
    return sqrtf(fmaxf(rel_var, 0.0f) * ref_area / fmaxf(area, 1.0f));
}

bool sample_rate_factors(const float *moments4, int width, int height, float *area_factor)
{
    size_t n = (size_t)width * (size_t)height;
    float *rel_var = malloc(n * sizeof(float));
    bool ok = rel_var && sample_rate_rel_var(moments4, width, height, rel_var);
    for (size_t i = 0; ok && i < n; ++i) area_factor[i] = sample_rate_factor(rel_var[i], area_factor[i], 1.0f);
    free(rel_var);
    return ok;
}

/* fmin(fmax(x, lo), hi) for lo <= hi, as compares: gcc calls libm for fmin and fmax, which
 * cost the search more than its sums. The same value for every x: NaN gives lo (fmax drops
 * it), and a tie returns a number equal to both */
static inline double clamp_to(double x, double lo, double hi) { return x > lo ? (x < hi ? x : hi) : lo; }

/* sum_i clamp(lambda f_i, lo, hi) */
static double spent(const float *factor, size_t n, double lambda, double lo, double hi)
{
    double s = 0.0;
    for (size_t i = 0; i < n; ++i) s += clamp_to(lambda * factor[i], lo, hi);
    return s;
}

void sample_rate_counts(const float *factor, size_t n, float floor_spp, float cap_spp, double total_spp,
                        float *spp_out)
{
    double lo = floor_spp, hi = fmax(cap_spp, floor_spp), goal = total_spp * (double)n;
    double l0 = 0.0, l1 = 1.0;
    /* grow the bracket until it spends the total (or every factor-carrying pixel is capped) */
    for (int k = 0; k < 200 && spent(factor, n, l1, lo, hi) < goal; ++k) l1 *= 2.0;
    /* to a relative 1e-6 of lambda: the counts within 1e-6 of theirs (~20 halvings; each is a
     * pass over the frame) */
    for (int k = 0; k < 60 && l1 - l0 > 1e-6 * l1; ++k) {
        double mid = 0.5 * (l0 + l1);
        if (spent(factor, n, mid, lo, hi) < goal) l0 = mid;
        else l1 = mid;
    }
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) sum += spp_out[i] = (float)clamp_to(l1 * factor[i], lo, hi);
    /* nothing left to follow the factors: the rest evenly */
    double rest = n ? (goal - sum) / (double)n : 0.0;
    if (rest > 1e-6)
        for (size_t i = 0; i < n; ++i) spp_out[i] += (float)rest;
}
