/* recon_coc_slope_px (gbuffer.h) with its per-frame factors taken once: LR's gather asks it for
 * every stored sample, and the call with its three divisions (two of them the same for every
 * sample) was 3% of a warm LR filter on motion_defocus_hard. The same float operations in the
 * same order, so the same value for every depth (tests/recon/test_lr_coc_slope.c). */
#ifndef WEDGE_RECON_LR_COC_SLOPE_H
#define WEDGE_RECON_LR_COC_SLOPE_H

#include <float.h>
#include <math.h>
#include <stdbool.h>

#include "recon/gbuffer.h"

typedef struct {
    bool pinhole;           /* no lens (or a degenerate camera): every slope is 0 */
    float radius_per_pixel_angle;    /* R / pixel_angle (world length per radian a pixel spans) */
    float inv_focal_world;  /* 1 / F */
} LrCocSlope;

static inline LrCocSlope lr_coc_slope_of(const ReconCamera *cam)
{
    float R = cam->lens_radius_world, F = cam->focal_distance_world, a = cam->pixel_angle;
    LrCocSlope s = {!(R > 0.0f) || !(F > 0.0f) || !(a > 0.0f), 0.0f, 0.0f};
    if (!s.pinhole) s.radius_per_pixel_angle = R / a, s.inv_focal_world = 1.0f / F;
    return s;
}

/* Signed CoC slope at camera depth z (px per unit lens), as recon_coc_slope_px. */
static inline float lr_coc_slope_px(const LrCocSlope *s, float depth_cam)
{
    if (s->pinhole) return 0.0f;
    float inv_z = (depth_cam > 0.0f) ? 1.0f / depth_cam : 0.0f; /* inf -> 0; behind: treat as far */
    float c = s->radius_per_pixel_angle * (s->inv_focal_world - inv_z);
    return isfinite(c) ? c : (c > 0.0f ? FLT_MAX : -FLT_MAX);
}

#endif
