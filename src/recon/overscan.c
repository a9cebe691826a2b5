/* The visible window of an overscanned frame (see overscan.h). */
#include "recon/overscan.h"

#include <string.h>

void overscan_crop(void *dst, const void *src, int src_w, int src_h, int margin, size_t elem_bytes)
{
    int w = src_w - 2 * margin, h = src_h - 2 * margin;
    size_t row = (size_t)w * elem_bytes;
    for (int y = 0; y < h; ++y)
        memcpy((char *)dst + (size_t)y * row,
               (const char *)src + ((size_t)(y + margin) * (size_t)src_w + (size_t)margin) * elem_bytes, row);
}

void overscan_crop_gbuffer(GBuffer *dst, const GBuffer *src, int margin)
{
    int sw = src->width, sh = src->height;
    FrameSum to[FRAME_SUM_COUNT], from[FRAME_SUM_COUNT];
    frame_sums(&dst->frame, to);
    frame_sums(&src->frame, from);
    for (int k = 0; k < FRAME_SUM_COUNT; ++k)
        overscan_crop(to[k].sum, from[k].sum, sw, sh, margin, (size_t)from[k].floats_per_pixel * sizeof(float));
    overscan_crop(dst->sums, src->sums, sw, sh, margin, sizeof(GBufferSums));
    overscan_crop(dst->hit, src->hit, sw, sh, margin, 1);
    overscan_crop(dst->mixed, src->mixed, sw, sh, margin, 1);
    overscan_crop(dst->glossy, src->glossy, sw, sh, margin, 1);
    overscan_crop(dst->albedo_varies, src->albedo_varies, sw, sh, margin, 1);
    overscan_crop(dst->lobe4, src->lobe4, sw, sh, margin, 4 * sizeof(float));
    overscan_crop(dst->pos4, src->pos4, sw, sh, margin, 4 * sizeof(float));
    overscan_crop(dst->nrm4, src->nrm4, sw, sh, margin, 4 * sizeof(float));
    overscan_crop(dst->pixel_world, src->pixel_world, sw, sh, margin, sizeof(float));
    dst->cam = src->cam;
    /* the scene's size as the whole traced frame saw it (what the methods used) */
    dst->scene_size_world = src->scene_size_world;
}
