/* FSF's plan under a --spp budget (fsf_budget_plan.h). */
#include "recon/fsf/fsf_budget_plan.h"

#include <math.h>
#include <stdlib.h>

#include "recon/fsf/fsf_bounce.h"
#include "recon/fsf/fsf_params.h"
#include "recon/sample_rate.h"

bool fsf_pixel_collapsed(const FsfPixel *px)
{
    return px->sigma_px[0] < FSF_COLLAPSED_SIGMA_PX || px->sigma_px[1] < FSF_COLLAPSED_SIGMA_PX;
}

float fsf_pixel_area_px(const FsfPixel *px)
{
    if (fsf_pixel_collapsed(px)) return 0.0f;
    return sample_rate_area_px(px->sigma_px[0] * px->sigma_px[0], px->sigma_px[1] * px->sigma_px[1]);
}

/* fsf_budget_plan.h */
float fsf_shear_overlap(float sigma_px, float eta_m, float half_m, float reach_sigmas)
{
    /* the filter's own taps: the shadows' stop at 1.5 sigma, not 2 (FsfGrid.reach_sigmas) */
    int r = fsf_radius_reach(sigma_px, reach_sigmas);
    if (r == 0 || eta_m == 0.0f || !(half_m > 0.0f)) return 1.0f;
    /* running sums of w and w^2 over the taps -r .. r (fsf_tap_prefix's w) */
    float cum1[FSF_CUM], cum2[FSF_CUM];
    cum1[0] = cum2[0] = 0.0f;
    for (int t = -r; t <= r; ++t) {
        float w = expf(-0.5f * (float)(t * t) / (sigma_px * sigma_px));
        cum1[t + r + 1] = cum1[t + r] + w, cum2[t + r + 1] = cum2[t + r] + w * w;
    }
    /* the mean over the light of sum_run w^2 / (sum_run w)^2, the run being the taps that cover
     * z (fsf_density's); midpoints of FSF_OVERLAP_NODES cells over [-L, L] */
    double mean_inv = 0.0;
    for (int c = 0; c < FSF_OVERLAP_NODES; ++c) {
        float z = ((float)c + 0.5f) / (float)FSF_OVERLAP_NODES * 2.0f * half_m - half_m;
        float a = (z - half_m) / eta_m, b = (z + half_m) / eta_m;
        int lo = (int)fmaxf(-(float)r, ceilf(fminf(a, b))), hi = (int)fminf((float)r, floorf(fmaxf(a, b)));
        float s1 = cum1[hi + r + 1] - cum1[lo + r], s2 = cum2[hi + r + 1] - cum2[lo + r];
        mean_inv += s1 > 0.0f ? (double)s2 / ((double)s1 * s1) : 1.0;
    }
    mean_inv /= FSF_OVERLAP_NODES;
    float unsheared = cum1[2 * r + 1] * cum1[2 * r + 1] / cum2[2 * r + 1];
    float ratio = (float)(1.0 / mean_inv) / unsheared;
    return ratio < 1.0f ? ratio : 1.0f;
}

float fsf_pixel_area_sheared_px(const FsfPixel *px, const FsfGrid *g)
{
    float a = sample_rate_area_px(px->sigma_px[0] * px->sigma_px[0], px->sigma_px[1] * px->sigma_px[1]);
    a *= fsf_shear_overlap(px->sigma_px[0], px->eta_m[0], g->half_m[0], g->reach_sigmas) *
         fsf_shear_overlap(px->sigma_px[1], px->eta_m[1], g->half_m[1], g->reach_sigmas);
    return a > 1.0f ? a : 1.0f;
}

bool fsf_shadow_area(const GBuffer *g, const SampleStore *st, const FsfLight *light, const float *share, float mu,
                     const FsfSlopeWindows *windows, FsfScratch *p, float *area_px)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    /* as fsf_method.c's gather, without the demodulated value (not known before compositing):
     * a pixel whose samples are all dark is filtered there but is no less noisy here */
    for (size_t i = 0; i < n; ++i)
        p->usable[i] = sample_store_count(st, i) > 0 && g->hit[i] && !g->mixed[i] && !fsf_pixel_creased(g, i);
    FsfParamsIn in = {g, st, light, p->usable, mu, windows};
    bool ok = fsf_pixel_params(&in, p->px, p->k_lo, p->k_hi);
    for (size_t i = 0; ok && i < n; ++i) {
        /* a surface the filter passes through: mixed (several surfaces), or most of its light
         * from another emitter */
        bool left = g->mixed[i] || (share && !(share[i] >= FSF_MIN_LIGHT_SHARE)) || !p->usable[i];
        if (sample_store_count(st, i) > 0 && g->hit[i])
            area_px[i] = fminf(area_px[i], left ? 0.0f : fsf_pixel_area_px(&p->px[i]));
    }
    return ok;
}

bool fsf_bounce_area(const GBuffer *g, const SampleStore *st, float mu, FsfScratch *p, float *area_px)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    /* the demodulated value is not known before compositing: usable without it */
    bool ok = fsf_bounce_coords(g, st, NULL, p->usable, p->y, p->count);
    FsfBounceIn in = {g, st, p->y, p->usable, mu, FSF_BOUNCE_PARALLAX_V, FSF_BOUNCE_H_MIN_FRAC};
    ok = ok && fsf_bounce_params(&in, p->px, p->k_lo, p->k_hi);
    for (size_t i = 0; ok && i < n; ++i)
        if (sample_store_count(st, i) > 0 && g->hit[i])
            area_px[i] = fminf(area_px[i], g->mixed[i] ? 0.0f : fsf_pixel_area_px(&p->px[i]));
    return ok;
}

void fsf_texture_area(const GBuffer *g, const FsfPixel *lens_px, float *area_px)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    for (size_t i = 0; i < n; ++i) {
        /* the lens filter's width in pixels (both axes share it, fsf_lens.h); 0 when left out */
        float lens_std_px = lens_px ? fminf(lens_px[i].sigma_px[0], lens_px[i].sigma_px[1]) : 0.0f;
        if (g->hit[i] && gbuffer_texture_needs_samples(g, i, lens_std_px))
            area_px[i] = fminf(area_px[i], FSF_TEXTURE_AREA_PX);
    }
}

void fsf_budget_plan(const float *want_spp, size_t n, const float *spp_now, int *spp_total)
{
    double carry = 0.0;
    for (size_t i = 0; i < n; ++i) {
        spp_total[i] = (int)spp_now[i];
        double extra = (double)want_spp[i] - (double)spp_now[i] + carry;
        int k = (int)floor(extra + 0.5);
        /* a pixel above its share (an earlier plan's) keeps it and lends nothing to the next */
        if (k < 0) k = 0, extra = 0.0;
        carry = extra - k;
        spp_total[i] += k;
    }
}

void fsf_blend_collapsed(const FsfPixel *px, const unsigned char *usable, const int *stored, const GBuffer *g,
                         const FsfGrid *grid, const float *mean4, float *value4)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    for (size_t i = 0; i < n; ++i) {
        if (!usable[i] || !fsf_pixel_collapsed(&px[i])) continue;
        if (!(px[i].sigma_px[0] > 0.0f || px[i].sigma_px[1] > 0.0f)) continue; /* passed through */
        /* the samples beyond the stored ones: the pixel's own (hits counts every pass's) */
        float n1 = (float)stored[i], extra = (float)g->sums[i].hits - n1;
        if (!(extra > 0.0f)) continue;
        /* inverse-variance weights: the filter as n1 A samples, the extras as themselves */
        float w_mean = extra / (n1 * fsf_pixel_area_sheared_px(&px[i], grid) + extra);
        for (int ch = 0; ch < 3; ++ch) {
            float *v = value4 + 4 * i + (size_t)ch;
            *v += w_mean * (mean4[4 * i + (size_t)ch] - *v);
        }
    }
}
