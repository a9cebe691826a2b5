/* Soft-shadow MAAF: light frames, the sums of eq. 20, per-pixel filters (see maaf_shadow.h). */
#include "recon/maaf/maaf_shadow.h"

#include <math.h>
#include <string.h>

#define INV_SQRT_2PI 0.39894228f

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
}

void maaf_light_normal(const MaafLight *l, const float p[3], float n[3])
{
    if (l->normal[0] != 0.0f || l->normal[1] != 0.0f || l->normal[2] != 0.0f) {
        memcpy(n, l->normal, 3 * sizeof(float));
        return;
    }
    float d[3] = {l->center[0] - p[0], l->center[1] - p[1], l->center[2] - p[2]};
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) n[k] = len > 0.0f ? d[k] / len : (k == 2 ? 1.0f : 0.0f);
}

void maaf_accumulate(int pairs, const MaafLight *l, float y1, float y2, const float f4[4], float *ysum)
{
    /* b_p(y) per axis (eq. 20): Gaussian of the light's band, phase -C_y^p y */
    float b1[MAAF_PAIRS_MAX][2], b2[MAAF_PAIRS_MAX][2];
    for (int p = 0; p < pairs; ++p) {
        float s = l->sy[p], g1 = s * INV_SQRT_2PI * expf(-0.5f * s * s * y1 * y1);
        float g2 = s * INV_SQRT_2PI * expf(-0.5f * s * s * y2 * y2);
        b1[p][0] = g1 * cosf(l->cy[p] * y1);
        b1[p][1] = -g1 * sinf(l->cy[p] * y1);
        b2[p][0] = g2 * cosf(l->cy[p] * y2);
        b2[p][1] = -g2 * sinf(l->cy[p] * y2);
    }
    int c = 0;
    for (int p = 0; p < pairs; ++p)
        for (int q = -(pairs - 1); q < pairs; ++q) {
            if (p == 0 && q < 0) continue;
            /* band -q along axis 2 has centre -C_y^q: the conjugate factor */
            float br = q >= 0 ? b2[q][0] : b2[-q][0], bi = q >= 0 ? b2[q][1] : -b2[-q][1];
            float wr = b1[p][0] * br - b1[p][1] * bi, wi = b1[p][0] * bi + b1[p][1] * br;
            float *yr = ysum + 8 * c, *yi = yr + 4;
            for (int ch = 0; ch < 4; ++ch) {
                yr[ch] += wr * f4[ch];
                yi[ch] += wi * f4[ch];
            }
            ++c;
        }
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
    (void)pairs;
    clear_param(param);
    if (!(std_px >= 0.25f) || !(pixel_world > 0.0f) || !isfinite(std_px)) return;
    float sx = 1.0f / (std_px * pixel_world);
    param[1] = sx * INV_SQRT_2PI;
    param[3] = 0.5f * sx * sx;
    float radius = ceilf(2.0f * std_px);
    param[0] = radius > (float)MAAF_RADIUS_CAP_PX ? (float)MAAF_RADIUS_CAP_PX : radius;
}
