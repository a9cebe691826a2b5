/* Pixel filters by importance sampling (see pixel_filter.h). Definitions follow pbrt-v4
 * (Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed., section 8.8):
 *   box       f = 1 on [-r, r]
 *   triangle  f = max(0, r - |x|)
 *   gaussian  f = max(0, g(x) - g(r)), g the normal density of deviation sigma (shifted so
 *             that f reaches 0 at the radius)
 *   mitchell  f = M(2 x / r), M the Mitchell-Netravali cubic with parameters B, C
 *   sinc      f = sinc(x) sinc(x / tau) on [-r, r] (Lanczos window of tau lobes)
 * each a product of the same 1D function in x and y. Box and triangle are sampled exactly
 * (weight 1); the others from a tabulated |f| (pbrt-v4's FilterSampler resolution). */
#include "render/pixel_filter.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PIXEL_FILTER_RADIUS_MAX 16.0f
#define CELLS_PER_UNIT_RADIUS 32

static const struct {
    const char *name;
    PixelFilterKind kind;
} filter_names[] = {{"box", PIXEL_FILTER_BOX},
                    {"gaussian", PIXEL_FILTER_GAUSSIAN},
                    {"triangle", PIXEL_FILTER_TRIANGLE},
                    {"mitchell", PIXEL_FILTER_MITCHELL},
                    {"sinc", PIXEL_FILTER_SINC}};

bool pixel_filter_kind_from_name(const char *name, PixelFilterKind *kind)
{
    for (size_t i = 0; i < sizeof filter_names / sizeof filter_names[0]; ++i)
        if (name && !strcmp(name, filter_names[i].name)) {
            *kind = filter_names[i].kind;
            return true;
        }
    return false;
}

static double gaussian_density(double x, double sigma)
{
    return exp(-x * x / (2.0 * sigma * sigma)) / sqrt(2.0 * M_PI * sigma * sigma);
}

/* The Mitchell-Netravali cubic on [-2, 2] (1988, eq. 8), as pbrt-v4's Mitchell1D. */
static double mitchell_1d(double x, double b, double c)
{
    x = fabs(x);
    if (x <= 1.0) return ((12 - 9 * b - 6 * c) * x * x * x + (-18 + 12 * b + 6 * c) * x * x + (6 - 2 * b)) / 6.0;
    if (x <= 2.0)
        return ((-b - 6 * c) * x * x * x + (6 * b + 30 * c) * x * x + (-12 * b - 48 * c) * x + (8 * b + 24 * c)) / 6.0;
    return 0.0;
}

static double sinc(double x)
{
    if (fabs(x) < 1e-5) return 1.0 - M_PI * M_PI * x * x / 6.0; /* Taylor: no 0/0 */
    return sin(M_PI * x) / (M_PI * x);
}

/* The 1D factor of the filter along axis a. */
static double filter_1d(const PixelFilter *pf, int a, double x)
{
    double r = pf->radius[a];
    if (fabs(x) > r) return 0.0;
    switch (pf->kind) {
    case PIXEL_FILTER_BOX: return 1.0;
    case PIXEL_FILTER_TRIANGLE: return r - fabs(x);
    case PIXEL_FILTER_GAUSSIAN: return fmax(0.0, gaussian_density(x, pf->sigma) - gaussian_density(r, pf->sigma));
    case PIXEL_FILTER_MITCHELL: return mitchell_1d(2.0 * x / r, pf->b, pf->c);
    case PIXEL_FILTER_SINC: return sinc(x) * sinc(x / pf->tau);
    }
    return 0.0;
}

float pixel_filter_eval(const PixelFilter *pf, float x, float y)
{
    return (float)(filter_1d(pf, 0, x) * filter_1d(pf, 1, y));
}

static bool tabulate_axis(PixelFilter *pf, int a)
{
    PixelFilterAxis *ax = &pf->axis[a];
    double r = pf->radius[a];
    int n = (int)(CELLS_PER_UNIT_RADIUS * r);
    if (n < 2) n = 2;
    ax->cells = n;
    ax->cdf = malloc((size_t)(n + 1) * sizeof *ax->cdf);
    ax->sign = malloc((size_t)n);
    if (!ax->cdf || !ax->sign) return false;
    double sum_abs = 0.0, sum = 0.0;
    double *acc = malloc((size_t)(n + 1) * sizeof *acc);
    if (!acc) return false;
    acc[0] = 0.0;
    for (int i = 0; i < n; ++i) {
        double x = -r + 2.0 * r * (i + 0.5) / n;
        double f = filter_1d(pf, a, x);
        ax->sign[i] = f < 0.0 ? -1 : 1;
        sum_abs += fabs(f);
        sum += f;
        acc[i + 1] = sum_abs;
    }
    bool ok = sum_abs > 0.0 && sum > 0.0;
    for (int i = 0; i <= n && ok; ++i) ax->cdf[i] = (float)(acc[i] / sum_abs);
    if (ok) ax->cdf[n] = 1.0f;
    ax->abs_over_sum = ok ? (float)(sum_abs / sum) : 0.0f;
    free(acc);
    return ok;
}

bool pixel_filter_init(PixelFilter *pf, const char *type, const ParamSet *params, SrcLoc loc, Diag *err)
{
    memset(pf, 0, sizeof *pf);
    if (!pixel_filter_kind_from_name(type, &pf->kind)) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "unknown pixel filter '%s' (box, gaussian, triangle, mitchell or sinc)",
                 type ? type : "");
        return false;
    }
    /* pbrt-v4's defaults (filters.cpp, Create functions) */
    float r_def = 0.5f;
    if (pf->kind == PIXEL_FILTER_GAUSSIAN) r_def = 1.5f;
    if (pf->kind == PIXEL_FILTER_TRIANGLE || pf->kind == PIXEL_FILTER_MITCHELL) r_def = 2.0f;
    if (pf->kind == PIXEL_FILTER_SINC) r_def = 4.0f;
    pf->radius[0] = params ? params_float(params, "xradius", r_def) : r_def;
    pf->radius[1] = params ? params_float(params, "yradius", r_def) : r_def;
    pf->sigma = params ? params_float(params, "sigma", 0.5f) : 0.5f;
    pf->b = params ? params_float(params, "B", 1.0f / 3.0f) : 1.0f / 3.0f;
    pf->c = params ? params_float(params, "C", 1.0f / 3.0f) : 1.0f / 3.0f;
    pf->tau = params ? params_float(params, "tau", 3.0f) : 3.0f;
    for (int a = 0; a < 2; ++a)
        if (!(pf->radius[a] > 0.0f && pf->radius[a] <= PIXEL_FILTER_RADIUS_MAX)) {
            diag_set(err, WEDGE_EXIT_INPUT, loc, "pixel filter '%s': %cradius must be in (0, %g] pixels, got %g", type,
                     a ? 'y' : 'x', (double)PIXEL_FILTER_RADIUS_MAX, (double)pf->radius[a]);
            return false;
        }
    if (pf->kind == PIXEL_FILTER_GAUSSIAN && !(pf->sigma > 0.0f)) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "pixel filter 'gaussian': sigma must be positive, got %g", (double)pf->sigma);
        return false;
    }
    if (pf->kind == PIXEL_FILTER_SINC && !(pf->tau > 0.0f)) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "pixel filter 'sinc': tau must be positive, got %g", (double)pf->tau);
        return false;
    }
    pf->unit_box = pf->kind == PIXEL_FILTER_BOX && pf->radius[0] == 0.5f && pf->radius[1] == 0.5f;
    if (pf->kind == PIXEL_FILTER_GAUSSIAN || pf->kind == PIXEL_FILTER_MITCHELL || pf->kind == PIXEL_FILTER_SINC) {
        for (int a = 0; a < 2; ++a)
            if (!tabulate_axis(pf, a)) {
                pixel_filter_free(pf);
                diag_set(err, WEDGE_EXIT_INPUT, loc,
                         "pixel filter '%s': its integral over the radius is not positive (parameters out of range?)", type);
                return false;
            }
    }
    return true;
}

void pixel_filter_free(PixelFilter *pf)
{
    for (int a = 0; a < 2; ++a) {
        free(pf->axis[a].cdf);
        free(pf->axis[a].sign);
        pf->axis[a].cdf = NULL;
        pf->axis[a].sign = NULL;
    }
}

/* Offset from the pixel centre along axis a for u in [0, 1); *w *= the axis weight. */
static float sample_axis(const PixelFilter *pf, int a, float u, float *w)
{
    float r = pf->radius[a];
    switch (pf->kind) {
    case PIXEL_FILTER_BOX: return (2.0f * u - 1.0f) * r;
    case PIXEL_FILTER_TRIANGLE:
        /* inverse CDF of the tent: each half holds half the mass */
        if (u < 0.5f) return -r + r * sqrtf(2.0f * u);
        return r - r * sqrtf(2.0f - 2.0f * u);
    default: break;
    }
    const PixelFilterAxis *ax = &pf->axis[a];
    /* The first cell i in [0, cells - 1) with cdf[i + 1] > u, else cells - 1 (cdf does not
     * decrease). The answer stays in [lo, lo + len - 1]; each step halves len whatever the
     * comparison says, so the loop's branch depends on the table only and the comparison
     * becomes a conditional move (u is random: as a branch it mispredicted about half the
     * time, twice per sample with the default Gaussian). For a non-decreasing table this
     * is the partition point a plain bisection finds, so the same cell results. */
    int lo = 0;
    for (int len = ax->cells; len > 1;) {
        int half = len / 2;
        lo = ax->cdf[lo + half] > u ? lo : lo + half;
        len -= half;
    }
    float width = ax->cdf[lo + 1] - ax->cdf[lo];
    float t = width > 0.0f ? (u - ax->cdf[lo]) / width : 0.5f;
    t = clamp01f(t);
    *w *= (float)ax->sign[lo] * ax->abs_over_sum;
    return -r + 2.0f * r * ((float)lo + t) / (float)ax->cells;
}

vec2 pixel_filter_sample_shaped(const PixelFilter *pf, vec2 u, float *weight)
{
    float w = 1.0f;
    float dx = sample_axis(pf, 0, u.x, &w), dy = sample_axis(pf, 1, u.y, &w);
    *weight = w;
    return v2(0.5f + dx, 0.5f + dy);
}
