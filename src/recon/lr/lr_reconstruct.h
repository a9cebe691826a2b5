/* LR reconstruction on the CPU in plain C: per tile, the partitions (lr_partition.h), then
 * per layer the reprojection (Algorithm 1, eq. 16), the separable screen filter along and
 * across the layer's motion (Algorithm 2) and front-to-back compositing (eq. 17). It is the
 * reference the OpenCL kernels (lr.cl) are tested against, and a fallback without OpenCL. */
#ifndef WEDGE_RECON_LR_RECONSTRUCT_H
#define WEDGE_RECON_LR_RECONSTRUCT_H

#include <math.h>

#include "recon/lr/lr_partition.h"
#include "recon/lr/lr_taps.h"

/* Pixels in the band of LrConfig.inset_px are left as they were (not reconstructed). */
typedef struct {
    float *rgb;          /* width * height * 3, the reconstructed image */
    float *layers;       /* width * height or NULL: non-empty layers of the pixel's tile (AOV) */
    float *extent_px;    /* width * height or NULL: sigma_x of the front-most layer with
                          * opacity at the pixel (AOV; a still layer's at the pixel's band
                          * class, LrConfig.band_class), 0 where none */
    long nonfinite;      /* non-finite sample radiances skipped (counted, never propagated) */
} LrOutput;

/* exp(-s / 2) for s >= 0, 0 beyond s = LR_GAUSS_CUT (weight 1.5e-8): 2^y with y = -s log2(e) / 2
 * split into round(y) (the exponent bits) and a remainder in [-1/2, 1/2] (Cephes' exp2f
 * polynomial, relative error ~2e-7). lr.cl has the same function operation for operation, so
 * the C passes and the kernels weight every sample with the same value; it costs about half
 * of a libm exp, and the reprojection evaluates it once per (layer, sample). */
#define LR_GAUSS_CUT 36.0f
static inline float lr_gauss(float s)
{
    if (!(s <= LR_GAUSS_CUT)) return 0.0f;
    float y = -0.72134752f * s; /* -log2(e) / 2 */
    float n = floorf(y + 0.5f), f = y - n;
    float p = 1.535336188319500e-4f;
    p = p * f + 1.339887440266574e-3f;
    p = p * f + 9.618437357674640e-3f;
    p = p * f + 5.550332471162809e-2f;
    p = p * f + 2.402264791363012e-1f;
    p = p * f + 6.931472028550421e-1f;
    union {
        int i;
        float f;
    } two_n = {.i = ((int)n + 127) << 23}; /* 2^n, n in [-26, 0]: a normal float */
    return (1.0f + f * p) * two_n.f;
}

/* The reprojected pixel of a sample for a layer filter (eq. 16), in the unrotated frame. */
void lr_reproject(const LrPlace *s, float cos_psi, float sin_psi, const LrFilter *f, float *p_px, float *q_px,
                  float *weight);

void lr_reconstruct_c(const LrSamples *img, const LrConfig *cfg, LrOutput *out);

#endif
