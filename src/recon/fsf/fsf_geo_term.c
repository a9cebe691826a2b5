/* The light's geometric term under FSF's shear, form 4 (fsf_geo_term.h). */
#include "recon/fsf/fsf_geo_term.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "core/vectorise.h"
#include "recon/fsf/fsf_filter.h"

float fsf_geo_G(const FsfGeoTerm *t, const float *pos, const float *nrm, float z1, float z2)
{
    float l[3];
    for (int c = 0; c < 3; ++c) l[c] = t->centre[c] + z1 * t->axis[0][c] + z2 * t->axis[1][c] - pos[c];
    float d2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    if (!(d2 > 0.0f)) return 0.0f;
    float inv_d = 1.0f / sqrtf(d2);
    float cos_r = (l[0] * nrm[0] + l[1] * nrm[1] + l[2] * nrm[2]) * inv_d;
    float cos_l = fabsf(l[0] * t->normal[0] + l[1] * t->normal[1] + l[2] * t->normal[2]) * inv_d;
    return cos_r > 0.0f ? cos_r * cos_l / d2 : 0.0f;
}

/* G as fsf_geo_G, at the light point lp (world: the centre plus z1 u plus z2 v, summed in
 * fsf_geo_G's order) from n receivers at once, written without branches so that the loop
 * vectorises: the same float operations lane by lane, hence the same bits. */
static inline float geo_G_at(const FsfGeoTerm *t, const float lp[3], float px, float py, float pz, float nx, float ny,
                             float nz)
{
    float l0 = lp[0] - px, l1 = lp[1] - py, l2 = lp[2] - pz;
    float d2 = l0 * l0 + l1 * l1 + l2 * l2;
    float inv_d = 1.0f / sqrtf(d2);
    float cos_r = (l0 * nx + l1 * ny + l2 * nz) * inv_d;
    float cos_l = fabsf(l0 * t->normal[0] + l1 * t->normal[1] + l2 * t->normal[2]) * inv_d;
    float g = cos_r * cos_l / d2; /* computed in every lane, kept where fsf_geo_G would */
    int keep = isgreater(d2, 0.0f) & isgreater(cos_r, 0.0f); /* quiet compares: nothing to keep in order */
    return keep ? g : 0.0f;
}

/* G's mean: an 8 x 8 midpoint grid over a static light; 24 x 24 over a swept one, whose
 * density (a diagonal band for a diagonal motion) the 8 x 8 cells resolve to 0.7% of the mean
 * (test_fsf_swept_light), 24 x 24 to 0.1%; only moving lights' frames pay for it */
enum { GEO_M = 8, GEO_M_SWEPT = 24, GEO_BLOCK = 64 };

float fsf_swept_joint(float z1, float z2, const float pose_m[2], const float motion_m[2])
{
    /* the shutter times at which each axis' extent covers the point: an interval of s */
    float lo = 0.0f, hi = 1.0f, z[2] = {z1, z2};
    for (int a = 0; a < 2; ++a) {
        float half = 0.5f * pose_m[a];
        if (motion_m[a] == 0.0f) {
            if (!(fabsf(z[a]) <= half)) return 0.0f;
            continue;
        }
        float s0 = (z[a] - half) / motion_m[a] + 0.5f, s1 = (z[a] + half) / motion_m[a] + 0.5f;
        lo = fmaxf(lo, fminf(s0, s1)), hi = fminf(hi, fmaxf(s0, s1));
    }
    return hi > lo ? hi - lo : 0.0f;
}

/* The trapezoid's mean over each of `cells` equal cells of [-half_m, half_m] (w, cells floats) */
static void cell_means(float half_m, float ramp_m, int cells, float *w)
{
    enum { SUB = 64 }; /* the profile is linear between its corners: 64 midpoints per cell leave
                        * at most 1/(8 * 64^2) of a corner's cell's weight */
    for (int a = 0; a < cells; ++a) {
        double sum = 0.0;
        for (int k = 0; k < SUB; ++k) {
            float z = half_m * (2.0f * ((float)a + ((float)k + 0.5f) / (float)SUB) / (float)cells - 1.0f);
            sum += fsf_swept_profile(z, half_m, ramp_m);
        }
        w[a] = (float)(sum / SUB);
    }
}

void fsf_geo_swept_weights(float half_m, float ramp_m, float w[FSF_GEO_CELLS])
{
    cell_means(half_m, ramp_m, FSF_GEO_CELLS, w);
}

/* fsf_geo_mean for pixels [i0, i0 + nb) (nb <= GEO_BLOCK), their guides copied to one array
 * per component so that each light point's G over the block is one vector loop; each pixel's
 * double sum runs over the points in the order a, b as before (one lane per pixel). */
static WEDGE_VECTORISED void geo_mean_block(const FsfGeoTerm *t, const float (*lp)[3], int points,
                                            const float (*corner)[3], const double *weight, const float *pos4,
                                            const float *nrm4, const unsigned char *usable, size_t i0, int nb,
                                            float *mean_g)
{
    float p[6][GEO_BLOCK];
    double sum[GEO_BLOCK];
    int above[GEO_BLOCK];
    for (int k = 0; k < nb; ++k) {
        for (int c = 0; c < 3; ++c) p[c][k] = pos4[4 * (i0 + (size_t)k) + (size_t)c];
        for (int c = 0; c < 3; ++c) p[3 + c][k] = nrm4[4 * (i0 + (size_t)k) + (size_t)c];
        sum[k] = 0.0, above[k] = 1;
    }
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < nb; ++k)
            above[k] &= isgreater(geo_G_at(t, corner[c], p[0][k], p[1][k], p[2][k], p[3][k], p[4][k], p[5][k]), 0.0f);
    double weights = points;
    for (int q = 0; q < points; ++q) {
        float g[GEO_BLOCK];
        for (int k = 0; k < nb; ++k) g[k] = geo_G_at(t, lp[q], p[0][k], p[1][k], p[2][k], p[3][k], p[4][k], p[5][k]);
        if (weight) /* a swept light: each point by its samples' density */
            for (int k = 0; k < nb; ++k) sum[k] += (double)g[k] * weight[q];
        else
            for (int k = 0; k < nb; ++k) sum[k] += (double)g[k];
    }
    if (weight) {
        weights = 0.0;
        for (int q = 0; q < points; ++q) weights += weight[q];
    }
    for (int k = 0; k < nb; ++k) {
        float mean = (float)(sum[k] / weights);
        mean_g[i0 + (size_t)k] = usable[i0 + (size_t)k] && above[k] && isfinite(mean) && mean > 0.0f ? mean : 0.0f;
    }
}

void fsf_geo_mean(const FsfGeoTerm *t, const float *pos4, const float *nrm4, const unsigned char *usable,
                  const float half_m[2], size_t n, float *mean_g)
{
    /* the light points (fsf_geo_G's sums without the receiver): an M x M midpoint grid (GEO_M,
     * GEO_M_SWEPT for a swept light), a outer and b inner as the mean sums them, and the four
     * corners */
    bool swept = t->ramp_m[0] > 0.0f || t->ramp_m[1] > 0.0f;
    int M = swept ? GEO_M_SWEPT : GEO_M;
    float lp[GEO_M_SWEPT * GEO_M_SWEPT][3], corner[4][3];
    for (int a = 0; a < M; ++a)
        for (int b = 0; b < M; ++b) {
            float z1 = half_m[0] * (2.0f * ((float)a + 0.5f) / (float)M - 1.0f);
            float z2 = half_m[1] * (2.0f * ((float)b + 0.5f) / (float)M - 1.0f);
            for (int c = 0; c < 3; ++c) lp[a * M + b][c] = t->centre[c] + z1 * t->axis[0][c] + z2 * t->axis[1][c];
        }
    for (int k = 0; k < 4; ++k) {
        float z1 = (k & 1 ? 1.0f : -1.0f) * half_m[0], z2 = (k & 2 ? 1.0f : -1.0f) * half_m[1];
        for (int c = 0; c < 3; ++c) corner[k][c] = t->centre[c] + z1 * t->axis[0][c] + z2 * t->axis[1][c];
    }
    /* a swept light: the points' weights, its samples' density's mean over each point's cell
     * (NULL: uniform, as before): the joint density of a translating pose where its extent and
     * motion are known, else the product of the axes' trapezoids */
    double weight[GEO_M_SWEPT * GEO_M_SWEPT];
    float axis_w[2][GEO_M_SWEPT];
    for (int a = 0; swept && a < 2; ++a) {
        if (t->ramp_m[a] > 0.0f) cell_means(half_m[a], t->ramp_m[a], M, axis_w[a]);
        else for (int k = 0; k < M; ++k) axis_w[a][k] = 1.0f; /* no ramp: uniform */
    }
    bool joint = swept && t->pose_m[0] > 0.0f && t->pose_m[1] > 0.0f;
    for (int a = 0; swept && a < M; ++a)
        for (int b = 0; b < M; ++b) {
            if (!joint) {
                weight[a * M + b] = (double)axis_w[0][a] * (double)axis_w[1][b];
                continue;
            }
            enum { SUB = 8 };
            double sum = 0.0;
            for (int i = 0; i < SUB; ++i)
                for (int k = 0; k < SUB; ++k) {
                    float z1 = half_m[0] * (2.0f * ((float)a + ((float)i + 0.5f) / SUB) / (float)M - 1.0f);
                    float z2 = half_m[1] * (2.0f * ((float)b + ((float)k + 0.5f) / SUB) / (float)M - 1.0f);
                    sum += fsf_swept_joint(z1, z2, t->pose_m, t->motion_m);
                }
            weight[a * M + b] = sum / (SUB * SUB);
        }
    for (size_t i0 = 0; i0 < n; i0 += GEO_BLOCK) {
        int nb = n - i0 < GEO_BLOCK ? (int)(n - i0) : GEO_BLOCK;
        /* a block without a usable pixel (the background, the light's own rows) costs nothing */
        bool any = false;
        for (int k = 0; k < nb && !any; ++k) any = usable[i0 + (size_t)k];
        if (any)
            geo_mean_block(t, (const float(*)[3])lp, M * M, (const float(*)[3])corner, swept ? weight : NULL, pos4,
                           nrm4, usable, i0, nb, mean_g);
        else memset(mean_g + i0, 0, sizeof(float) * (size_t)nb);
    }
}

void fsf_geo_factors(const FsfGeoTerm *t, const float *pos4, const float *nrm4, size_t i, float y1, float y2,
                     float z1, float *f_rgb, float *f_w)
{
    *f_rgb = *f_w = 1.0f;
    if (!t || !(t->mean_g[i] > 0.0f)) return;
    const float *p = pos4 + 4 * i, *nr = nrm4 + 4 * i;
    float g_y = fsf_geo_G(t, p, nr, y1, y2);
    if (!(g_y > 0.0f)) return;
    float g_z = fsf_geo_G(t, p, nr, z1, y2);
    /* value V g(y) becomes V g(z); the weight g(z) (normalised by the pixel's mean term) */
    *f_rgb = g_z / g_y;
    *f_w = g_z / t->mean_g[i];
}

float fsf_geo_marginal(const FsfGeoTerm *t, const float *pos, const float *nrm, float half1_m, float z2)
{
    enum { M = 8 }; /* as fsf_geo_mean and fsf.cl's fsf_geo_marginal (one float8) */
    float sum = 0.0f;
    if (t->ramp_m[0] > 0.0f) { /* a swept light: weighted by its samples' density along z1 */
        float w[FSF_GEO_CELLS], weights = 0.0f;
        fsf_geo_swept_weights(half1_m, t->ramp_m[0], w);
        for (int a = 0; a < M; ++a) {
            float z1 = half1_m * (2.0f * ((float)a + 0.5f) / (float)M - 1.0f);
            sum += w[a] * fsf_geo_G(t, pos, nrm, z1, z2), weights += w[a];
        }
        return sum / weights;
    }
    for (int a = 0; a < M; ++a)
        sum += fsf_geo_G(t, pos, nrm, half1_m * (2.0f * ((float)a + 0.5f) / (float)M - 1.0f), z2);
    return sum / (float)M;
}

float fsf_geo_factor2(const FsfGeoTerm *t, const float *pos4, const float *nrm4, size_t i, float half1_m, float y2,
                      float z2)
{
    if (!t || !(t->mean_g[i] > 0.0f)) return 1.0f;
    const float *p = pos4 + 4 * i, *nr = nrm4 + 4 * i;
    float g_y = fsf_geo_marginal(t, p, nr, half1_m, y2);
    /* rgb and weight both carry the term at y2 after pass 1a: move both to z2 */
    return g_y > 0.0f ? fsf_geo_marginal(t, p, nr, half1_m, z2) / g_y : 1.0f;
}
