/* Soft-shadow MAAF: light frames, the sums of eq. 20, per-pixel filters (see maaf_shadow.h). */
#include "recon/maaf/maaf_shadow.h"

#include "recon/maaf/maaf_band_cdf.h"

#include <math.h>
#include <string.h>

#define INV_SQRT_2PI 0.39894228f

/* c_p(y) along axis a for the bands p < pairs: the window [lo - y, hi - y] in units of the
 * y-Gaussian's primal std (1 / sy) and Phi_p at its two ends (maaf_band_cdf.h). y outside the
 * extent is its nearest end, as the per-light table of 129 entries had it (2026-12-01). The two
 * ends' places in the table are found once for all the bands, and the central band, whose
 * table is real (its imaginary parts all +0), reads only the real parts: the same floats. */
static inline void light_factors(const MaafBandCdf *table, const MaafLight *l, int a, float y, int pairs, float c[][2])
{
    if (!(y > l->lo[a])) y = l->lo[a]; /* NaN too */
    if (y > l->hi[a]) y = l->hi[a];
    MaafBandCdfAt hi = maaf_band_cdf_at(l->sy * (l->hi[a] - y)), lo = maaf_band_cdf_at(l->sy * (l->lo[a] - y));
    c[0][0] = maaf_band_cdf_lerp_re(table, 0, hi) - maaf_band_cdf_lerp_re(table, 0, lo);
    c[0][1] = 0.0f;
    for (int p = 1; p < pairs; ++p) {
        float up[2], down[2];
        maaf_band_cdf_lerp(table, p, hi, up);
        maaf_band_cdf_lerp(table, p, lo, down);
        c[p][0] = up[0] - down[0];
        c[p][1] = up[1] - down[1];
    }
}

/* The light's mean c_p per axis: the expectation over its samples by the trapezoid rule on
 * MAAF_MEAN_NODES nodes over its extent. A static light's samples are uniform on it; a swept
 * light's density along an axis is the fraction of the shutter during which it covers that
 * coordinate (the share of its poses whose extent holds it; a light sliding along t1 gives a
 * trapezoid). */
static void light_means(int pairs, MaafLight *l)
{
    for (int a = 0; a < 2; ++a) {
        double sum[MAAF_PAIRS_MAX][2] = {{0.0}}, total = 0.0;
        for (int e = 0; e < MAAF_MEAN_NODES; ++e) {
            double y = l->lo[a] + (l->hi[a] - l->lo[a]) * e / (MAAF_MEAN_NODES - 1.0);
            int covered = 1;
            if (l->sweep_nodes > 0 && l->sweep) {
                covered = 0;
                for (int k = 0; k < l->sweep_nodes; ++k) covered += y >= l->sweep->lo[a][k] && y <= l->sweep->hi[a][k];
            }
            double density = (e == 0 || e == MAAF_MEAN_NODES - 1 ? 0.5 : 1.0) * covered;
            if (density == 0.0) continue;
            float c[MAAF_PAIRS_MAX][2];
            light_factors(maaf_band_cdf(), l, a, (float)y, pairs, c);
            total += density;
            for (int p = 0; p < pairs; ++p)
                for (int k = 0; k < 2; ++k) sum[p][k] += density * c[p][k];
        }
        for (int p = 0; p < pairs; ++p)
            for (int k = 0; k < 2; ++k) l->mean[a][p][k] = total > 0.0 ? (float)(sum[p][k] / total) : 0.0f;
    }
}

void maaf_light_design(float sigma_light_world, int pairs, MaafLight *l)
{
    float wy = sigma_light_world > 0.0f && isfinite(sigma_light_world) ? 2.0f / sigma_light_world : 0.0f;
    l->omega_y_max = wy;
    l->sy = wy / (2.0f * (float)pairs - 1.0f); /* eq. 6; C_y^p = 2p sy is in the universal table */
    memset(l->mean, 0, sizeof l->mean);
    if (!(wy > 0.0f)) return;
    light_means(pairs, l);
}

bool maaf_light_design_copy(const MaafLight *from, float sigma_light_world, MaafLight *l)
{
    float wy = sigma_light_world > 0.0f && isfinite(sigma_light_world) ? 2.0f / sigma_light_world : 0.0f;
    if (!(wy > 0.0f) || from->omega_y_max != wy || from->lo[0] != l->lo[0] || from->hi[0] != l->hi[0] ||
        from->lo[1] != l->lo[1] || from->hi[1] != l->hi[1] || from->sweep_nodes != l->sweep_nodes ||
        (l->sweep_nodes > 0 && (!from->sweep || !l->sweep || memcmp(from->sweep, l->sweep, sizeof *l->sweep))))
        return false;
    l->omega_y_max = wy;
    l->sy = from->sy;
    memcpy(l->mean, from->mean, sizeof l->mean);
    return true;
}

void maaf_light_axes(const MaafLight *l, const float p[3], float t1[3], float t2[3])
{
    if (l->t1[0] != 0.0f || l->t1[1] != 0.0f || l->t1[2] != 0.0f) {
        memcpy(t1, l->t1, 3 * sizeof(float));
        memcpy(t2, l->t2, 3 * sizeof(float));
        return;
    }
    float d[3] = {l->center[0] - p[0], l->center[1] - p[1], l->center[2] - p[2]};
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    float n[3] = {0.0f, 0.0f, 1.0f};
    if (len > 0.0f)
        for (int k = 0; k < 3; ++k) n[k] = d[k] / len;
    maaf_basis(n, t1, t2);
}

void maaf_light_factor(const MaafLight *l, int axis, int p, float y, float c[2])
{
    float all[MAAF_PAIRS_MAX][2];
    light_factors(maaf_band_cdf(), l, axis, y, p + 1, all);
    c[0] = all[p][0], c[1] = all[p][1];
}

static void accumulate(int pairs, const MaafLight *l, float b1[][2], float b2[][2], const float f4[4], float *ysum);

void maaf_accumulate(int pairs, const MaafLight *l, float y1, float y2, const float f4[4], float *ysum)
{
    /* c_p(y) per axis (eq. 20 with the light integrated, see maaf_shadow.h) */
    float b1[MAAF_PAIRS_MAX][2], b2[MAAF_PAIRS_MAX][2];
    const MaafBandCdf *table = maaf_band_cdf();
    light_factors(table, l, 0, y1, pairs, b1);
    light_factors(table, l, 1, y2, pairs, b2);
    accumulate(pairs, l, b1, b2, f4, ysum);
}

void maaf_accumulate_unknown(int pairs, const MaafLight *l, const float f4[4], float *ysum)
{
    float b1[MAAF_PAIRS_MAX][2], b2[MAAF_PAIRS_MAX][2];
    for (int p = 0; p < pairs; ++p)
        for (int k = 0; k < 2; ++k) {
            b1[p][k] = l->mean[0][p][k];
            b2[p][k] = l->mean[1][p][k];
        }
    accumulate(pairs, l, b1, b2, f4, ysum);
}

/* The factors of the components (p, q) from the per-axis ones, the central component (0, 0)'s
 * the product of c_0's means over the light: c_0(y) is the part of the sample's y-window on the
 * light (1 at its centre, about 1/2 at an edge), and as the central component's weight it
 * averages a pixel's samples over the light with that profile instead of uniformly, biased
 * wherever the light arrives unevenly across it (its cosines and distances; docs/algorithms.md
 * 9.20). The bands p or q >= 1, and c_0 where it multiplies one of them, keep y. */
static void accumulate(int pairs, const MaafLight *l, float b1[][2], float b2[][2], const float f4[4], float *ysum)
{
    float w[2 * MAAF_COMPS_MAX];
    int c = 0;
    for (int p = 0; p < pairs; ++p)
        for (int q = -(pairs - 1); q < pairs; ++q) {
            if (p == 0 && q < 0) continue;
            /* band -q along axis 2 has centre -C_y^q: the conjugate factor */
            float br = q >= 0 ? b2[q][0] : b2[-q][0], bi = q >= 0 ? b2[q][1] : -b2[-q][1];
            w[2 * c] = b1[p][0] * br - b1[p][1] * bi;
            w[2 * c + 1] = b1[p][0] * bi + b1[p][1] * br;
            ++c;
        }
    const float *m1 = l->mean[0][0], *m2 = l->mean[1][0];
    w[0] = m1[0] * m2[0] - m1[1] * m2[1];
    w[1] = m1[0] * m2[1] + m1[1] * m2[0];
    maaf_factors_accumulate(c, w, f4, ysum);
}

static void clear_param(float *param) { memset(param, 0, MAAF_PARAM_STRIDE * sizeof(float)); }

float maaf_pixel_param(float s_min, float s_max, float omega_y_max, int pairs, float kappa, float pixel_world,
                       float *param)
{
    clear_param(param);
    MaafDesign2D d;
    if (!(pixel_world > 0.0f) || !(kappa > 0.0f) || !maaf_design_2d(s_min, s_max, omega_y_max, pairs, &d)) return 0.0f;
    float std_px = 0.0f;
    for (int p = 0; p < d.pairs; ++p) {
        /* kappa widens every component in Omega_x (narrower in x) and keeps its centre on the wedge */
        float sx = kappa * d.c[p].sx;
        param[1 + 3 * p] = d.c[p].weight * sx * INV_SQRT_2PI; /* mu_p g's normalisation */
        param[2 + 3 * p] = d.c[p].cx;
        param[3 + 3 * p] = 0.5f * sx * sx;
        if (p == 0) std_px = 1.0f / (sx * pixel_world); /* the widest component */
    }
    if (!isfinite(std_px) || std_px < 0.25f) { /* below a quarter pixel nothing changes */
        clear_param(param);
        return 0.0f;
    }
    float radius = ceilf(2.0f * std_px);
    param[0] = radius > (float)MAAF_RADIUS_CAP_PX ? (float)MAAF_RADIUS_CAP_PX : radius;
    return std_px;
}

void maaf_pixel_param_plain(float std_px, float pixel_world, int pairs, float *param)
{
    clear_param(param);
    if (!(std_px >= 0.25f) || !(pixel_world > 0.0f) || !isfinite(std_px)) return;
    float sx = 1.0f / (std_px * pixel_world);
    param[1] = sx * INV_SQRT_2PI;
    /* the other bands get amplitude 0 but the same Gaussian: their row-pass sums, which a
     * neighbour's column pass may read, are smoothed like the central one, not box-summed */
    for (int p = 0; p < pairs && p < MAAF_PAIRS_MAX; ++p) param[3 + 3 * p] = 0.5f * sx * sx;
    float radius = ceilf(2.0f * std_px);
    param[0] = radius > (float)MAAF_RADIUS_CAP_PX ? (float)MAAF_RADIUS_CAP_PX : radius;
}
