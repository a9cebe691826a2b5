/* Plain C reference implementations of the recon kernels (aaf/aaf.cl), written from the
 * definitions (AAF-shadow eqs. 10-12) as straightforward loops, for the kernel tests. */
#ifndef WEDGE_TESTS_RECON_AAF_REFERENCE_H
#define WEDGE_TESTS_RECON_AAF_REFERENCE_H

#include <math.h>
#include <stddef.h>

/* One 1D pass over a w x h image along axis 0 (x) or 1 (y). Same buffer layouts as aaf.cl. */
static void ref_aaf_pass(int w, int h, int axis, int pixel_mode, float cos_normal_min, float depth_tol_rel,
                         float sharp_beta_ratio, const float *value, const float *pos, const float *nrm, const float *plane,
                         const float *param, float *out)
{
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            int i = y * w + x;
            const float *c = value + 4 * i;
            int radius = (int)param[2 * i + 1];
            if (radius <= 0 || c[3] == 0.0f) {
                for (int k = 0; k < 4; ++k) out[4 * i + k] = c[k];
                continue;
            }
            double sum[3] = {0, 0, 0}, wsum = 0;
            for (int t = -radius; t <= radius; ++t) {
                int xx = axis == 0 ? x + t : x, yy = axis == 0 ? y : y + t;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                int j = yy * w + xx;
                const float *v = value + 4 * j;
                if (v[3] == 0.0f) continue;
                double dist2;
                if (pixel_mode) {
                    /* with a slope plane: same sign and at least half the centre's slope */
                    if (plane && (double)plane[4 * j] * plane[4 * i] < 0.5 * (double)plane[4 * i] * plane[4 * i]) continue;
                    dist2 = (double)t * t;
                } else {
                    const float *nc = nrm + 4 * i, *nj = nrm + 4 * j;
                    if (nc[3] != nj[3]) continue;
                    double ndot = (double)nc[0] * nj[0] + (double)nc[1] * nj[1] + (double)nc[2] * nj[2];
                    if (ndot < cos_normal_min) continue;
                    /* sharper (narrower or unfiltered) neighbours stay out: beta_j < ratio beta_i */
                    if (sharp_beta_ratio > 0.0f) {
                        if (param[2 * j + 1] <= 0.0f) continue;
                        double bi = 1.0 / sqrt(2.0 * param[2 * i]), bj = 1.0 / sqrt(2.0 * param[2 * j]);
                        if (bj < (double)sharp_beta_ratio * bi * (1.0 - 1e-6)) continue; /* inv 0: infinite */
                    }
                    double dp[3], along = 0, plane_off = 0, len2 = 0;
                    for (int k = 0; k < 3; ++k) {
                        dp[k] = (double)pos[4 * j + k] - (double)pos[4 * i + k];
                        plane_off += nc[k] * dp[k];
                        along += plane[4 * i + k] * dp[k];
                        len2 += dp[k] * dp[k];
                    }
                    if (fabs(plane_off) > (double)depth_tol_rel * pos[4 * i + 3]) continue;
                    dist2 = len2 - along * along;
                    if (dist2 < 0) dist2 = 0;
                }
                double wt = exp(-dist2 * param[2 * i]);
                for (int k = 0; k < 3; ++k) sum[k] += wt * v[k];
                wsum += wt;
            }
            if (wsum > 0) {
                for (int k = 0; k < 3; ++k) out[4 * i + k] = (float)(sum[k] / wsum);
                out[4 * i + 3] = 1.0f;
            } else {
                for (int k = 0; k < 4; ++k) out[4 * i + k] = c[k];
            }
        }
    }
}

/* The full separable filter: x pass then y pass (tmp holds 4*w*h floats). */
static void ref_aaf_filter(int w, int h, int pixel_mode, float cos_normal_min, float depth_tol_rel,
                           float sharp_beta_ratio, const float *value, const float *pos, const float *nrm, const float *plane,
                           const float *param, float *tmp, float *out)
{
    ref_aaf_pass(w, h, 0, pixel_mode, cos_normal_min, depth_tol_rel, sharp_beta_ratio, value, pos, nrm, plane, param, tmp);
    ref_aaf_pass(w, h, 1, pixel_mode, cos_normal_min, depth_tol_rel, sharp_beta_ratio, tmp, pos, nrm, plane, param, out);
}

#endif
