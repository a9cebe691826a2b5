/* A synthetic 5D light field for LR tests: a textured background plane and a textured
 * foreground disk, each with its own circle-of-confusion slope and screen motion, sampled
 * exactly (the visible surface of a sample is found analytically, with occlusion). */
#ifndef WEDGE_TESTS_LR_SCENE_H
#define WEDGE_TESTS_LR_SCENE_H

#include <math.h>
#include <stdlib.h>

#include "recon/lr/lr_partition.h"

typedef struct {
    float depth, coc_px, motion_px[2];
    float cx_px, cy_px, radius_px; /* the disk at mid-shutter through the lens centre; radius <= 0: plane */
    float freq;                    /* texture: 0.5 + 0.4 sin(freq x) cos(freq y), radians per pixel */
} LrTestLayer;

static unsigned lr_test_rand(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}
static float lr_test_unit(unsigned *s) { return (float)lr_test_rand(s) / 16777216.0f; }

/* A sample's film position jittered in pixel (px, py), lens position uniform on the unit disk,
 * time uniform in [0, 1]. */
static void lr_test_place(LrSample *s, int px, int py, unsigned *seed)
{
    s->x_px = (float)px + lr_test_unit(seed);
    s->y_px = (float)py + lr_test_unit(seed);
    float r = sqrtf(lr_test_unit(seed)), phi = 6.2831853f * lr_test_unit(seed);
    s->u = r * cosf(phi);
    s->v = r * sinf(phi);
    s->t = lr_test_unit(seed);
}

/* Fills w*h*spp samples: jittered in the pixel, uniform on the unit disk and in time.
 * Layers are listed front to back; the last should be a plane (radius <= 0). */
static inline void lr_test_scene(LrSample *out, int w, int h, int spp, const LrTestLayer *layers, int nl, unsigned seed)
{
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px)
            for (int k = 0; k < spp; ++k) {
                LrSample *s = &out[((size_t)py * w + px) * spp + k];
                lr_test_place(s, px, py, &seed);
                for (int l = 0; l < nl; ++l) {
                    const LrTestLayer *L = &layers[l];
                    /* the surface point seen: undo defocus and motion */
                    float ox = s->x_px - L->coc_px * s->u - L->motion_px[0] * (s->t - 0.5f);
                    float oy = s->y_px - L->coc_px * s->v - L->motion_px[1] * (s->t - 0.5f);
                    float dx = ox - L->cx_px, dy = oy - L->cy_px;
                    if (L->radius_px > 0 && dx * dx + dy * dy > L->radius_px * L->radius_px && l + 1 < nl) continue;
                    float tex = 0.5f + 0.4f * sinf(L->freq * ox) * cosf(L->freq * oy);
                    s->depth = L->depth;
                    s->coc_px = L->coc_px;
                    s->motion_px[0] = L->motion_px[0];
                    s->motion_px[1] = L->motion_px[1];
                    s->L[0] = tex;
                    s->L[1] = 0.5f * tex + 0.1f * (float)l;
                    s->L[2] = 1.0f - tex;
                    break;
                }
            }
}

/* A static textured plane tilted in depth, as a floor is: the circle-of-confusion slope of
 * the point seen through the lens centre at row y0 is c(y0) = c_top + dc_dy y0 (linear in y0,
 * as both the slope and a floor's screen row are linear in 1/depth). A sample at film row y
 * and lens v sees the point with y = y0 + c(y0) v, i.e. y0 = (y - c_top v) / (1 + dc_dy v)
 * (|dc_dy| < 1: every film row sees the plane), and x0 = x - c(y0) u. Texture of period
 * 2 pi / freq px along both axes of the plane's screen image. */
static inline void lr_test_tilted_sample(LrSample *s, int px, int py, float c_top, float dc_dy, float freq, unsigned *seed)
{
    lr_test_place(s, px, py, seed);
    float y0 = (s->y_px - c_top * s->v) / (1.0f + dc_dy * s->v), c = c_top + dc_dy * y0;
    float x0 = s->x_px - c * s->u;
    float tex = 0.5f + 0.4f * sinf(freq * x0) * cosf(freq * y0);
    s->depth = 10.0f + c; /* c grows with depth, as the layers' bounds assume */
    s->coc_px = c;
    s->motion_px[0] = s->motion_px[1] = 0.0f;
    s->L[0] = tex, s->L[1] = 0.5f * tex + 0.2f, s->L[2] = 1.0f - tex;
}

#endif
