/* The filter-gain estimate (see filter_gain.h). */
#include "recon/filter_gain.h"

#include <math.h>

/* relMSE's weight of a pixel whose value is m: 1 / (m^2 + 0.01) (core/image_metrics.c) */
#define RELMSE_FLOOR 0.01

/* The unbiased variance of x[0..count). */
static double variance(const double *x, int count)
{
    double mean = 0.0, sq = 0.0;
    for (int i = 0; i < count; ++i) mean += x[i];
    mean /= count;
    for (int i = 0; i < count; ++i) sq += (x[i] - mean) * (x[i] - mean);
    return sq / (count - 1);
}

enum { FILTER_GAIN_MAX_SAMPLES = 256 };

void filter_gain_add_pixel(FilterGainTotals *t, const FilterGainSample *s, int n, bool mixed)
{
    filter_gain_add_pixel_sets(t, s, n, n, mixed, 1.0);
}

bool filter_gain_sample_finite(const FilterGainSample *s)
{
    return isfinite(s->radiance) && isfinite(s->direct_filterable) && isfinite(s->albedo_direct) &&
           isfinite(s->indirect_filterable) && isfinite(s->albedo_indirect);
}

void filter_gain_add_pixel_sets(FilterGainTotals *t, const FilterGainSample *s, int n_a, int n_b, bool mixed,
                                double footprint)
{
    int count = n_a + n_b;
    if (n_a < 2 || n_b < 2 || count > FILTER_GAIN_MAX_SAMPLES) return;
    double sum_l = 0.0, sum_a = 0.0, sum_d = 0.0, sum_b = 0.0, sum_i = 0.0, mean_a = 0.0, mean_b = 0.0;
    for (int i = 0; i < count; ++i) {
        sum_l += s[i].radiance;
        *(i < n_a ? &mean_a : &mean_b) += s[i].radiance;
        sum_d += s[i].direct_filterable, sum_a += s[i].albedo_direct;
        sum_i += s[i].indirect_filterable, sum_b += s[i].albedo_indirect;
    }
    double mean = sum_l / count, w = 1.0 / (mean * mean + RELMSE_FLOOR);
    mean_a /= n_a, mean_b /= n_b;
    /* the pixel's demodulated lights, what an ideal filter gives every sample back */
    double v_direct = sum_a > 0.0 ? sum_d / sum_a : 0.0, v_indirect = sum_b > 0.0 ? sum_i / sum_b : 0.0;
    double x[FILTER_GAIN_MAX_SAMPLES];
    double left[FILTER_GAIN_CONFIGS];
    for (int c = 0; c < FILTER_GAIN_CONFIGS; ++c) {
        bool direct = (c & FILTER_GAIN_DIRECT) && sum_a > 0.0, indirect = (c & FILTER_GAIN_INDIRECT) && sum_b > 0.0;
        for (int i = 0; i < count; ++i) {
            double l = s[i].radiance;
            if (direct) l += s[i].albedo_direct * v_direct - s[i].direct_filterable;
            if (indirect) l += s[i].albedo_indirect * v_indirect - s[i].indirect_filterable;
            x[i] = l;
        }
        left[c] = variance(x, count);
    }
    double f = footprint >= 1.0 ? footprint : 1.0;
    for (int c = 0; c < FILTER_GAIN_CONFIGS; ++c) {
        /* a mixed pixel is passed through; an ideal filter never adds variance (the estimate
         * can, by a few samples' chance) */
        double v = mixed ? left[FILTER_GAIN_NONE] : fmin(left[c], left[FILTER_GAIN_NONE]);
        t->left[c] += w * v;
        t->camera_left[c] += w * v / f;
        t->camera_left_own[c] += w * v / (f * f);
    }
    t->camera_footprint_sum += f;
    t->var_mean_n += w * 0.5 * (mean_a - mean_b) * (mean_a - mean_b);
    if (!mixed) t->var_filterable += w * left[FILTER_GAIN_NONE];
    if (n_a > t->set_spp) t->set_spp = n_a; /* the probe's set size (a pixel that lost samples has fewer) */
    t->pixels++;
    t->pixels_filterable += !mixed;
}

void filter_gain_split_pixel(FilterGainSample *s, const bool *off_first, int count, bool split_direct, bool split_indirect)
{
    for (int k = 0; k < count; ++k) {
        if (off_first[k] || !split_direct) s[k].direct_filterable = 0.0f, s[k].albedo_direct = 0.0f;
        if (off_first[k] || !split_indirect) s[k].indirect_filterable = 0.0f, s[k].albedo_indirect = 0.0f;
    }
}

double filter_gain_share(const FilterGainTotals *t, FilterGainConfig c)
{
    double all = t->left[FILTER_GAIN_NONE];
    if (!(all > 0.0)) return 0.0;
    double s = 1.0 - t->left[c] / all;
    return s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
}

double filter_gain_filterable_share(const FilterGainTotals *t)
{
    double all = t->left[FILTER_GAIN_NONE];
    if (!(all > 0.0)) return 0.0;
    double q = t->var_filterable / all;
    return q < 0.0 ? 0.0 : q > 1.0 ? 1.0 : q;
}

double filter_gain_alpha(const FilterGainTotals *t)
{
    /* var(mean of n) = sigma^2 n^-alpha: alpha = log(sigma^2 / var(mean of n)) / log n */
    if (t->set_spp < 2 || !(t->left[FILTER_GAIN_NONE] > 0.0)) return 1.0;
    if (!(t->var_mean_n > 0.0)) return FILTER_GAIN_ALPHA_MAX; /* the two sets agree exactly */
    double a = log(t->left[FILTER_GAIN_NONE] / t->var_mean_n) / log((double)t->set_spp);
    return a < FILTER_GAIN_ALPHA_MIN ? FILTER_GAIN_ALPHA_MIN : a > FILTER_GAIN_ALPHA_MAX ? FILTER_GAIN_ALPHA_MAX : a;
}

double filter_gain_error_ratio(const FilterGainTotals *t, FilterGainConfig c, double footprint)
{
    return filter_gain_error_ratio_at(t, c, footprint, 1.0);
}

double filter_gain_error_ratio_at(const FilterGainTotals *t, FilterGainConfig c, double footprint,
                                  double neighbour_error)
{
    double s = filter_gain_share(t, c);
    /* the filter's own-pixel part (1 / footprint^2 of what it removes) is left out: under 2% */
    return (1.0 - s) + s * neighbour_error / footprint;
}

double filter_gain_camera_error_ratio(const FilterGainTotals *t, FilterGainConfig c, double footprint)
{
    return filter_gain_camera_error_ratio_at(t, c, footprint, 1.0);
}

double filter_gain_camera_error_ratio_at(const FilterGainTotals *t, FilterGainConfig c, double footprint,
                                         double neighbour_error)
{
    double all = t->left[FILTER_GAIN_NONE];
    if (!(all > 0.0)) return 1.0;
    double kept = t->camera_left[c], removed = t->camera_left[FILTER_GAIN_NONE] - kept;
    if (removed < 0.0) removed = 0.0;
    double own = fmin(t->camera_left_own[c], kept); /* the pixels' own samples' part of kept */
    /* kept + (g - 1) (kept - own): at g = 1 exactly the ratio as measured */
    return (kept + (neighbour_error - 1.0) * (kept - own) + neighbour_error * removed / footprint) / all;
}
