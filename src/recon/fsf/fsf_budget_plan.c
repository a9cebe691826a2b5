/* FSF's plan under a --spp budget (fsf_budget_plan.h). */
#include "recon/fsf/fsf_budget_plan.h"

#include <math.h>
#include <stdlib.h>

#include "recon/fsf/fsf_bounce.h"
#include "recon/fsf/fsf_params.h"

bool fsf_pixel_collapsed(const FsfPixel *px)
{
    return px->sigma_px[0] < FSF_COLLAPSED_SIGMA_PX || px->sigma_px[1] < FSF_COLLAPSED_SIGMA_PX;
}

/* Per-pixel parameters and slope ranges of one effect's filter, for the plan only. */
typedef struct {
    FsfPixel *px;
    float *k_lo, *k_hi;
    unsigned char *usable;
} PlanParams;

static bool params_alloc(size_t n, PlanParams *p)
{
    p->px = malloc(n * sizeof(FsfPixel));
    p->k_lo = malloc(n * sizeof(float)), p->k_hi = malloc(n * sizeof(float));
    p->usable = malloc(n);
    return p->px && p->k_lo && p->k_hi && p->usable;
}

static void params_free(PlanParams *p)
{
    free(p->px), free(p->k_lo), free(p->k_hi), free(p->usable);
}

bool fsf_shadow_collapsed(const GBuffer *g, const SampleStore *st, const FsfLight *light, const float *share, float mu,
                          unsigned char *collapsed)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    PlanParams p;
    bool ok = params_alloc(n, &p);
    /* as fsf_method.c's gather, without the demodulated value (not known before compositing):
     * a pixel whose samples are all dark is filtered there but is no less noisy here */
    for (size_t i = 0; ok && i < n; ++i)
        p.usable[i] = sample_store_count(st, i) > 0 && g->hit[i] && !g->mixed[i];
    FsfParamsIn in = {g, st, light, p.usable, mu};
    ok = ok && fsf_pixel_params(&in, p.px, p.k_lo, p.k_hi);
    for (size_t i = 0; ok && i < n; ++i) {
        /* a surface the filter passes through: mixed (several surfaces), or most of its light
         * from another emitter */
        bool left = g->mixed[i] || (share && !(share[i] >= FSF_MIN_LIGHT_SHARE));
        if (sample_store_count(st, i) > 0 && g->hit[i] && (left || fsf_pixel_collapsed(&p.px[i]))) collapsed[i] = 1;
    }
    params_free(&p);
    return ok;
}

bool fsf_bounce_collapsed(const GBuffer *g, const SampleStore *st, float mu, unsigned char *collapsed)
{
    size_t n = (size_t)g->width * (size_t)g->height, slots = n * (size_t)sample_store_capacity(st);
    PlanParams p;
    /* the v-plane coordinates need a value to scale the samples to: any usable one will do */
    float *ones = malloc(n * 4 * sizeof(float)), *y = malloc((slots + 1) * 2 * sizeof(float));
    float *v = malloc((slots + 1) * 3 * sizeof(float));
    int *count = malloc(n * sizeof(int));
    bool ok = params_alloc(n, &p) && ones && y && v && count;
    for (size_t i = 0; ok && i < 4 * n; ++i) ones[i] = 1.0f;
    long long nonfinite = 0;
    ok = ok && fsf_bounce_samples(g, st, ones, p.usable, y, v, count, &nonfinite);
    FsfBounceIn in = {g, st, y, p.usable, mu, FSF_BOUNCE_PARALLAX_V, FSF_BOUNCE_H_MIN_FRAC};
    ok = ok && fsf_bounce_params(&in, p.px, p.k_lo, p.k_hi);
    for (size_t i = 0; ok && i < n; ++i)
        if (sample_store_count(st, i) > 0 && g->hit[i] && (g->mixed[i] || fsf_pixel_collapsed(&p.px[i])))
            collapsed[i] = 1;
    free(ones), free(y), free(v), free(count);
    params_free(&p);
    return ok;
}

void fsf_budget_plan(const unsigned char *collapsed, size_t n, int pass1_spp, int budget_spp, float ratio,
                     const float *spp_now, int *spp_total)
{
    double room = (double)budget_spp * (double)n;
    size_t n_collapsed = 0;
    for (size_t i = 0; i < n; ++i) {
        spp_total[i] = (int)spp_now[i];
        room -= spp_now[i];
        n_collapsed += collapsed[i] != 0;
    }
    if (!(room > 0.0)) return;
    /* n_c / n_1 = ratio at most (the equal-variance optimum); the rest evenly elsewhere */
    double per_collapsed = 0.0, cap = ((double)ratio - 1.0) * (double)pass1_spp;
    if (n_collapsed > 0) per_collapsed = fmin(cap > 0.0 ? cap : 0.0, room / (double)n_collapsed);
    size_t n_other = n - n_collapsed;
    double per_other = n_other > 0 ? (room - per_collapsed * (double)n_collapsed) / (double)n_other : 0.0;
    if (n_other == 0) per_collapsed = room / (double)n; /* every pixel collapsed: all of it evenly */
    double carry[2] = {0.0, 0.0}; /* per class, so that neither lends samples to the other */
    for (size_t i = 0; i < n; ++i) {
        int c = collapsed[i] != 0;
        double want = (c ? per_collapsed : per_other) + carry[c];
        int k = (int)floor(want + 0.5);
        if (k < 0) k = 0;
        carry[c] = want - k;
        spp_total[i] += k;
    }
}
