/* Overscan: the visible part of a frame traced with a band of M pixels around the image
 * (renderer_set_overscan). The pipeline reconstructs the enlarged frame, so that methods that
 * read samples beyond a pixel (LR, up to its window margin) find real samples at the image
 * border, and hands out only the visible W x H window: image, AOV layers and guides.
 * docs/algorithms.md, "Overscan". */
#ifndef WEDGE_RECON_OVERSCAN_H
#define WEDGE_RECON_OVERSCAN_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/gbuffer.h"
#include "render/frame.h"

/* Copies the (src_w - 2 margin) x (src_h - 2 margin) window at (margin, margin) of a src_w x
 * src_h image with elem_bytes per pixel into dst (rows packed). */
void overscan_crop(void *dst, const void *src, int src_w, int src_h, int margin, size_t elem_bytes);

/* The visible window of every per-pixel array of src (frame sums, guide sums, guides) into
 * dst, which has the visible size (gbuffer_init). */
void overscan_crop_gbuffer(GBuffer *dst, const GBuffer *src, int margin);

#endif
