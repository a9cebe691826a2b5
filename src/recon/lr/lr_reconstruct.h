/* LR reconstruction on the CPU in plain C: per tile, the partitions (lr_partition.h), then
 * per layer the reprojection (Algorithm 1, eq. 16), the separable screen filter along and
 * across the layer's motion (Algorithm 2) and front-to-back compositing (eq. 17). It is the
 * reference the OpenCL kernels (lr.cl) are tested against, and a fallback without OpenCL. */
#ifndef WEDGE_RECON_LR_RECONSTRUCT_H
#define WEDGE_RECON_LR_RECONSTRUCT_H

#include "recon/lr/lr_partition.h"

typedef struct {
    float *rgb;          /* width * height * 3, the reconstructed image */
    float *layers;       /* width * height or NULL: non-empty layers of the pixel's tile (AOV) */
    float *extent_px;    /* width * height or NULL: sigma_x of the front-most layer with
                          * opacity at the pixel (AOV), 0 where none */
    long nonfinite;      /* non-finite sample radiances skipped (counted, never propagated) */
} LrOutput;

/* Screen-filter radius for a primal sigma: 3 sigma, at least 0, at most half the window and
 * at most LR_MAX_RADIUS_PX (the kernels' tap tables). */
enum { LR_MAX_RADIUS_PX = 32 };
int lr_filter_radius_px(float inv_sigma_px, const LrConfig *cfg);

/* The screen filter's tap weights w[k] = exp(-(k / sigma)^2 / 2), k = 0..r (r <=
 * LR_MAX_RADIUS_PX): once per partition, shared by the C passes and the kernels (lr.cl reads
 * them from the host), so both weight every tap with the same value. */
void lr_tap_weights(float inv_sigma_px, int r, float *w);

/* The reprojected pixel of a sample for a layer filter (eq. 16), in the unrotated frame. */
void lr_reproject(const LrSample *s, float cos_psi, float sin_psi, const LrFilter *f, float *p_px, float *q_px,
                  float *weight);

void lr_reconstruct_c(const LrSamples *img, const LrConfig *cfg, LrOutput *out);

#endif
