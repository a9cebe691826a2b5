/* Indirect-light MAAF: the direction-factor tables and the v-plane coordinate (see
 * maaf_indirect.h; derivation in docs/algorithms.md 9.12). */
#include "recon/maaf/maaf_indirect.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The transfer up to its constant 1/pi (which cancels in c_pq's ratio). */
static double transfer(double v1, double v2)
{
    double r = 1.0 + v1 * v1 + v2 * v2;
    return 1.0 / (r * r);
}

float maaf_indirect_contact_alpha(float spp)
{
    float n = spp >= 1.0f ? spp : 1.0f; /* also NaN */
    /* the fourth root: the width where bias^2 (linear in the width at a kink) meets the variance
     * (over the width's area), docs/algorithms.md 9.26 */
    return MAAF_INDIRECT_CONTACT_ALPHA * sqrtf(sqrtf(n / MAAF_INDIRECT_CONTACT_BASE_SPP));
}

void maaf_indirect_heights(float zmin_world, float zmax_world, float omega_v_max, int pairs, float pixel_world, float spp,
                           float *h_min, float *h_max)
{
    int n = pairs < 1 ? 1 : pairs > MAAF_PAIRS_MAX ? MAAF_PAIRS_MAX : pairs;
    /* AAF-GI eq. 15's pixel term, Omega_x <= alpha / d, on the central band's Omega_x */
    float contact = omega_v_max * pixel_world / ((float)(2 * n - 1) * maaf_indirect_contact_alpha(spp));
    *h_min = zmin_world >= contact ? zmin_world : contact; /* also NaN */
    *h_max = zmax_world >= *h_min ? zmax_world : *h_min;
}

void maaf_direction_means(float kappa, int pairs, MaafLens *t)
{
    memset(t, 0, sizeof *t);
    int n = pairs < 1 ? 1 : pairs > MAAF_PAIRS_MAX ? MAAF_PAIRS_MAX : pairs;
    t->pairs = n;
    t->comps = maaf_component_count(n);
    t->omega_u_max = kappa * MAAF_INDIRECT_OMEGA_V;
    for (int c = 0; c < t->comps; ++c) t->mean[c] = maaf_direction_mean(n, c); /* an expf per sample otherwise */
}

bool maaf_direction_design(float kappa, int pairs, MaafLens *t)
{
    maaf_direction_means(kappa, pairs, t);
    maaf_lens_flips(t);
    int n = t->pairs, bands = 2 * n - 1;
    enum { T = MAAF_LENS_TABLE };
    double s = maaf_lens_band_std(t), std = 1.0 / s, node = 2.0 * MAAF_INDIRECT_V_HALF / (T - 1);
    /* The convolution's grid: a whole number m of steps per table step (so every table node
     * is a grid node and the kernel is one array of offsets), fine enough for the Gaussian
     * (std / 8) and for the fastest band's oscillation (period pi std / (N - 1): 12 steps);
     * the kernel is cut at 5 stds (its tail there is 4e-6 of its peak). */
    double fine = fmin(std / 8.0, M_PI * std / (12.0 * (n > 1 ? n - 1 : 1)));
    int m = (int)ceil(node / fine);
    double de = node / m;
    int r = (int)ceil(5.0 * std / de), M = (T - 1) * m + 1 + 2 * r; /* grid j: v = -V - r de + j de */
    double v0 = -MAAF_INDIRECT_V_HALF - r * de;
    t->table = calloc((size_t)t->comps * MAAF_LENS_ROWS * MAAF_LENS_ROWS * 2, sizeof(float));
    double *kre = malloc((size_t)bands * (2 * r + 1) * sizeof(double)), *kim = malloc((size_t)bands * (2 * r + 1) * sizeof(double));
    double *tr = malloc((size_t)M * M * sizeof(double));
    double *are = malloc((size_t)n * M * T * sizeof(double)), *aim = malloc((size_t)n * M * T * sizeof(double)); /* q >= 0 */
    bool ok = t->table && kre && kim && tr && are && aim;
    /* kernel of band q at offset o steps: exp(j C^q o de) g(o de; s) de (the integration weight
     * included; the ends are 5 stds out, so the plain sum is the trapezoid rule) */
    for (int q = -(n - 1); ok && q < n; ++q)
        for (int o = -r; o <= r; ++o) {
            double x = o * de, g = s * 0.3989422804014327 * exp(-0.5 * s * s * x * x) * de;
            kre[(size_t)(q + n - 1) * (2 * r + 1) + (o + r)] = g * cos(maaf_lens_band_centre(t, q) * x);
            kim[(size_t)(q + n - 1) * (2 * r + 1) + (o + r)] = g * sin(maaf_lens_band_centre(t, q) * x);
        }
    for (int a = 0; ok && a < M; ++a)
        for (int b = 0; b < M; ++b) tr[(size_t)a * M + b] = transfer(v0 + a * de, v0 + b * de);
    /* pass A, along v2: A_q(v1 = grid a, v2 = node i2) = sum_o k_q(o) T(v1, node i2 + o), for
     * q >= 0 only (k_{-q} = conj k_q and T is real: A_{-q} = conj A_q). The loops run over i2
     * innermost, so that they vectorise. */
    for (int q = 0; ok && q < n; ++q) {
        const double *kr = kre + (size_t)(q + n - 1) * (2 * r + 1) + r, *ki = kim + (size_t)(q + n - 1) * (2 * r + 1) + r;
        for (int a = 0; a < M; ++a) {
            double *sr = are + ((size_t)q * M + a) * T, *si = aim + ((size_t)q * M + a) * T;
            for (int i2 = 0; i2 < T; ++i2) sr[i2] = si[i2] = 0.0;
            const double *row = tr + (size_t)a * M + r; /* grid index of node 0 */
            for (int o = -r; o <= r; ++o)
                for (int i2 = 0; i2 < T; ++i2) {
                    double x = row[(size_t)i2 * m + o];
                    sr[i2] += kr[o] * x;
                    si[i2] += ki[o] * x;
                }
        }
    }
    /* pass B, along v1, per component, over the stored quadrant (maaf_lens_factors folds the
     * rest onto it: T is even in v1 and in v2, and each band's kernel at -t is the conjugate of
     * that at t) */
    double *acc_re = malloc(T * sizeof(double)), *acc_im = malloc(T * sizeof(double));
    ok = ok && acc_re && acc_im;
    int c = 0;
    for (int p = 0; ok && p < n; ++p)
        for (int q = -(n - 1); q < n; ++q) {
            if (p == 0 && q < 0) continue;
            const double *kr = kre + (size_t)(p + n - 1) * (2 * r + 1) + r, *ki = kim + (size_t)(p + n - 1) * (2 * r + 1) + r;
            const double *ar = are + (size_t)abs(q) * M * T, *ai = aim + (size_t)abs(q) * M * T;
            double conj = q < 0 ? -1.0 : 1.0;
            for (int i1 = 0; i1 < MAAF_LENS_ROWS; ++i1) {
                for (int i2 = 0; i2 < T; ++i2) acc_re[i2] = acc_im[i2] = 0.0;
                for (int o = -r; o <= r; ++o) {
                    const double *xr = ar + ((size_t)i1 * m + r + o) * T, *xi = ai + ((size_t)i1 * m + r + o) * T;
                    double wr = kr[o], wi = ki[o];
                    for (int i2 = 0; i2 < T; ++i2) {
                        double yi = conj * xi[i2];
                        acc_re[i2] += wr * xr[i2] - wi * yi;
                        acc_im[i2] += wr * yi + wi * xr[i2];
                    }
                }
                for (int i2 = 0; i2 < T; ++i2) {
                    double inv = 1.0 / transfer(-MAAF_INDIRECT_V_HALF + i1 * node, -MAAF_INDIRECT_V_HALF + i2 * node);
                    maaf_lens_store(t, c, i1, i2, (float)(acc_re[i2] * inv), (float)(acc_im[i2] * inv));
                }
            }
            ++c;
        }
    free(acc_re), free(acc_im);
    free(kre), free(kim), free(tr), free(are), free(aim);
    if (!ok) maaf_lens_free(t);
    return ok;
}

void maaf_direction_factor(const MaafLens *t, int c, const float v[2], float out[2])
{
    maaf_lens_factor(t, c, v[0] / MAAF_INDIRECT_V_HALF, v[1] / MAAF_INDIRECT_V_HALF, out);
}

float maaf_direction_mean(int pairs, int c)
{
    int k = 0;
    for (int p = 0; p < pairs; ++p)
        for (int q = -(pairs - 1); q < pairs; ++q) {
            if (p == 0 && q < 0) continue;
            if (k++ == c) return expf(-2.0f * (float)(p * p + q * q)); /* C / sv = 2p per axis */
        }
    return 0.0f;
}

bool maaf_direction_coord(const float t1[3], const float t2[3], const float n[3], const float d[3], float v[2])
{
    float dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    if (!(dn > 1.0e-6f)) return false;
    v[0] = (d[0] * t1[0] + d[1] * t1[1] + d[2] * t1[2]) / dn;
    v[1] = (d[0] * t2[0] + d[1] * t2[1] + d[2] * t2[2]) / dn;
    return isfinite(v[0]) && isfinite(v[1]);
}

void maaf_direction_accumulate(const MaafLens *t, const float t1[3], const float t2[3], const float n[3],
                               const float *d, const float f4[4], float *ysum)
{
    float v[2];
    if (d && maaf_direction_coord(t1, t2, n, d, v)) {
        /* the table's cell reads every component at once (lens_cell clamps beyond the table) */
        maaf_lens_accumulate(t, v[0] / MAAF_INDIRECT_V_HALF, v[1] / MAAF_INDIRECT_V_HALF, f4, ysum);
        return;
    }
    for (int c = 0; c < t->comps; ++c) {
        float w = t->mean[c], *yr = ysum + 8 * c;
        for (int ch = 0; ch < 4; ++ch) yr[ch] += w * f4[ch];
    }
}
