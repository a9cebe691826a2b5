/* Soft-shadow MAAF: light frames, the sums of eq. 20, per-pixel filters (see maaf_shadow.h). */
#include "recon/maaf/maaf_shadow.h"

#include <math.h>
#include <string.h>

#define INV_SQRT_2PI 0.39894228f

/* One axis' table c_p(y_e), e < MAAF_YTABLE, y_e = lo + (hi - lo) e / (MAAF_YTABLE - 1), of
 *     c_p(y) = int_{lo - y}^{hi - y} exp(j C_p t) g(t; s) dt
 * for the bands p < pairs by Simpson's rule with 2 (MAAF_YTABLE - 1) steps over each window (the
 * integrand is smooth: a Gaussian of std 1/s times an oscillation of period 2 pi / C, both wider
 * than a step). Every window is the light's width w long and starts at a multiple of
 * w / (MAAF_YTABLE - 1), so the Simpson panels of all the windows are the same panels of one grid
 * over [-w, w]: each panel is integrated once, and a window is the difference of two running sums
 * of them (the same weights as each window's own Simpson sum; only the order of the additions
 * differs). This is 2 (2 MAAF_YTABLE - 1) integrand values an axis instead of MAAF_YTABLE windows
 * of 2 MAAF_YTABLE - 1: a mesh light of thousands of triangles, each with its own extents, designed
 * each one's table in a millisecond. The bands share s (eq. 6: Omega_y_max / (2N - 1) for every
 * band), so the Gaussian is one exp per node for all of them, and the central band (C t = +-0)
 * takes no cosine or sine: they give exactly 1 and C t there. */
static void window_table(double lo, double hi, const float *C, double s, int pairs, float table[][MAAF_YTABLE][2])
{
    enum { PANELS = MAAF_YTABLE - 1, NODES = 4 * PANELS + 1 }; /* panels of the window; nodes over [-w, w] */
    double w = hi - lo, h = w / (2 * PANELS);                  /* Simpson's step */
    double f[NODES][MAAF_PAIRS_MAX][2];                          /* the integrand at node j: t = (j - 2 PANELS) h */
    for (int j = 0; j < NODES; ++j) {
        double t = (j - 2 * PANELS) * h, g = s * 0.3989422804014327 * exp(-0.5 * s * s * t * t);
        for (int p = 0; p < pairs; ++p) {
            double x = C[p] * t;
            bool zero = x == 0.0;
            f[j][p][0] = g * (zero ? 1.0 : cos(x));
            f[j][p][1] = g * (zero ? x : sin(x));
        }
    }
    /* run[m]: the panels [0, m) of the 2 PANELS over [-w, w] (panel m spans nodes 2m .. 2m + 2) */
    double run[2 * PANELS + 1][MAAF_PAIRS_MAX][2];
    for (int p = 0; p < pairs; ++p) run[0][p][0] = run[0][p][1] = 0.0;
    for (int m = 0; m < 2 * PANELS; ++m)
        for (int p = 0; p < pairs; ++p)
            for (int k = 0; k < 2; ++k)
                run[m + 1][p][k] = run[m][p][k] + (f[2 * m][p][k] + 4.0 * f[2 * m + 1][p][k] + f[2 * m + 2][p][k]) * h / 3.0;
    /* window e spans t in [-w e / PANELS, w (PANELS - e) / PANELS]: panels PANELS - e .. 2 PANELS - e */
    for (int e = 0; e < MAAF_YTABLE; ++e)
        for (int p = 0; p < pairs; ++p)
            for (int k = 0; k < 2; ++k) table[p][e][k] = (float)(run[2 * PANELS - e][p][k] - run[PANELS - e][p][k]);
}

/* A swept light's mean c_p: the expectation over its samples, whose density along an axis is
 * the fraction of the shutter during which the light covers that coordinate (the share of its
 * poses whose extent holds it; a light sliding along t1 gives a trapezoid). The static light's
 * mean is the same with density 1 over its extent. */
static void swept_means(int pairs, MaafLight *l)
{
    for (int a = 0; a < 2; ++a) {
        double density[MAAF_YTABLE], total = 0.0;
        for (int e = 0; e < MAAF_YTABLE; ++e) {
            double y = l->lo[a] + (l->hi[a] - l->lo[a]) * e / (MAAF_YTABLE - 1.0);
            int covered = 0;
            for (int k = 0; k < l->sweep_nodes; ++k) covered += y >= l->sweep_lo[a][k] && y <= l->sweep_hi[a][k];
            density[e] = (e == 0 || e == MAAF_YTABLE - 1 ? 0.5 : 1.0) * covered;
            total += density[e];
        }
        for (int p = 0; p < pairs; ++p)
            for (int k = 0; k < 2; ++k) {
                double s = 0.0;
                for (int e = 0; e < MAAF_YTABLE; ++e) s += density[e] * l->table[a][p][e][k];
                l->mean[a][p][k] = total > 0.0 ? (float)(s / total) : 0.0f;
            }
    }
}

void maaf_light_design(float sigma_light_world, int pairs, MaafLight *l)
{
    float wy = sigma_light_world > 0.0f && isfinite(sigma_light_world) ? 2.0f / sigma_light_world : 0.0f;
    l->omega_y_max = wy;
    float bands = 2.0f * (float)pairs - 1.0f;
    for (int p = 0; p < MAAF_PAIRS_MAX; ++p) {
        /* eq. 6 */
        l->cy[p] = p < pairs ? wy * 2.0f * (float)p / bands : 0.0f;
        l->sy[p] = p < pairs ? wy / bands : 0.0f;
    }
    memset(l->table, 0, sizeof l->table);
    if (!(wy > 0.0f)) return;
    /* a light as wide along t2 as along t1 (squares, disks, spheres) has the same table on both
     * axes: the second is a copy, not 2 x 129 more integrals of 257 steps per band */
    bool same_axes = l->lo[1] == l->lo[0] && l->hi[1] == l->hi[0];
    for (int a = 0; a < 2; ++a) {
        if (a == 1 && same_axes) {
            for (int p = 0; p < pairs; ++p) memcpy(l->table[1][p], l->table[0][p], sizeof l->table[0][p]);
            continue;
        }
        window_table(l->lo[a], l->hi[a], l->cy, l->sy[0], pairs, l->table[a]);
    }
    if (l->sweep_nodes > 0) {
        swept_means(pairs, l);
        return;
    }
    for (int a = 0; a < 2; ++a)
        for (int p = 0; p < pairs; ++p)
            for (int k = 0; k < 2; ++k) { /* trapezoid rule over the uniform table */
                double s = 0.0;
                for (int e = 0; e < MAAF_YTABLE; ++e)
                    s += (e == 0 || e == MAAF_YTABLE - 1 ? 0.5 : 1.0) * l->table[a][p][e][k];
                l->mean[a][p][k] = (float)(s / (MAAF_YTABLE - 1));
            }
}

bool maaf_light_design_copy(const MaafLight *from, float sigma_light_world, MaafLight *l)
{
    float wy = sigma_light_world > 0.0f && isfinite(sigma_light_world) ? 2.0f / sigma_light_world : 0.0f;
    if (!(wy > 0.0f) || from->omega_y_max != wy || from->lo[0] != l->lo[0] || from->hi[0] != l->hi[0] ||
        from->lo[1] != l->lo[1] || from->hi[1] != l->hi[1] || from->sweep_nodes != l->sweep_nodes ||
        memcmp(from->sweep_lo, l->sweep_lo, sizeof l->sweep_lo) || memcmp(from->sweep_hi, l->sweep_hi, sizeof l->sweep_hi))
        return false;
    l->omega_y_max = wy;
    memcpy(l->cy, from->cy, sizeof l->cy);
    memcpy(l->sy, from->sy, sizeof l->sy);
    memcpy(l->table, from->table, sizeof l->table);
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
    float span = l->hi[axis] - l->lo[axis];
    float u = span > 0.0f ? (y - l->lo[axis]) / span * (MAAF_YTABLE - 1) : 0.0f;
    if (!(u > 0.0f)) u = 0.0f; /* NaN too */
    if (u > MAAF_YTABLE - 1) u = MAAF_YTABLE - 1;
    int e = (int)u;
    if (e > MAAF_YTABLE - 2) e = MAAF_YTABLE - 2;
    float t = u - (float)e;
    const float(*row)[2] = l->table[axis][p];
    c[0] = row[e][0] + t * (row[e + 1][0] - row[e][0]);
    c[1] = row[e][1] + t * (row[e + 1][1] - row[e][1]);
}

static void accumulate(int pairs, const MaafLight *l, float b1[][2], float b2[][2], const float f4[4], float *ysum);

void maaf_accumulate(int pairs, const MaafLight *l, float y1, float y2, const float f4[4], float *ysum)
{
    /* c_p(y) per axis (eq. 20 with the light integrated, see maaf_shadow.h) */
    float b1[MAAF_PAIRS_MAX][2], b2[MAAF_PAIRS_MAX][2];
    for (int p = 0; p < pairs; ++p) {
        maaf_light_factor(l, 0, p, y1, b1[p]);
        maaf_light_factor(l, 1, p, y2, b2[p]);
    }
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
