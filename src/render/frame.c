/* Frame buffers: per-pixel sums and their resolution into images. */
#include "render/frame.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/zalloc.h"

bool frame_init(Frame *f, int width, int height) { return frame_init_planes(f, width, height, FRAME_PLANES_ALL); }

bool frame_init_planes(Frame *f, int width, int height, unsigned planes)
{
    *f = (Frame){0};
    if (width <= 0 || height <= 0) return false;
    size_t n = (size_t)width * (size_t)height;
    f->width = width, f->height = height;
    f->color = zalloc(3 * n, sizeof(float));
    f->spp = zalloc(n, sizeof(float));
    bool ok = f->color && f->spp;
    if (planes & FRAME_PLANES_PARTS) {
        f->direct = zalloc(3 * n, sizeof(float));
        f->indirect = zalloc(3 * n, sizeof(float));
        f->emission = zalloc(3 * n, sizeof(float));
        ok = ok && f->direct && f->indirect && f->emission;
    }
    if (planes & FRAME_PLANES_GUIDES) {
        f->albedo = zalloc(3 * n, sizeof(float));
        f->normal = zalloc(3 * n, sizeof(float));
        f->depth = zalloc(n, sizeof(float));
        f->hits = zalloc(n, sizeof(float));
        ok = ok && f->albedo && f->normal && f->depth && f->hits;
    }
    if (!ok) frame_free(f);
    return ok;
}

unsigned frame_planes(const Frame *f)
{
    return (f->direct ? FRAME_PLANES_PARTS : 0u) | (f->albedo ? FRAME_PLANES_GUIDES : 0u);
}

void frame_free(Frame *f)
{
    free(f->color), free(f->direct), free(f->indirect), free(f->emission);
    free(f->albedo), free(f->normal), free(f->depth), free(f->hits), free(f->spp);
    *f = (Frame){0};
}

void frame_sums(const Frame *f, FrameSum out[FRAME_SUM_COUNT])
{
    float *const sums[FRAME_SUM_COUNT] = {f->color,  f->direct, f->indirect, f->emission, f->albedo,
                                          f->normal, f->depth,  f->hits,     f->spp};
    for (int k = 0; k < FRAME_SUM_COUNT; ++k) out[k] = (FrameSum){sums[k], k < 6 ? 3 : 1};
}

void frame_clear(Frame *f)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    FrameSum sums[FRAME_SUM_COUNT];
    frame_sums(f, sums);
    for (int k = 0; k < FRAME_SUM_COUNT; ++k)
        if (sums[k].sum) memset(sums[k].sum, 0, (size_t)sums[k].floats_per_pixel * n * sizeof(float));
    f->guides_skipped = false;
}

long frame_resolve3(const Frame *f, const float *sum3, float *out)
{
    long guarded = 0;
    size_t n = (size_t)f->width * (size_t)f->height;
    for (size_t i = 0; i < n; ++i) {
        float s = f->spp[i];
        for (int c = 0; c < 3; ++c) {
            float v = s > 0.0f ? sum3[3 * i + c] / s : 0.0f;
            if (!isfinite(v)) v = 0.0f, ++guarded;
            out[3 * i + c] = v;
        }
    }
    return guarded;
}

long frame_resolve_normal(const Frame *f, float *out3)
{
    long guarded = 0;
    size_t n = (size_t)f->width * (size_t)f->height;
    for (size_t i = 0; i < n; ++i) {
        const float *s = f->normal + 3 * i;
        double len = sqrt((double)s[0] * s[0] + (double)s[1] * s[1] + (double)s[2] * s[2]);
        for (int c = 0; c < 3; ++c) {
            float v = len > 0.0 ? (float)(s[c] / len) : 0.0f;
            if (!isfinite(v)) v = 0.0f, ++guarded;
            out3[3 * i + c] = v;
        }
    }
    return guarded;
}

long frame_resolve_depth(const Frame *f, float *out1)
{
    long guarded = 0;
    size_t n = (size_t)f->width * (size_t)f->height;
    for (size_t i = 0; i < n; ++i) {
        float v = f->hits[i] > 0.0f ? f->depth[i] / f->hits[i] : 0.0f;
        if (!isfinite(v)) v = 0.0f, ++guarded;
        out1[i] = v;
    }
    return guarded;
}

double frame_spp_avg(const Frame *f)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    double s = 0.0;
    for (size_t i = 0; i < n; ++i) s += f->spp[i];
    return n ? s / (double)n : 0.0;
}
