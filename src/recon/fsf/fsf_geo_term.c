/* The light's geometric term under FSF's shear, form 4 (fsf_geo_term.h). */
#include "recon/fsf/fsf_geo_term.h"

#include <math.h>

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

void fsf_geo_mean(const FsfGeoTerm *t, const float *pos4, const float *nrm4, const unsigned char *usable,
                  const float half_m[2], size_t n, float *mean_g)
{
    enum { M = 8 };
    for (size_t i = 0; i < n; ++i) {
        const float *p = pos4 + 4 * i, *nr = nrm4 + 4 * i;
        mean_g[i] = 0.0f;
        if (!usable[i]) continue;
        /* every light corner above the horizon: G is smooth over the light */
        int above = 1;
        for (int c = 0; c < 4; ++c)
            above &= fsf_geo_G(t, p, nr, (c & 1 ? 1.0f : -1.0f) * half_m[0], (c & 2 ? 1.0f : -1.0f) * half_m[1]) > 0.0f;
        if (!above) continue;
        double sum = 0.0;
        for (int a = 0; a < M; ++a)
            for (int b = 0; b < M; ++b)
                sum += fsf_geo_G(t, p, nr, half_m[0] * (2.0f * ((float)a + 0.5f) / (float)M - 1.0f),
                                 half_m[1] * (2.0f * ((float)b + 0.5f) / (float)M - 1.0f));
        float mean = (float)(sum / (double)(M * M));
        mean_g[i] = isfinite(mean) && mean > 0.0f ? mean : 0.0f;
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
