/* The light LR's samples carry beside a shading filter (see lr_shading.h). */
#include "recon/lr/lr_shading.h"

#include <math.h>

/* Pixels whose depth differs more than this (relative) are other surfaces. */
#define LR_SAME_SURFACE_DEPTH 0.05f

bool lr_filtered_light(const float *value4, const float *factor, size_t i, float out[3])
{
    if (!value4 || value4[4 * i + 3] == 0.0f) return false;
    float f = factor ? factor[i] : 1.0f;
    for (int c = 0; c < 3; ++c) out[c] = f * value4[4 * i + c];
    return isfinite(out[0]) && isfinite(out[1]) && isfinite(out[2]);
}

size_t lr_light_pixel(const GBuffer *g, float x0_px, float y0_px, float depth, float object_id, size_t own)
{
    if (!(depth < INFINITY) || !(x0_px >= 0.0f && y0_px >= 0.0f && x0_px < (float)g->width && y0_px < (float)g->height))
        return own;
    size_t q = (size_t)(int)y0_px * (size_t)g->width + (size_t)(int)x0_px;
    bool same = g->nrm4[4 * q + 3] == object_id && fabsf(g->pos4[4 * q + 3] - depth) <= LR_SAME_SURFACE_DEPTH * depth;
    return same ? q : own;
}

/* Albedo below this is black: no light per unit albedo (composite.c's MIN_ALBEDO). */
#define LR_MIN_ALBEDO 1.0e-4f

void lr_delta_light(const GBuffer *g, const SampleStore *st, const float *shading, float *delta4)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    int cap = sample_store_capacity(st);
    for (size_t q = 0; q < n; ++q) {
        int count = sample_store_count(st, q);
        double a[3] = {0, 0, 0}, u[3] = {0, 0, 0};
        for (int k = 0; k < count; ++k) {
            const float *sh = shading + (q * (size_t)cap + (size_t)k) * LR_SHADING_FLOATS;
            for (int c = 0; c < 3; ++c) a[c] += sh[6 + c], u[c] += sh[10 + c];
        }
        bool ok = count > 0 && g->hit[q] && !g->mixed[q];
        for (int c = 0; c < 3; ++c) {
            ok = ok && a[c] > LR_MIN_ALBEDO * count;
            delta4[4 * q + c] = ok ? (float)(u[c] / a[c]) : 0.0f;
        }
        delta4[4 * q + 3] = ok && isfinite(delta4[4 * q]) && isfinite(delta4[4 * q + 1]) && isfinite(delta4[4 * q + 2]);
    }
}

/* One sample's light with its filterable direct and indirect light replaced by albedo times
 * the filtered light, and its delta lights' light by albedo times their pixel mean (ed, ei,
 * eu: NULL leaves that part as it is). */
static void replaced_light(const float *radiance, const float *shading, const float *ed, const float *ei,
                           const float *eu, float out[3])
{
    for (int c = 0; c < 3; ++c) {
        out[c] = radiance[c];
        if (ed) out[c] += shading[6 + c] * ed[c] - shading[c];
        if (ei) out[c] += shading[6 + c] * ei[c] - shading[3 + c];
        if (eu) out[c] += shading[6 + c] * eu[c] - shading[10 + c];
    }
}

void lr_pixel_light(int n, const float *radiance, const float *shading, const size_t *src,
                    const ReconShadingLight *light, const float *delta4, const float value[3], float *out)
{
    double sum[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < n; ++k) {
        float ed_buf[3], ei_buf[3], eu_buf[3];
        const float *ed = NULL, *ei = NULL, *eu = NULL;
        if (shading && light && src) {
            ed = lr_filtered_light(light->direct4, light->direct_factor, src[k], ed_buf) ? ed_buf : NULL;
            ei = lr_filtered_light(light->indirect4, NULL, src[k], ei_buf) ? ei_buf : NULL;
            eu = lr_filtered_light(delta4, NULL, src[k], eu_buf) ? eu_buf : NULL;
        }
        replaced_light(radiance + 3 * k, shading ? shading + LR_SHADING_FLOATS * k : NULL, ed, ei, eu, out + 3 * k);
        for (int c = 0; c < 3; ++c) sum[c] += out[3 * k + c];
    }
    for (int c = 0; c < 3; ++c) {
        float shift = n > 0 ? (float)(value[c] - sum[c] / n) : 0.0f;
        if (!isfinite(shift)) shift = 0.0f; /* a non-finite mean: the sample itself counts it */
        for (int k = 0; k < n; ++k) out[3 * k + c] += shift;
    }
}
