/* Fast 4D sheared filtering (FSF, seeds/000) of soft shadows as a reconstruction method
 * (recon/method.h).
 *
 *   samples  a fixed count for the whole frame (16 per pixel, or --spp; FSF section 5 uses
 *            4-16 in one pass); the pipeline's per-sample store keeps each sample's shadow-ray
 *            geometry (light point, d_light, d_occ) and its direct light
 *   filter   the demodulated direct light: each sample's direct light scaled by its pixel's
 *            demodulation (the pipeline's value over the raw mean: albedo and the unoccluded
 *            irradiance r(x) divided out), filtered by the 4D sheared filter (fsf_filter.h)
 *            with per-pixel shear and widths (fsf_params.h): parameters on the host, the four
 *            passes in OpenCL (fsf_cl.h; fsf_filter_factored when no device was opened)
 *   AOVs     fsf.eta_m_per_px (the shear along the light's first axis, light metres per pixel
 *            step), fsf.sigma_px (the width along it), fsf.k_spread (k_hi - k_lo) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/fsf/fsf_cl.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/fsf/fsf_light.h"
#include "recon/fsf/fsf_params.h"
#include "recon/method.h"

/* FSF section 5: 4 to 16 samples per pixel; 16 = a 4 x 4 grid over the light. */
#define FSF_DEFAULT_SPP 16
/* Pixels whose unoccluded irradiance is below this fraction of the frame's largest keep their
 * own light (dividing by it is unstable), as with AAF. */
#define MIN_SHADE_REL 1.0e-3f

struct ReconMethod {
    const Renderer *renderer;
    const GBuffer *g;
    SampleStore *store;
    FsfLight light;
    float mu;
    FsfCl *cl;
    float *shade;                /* unoccluded irradiance (the light factor) */
    float *eta_aov, *sigma_aov, *spread_aov;
    long long nonfinite;         /* filtered pixels whose result was not finite (kept unfiltered) */
};

static int fsf_pass1_spp(EffectMask effects)
{
    (void)effects;
    return FSF_DEFAULT_SPP;
}

static void fsf_destroy(ReconMethod *m)
{
    if (!m) return;
    fsf_cl_destroy(m->cl);
    free(m->shade);
    free(m->eta_aov);
    free(m->sigma_aov);
    free(m->spread_aov);
    free(m);
}

static bool fsf_create(const ReconSetup *s, ReconMethod **out, Diag *d)
{
    *out = NULL;
    if (!s->store) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "FSF needs the per-sample store (none was given)");
        return false;
    }
    ReconMethod *m = calloc(1, sizeof *m);
    size_t n = (size_t)s->gbuffer->width * (size_t)s->gbuffer->height;
    if (m) {
        m->shade = calloc(n, sizeof(float));
        m->eta_aov = calloc(n, sizeof(float));
        m->sigma_aov = calloc(n, sizeof(float));
        m->spread_aov = calloc(n, sizeof(float));
    }
    if (!m || !m->shade || !m->eta_aov || !m->sigma_aov || !m->spread_aov) {
        fsf_destroy(m);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF buffers");
        return false;
    }
    if (!fsf_light_from_renderer(s->renderer, &m->light, d)) {
        fsf_destroy(m);
        return false;
    }
    m->renderer = s->renderer;
    m->g = s->gbuffer;
    m->store = s->store;
    m->mu = s->mu > 0.0f ? s->mu : 1.0f;
    *out = m;
    return true;
}

static bool fsf_open_device(ReconMethod *m, ClRuntime *rt, Diag *d)
{
    if (m->cl) return true;
    return (m->cl = fsf_cl_create(rt, d)) != NULL;
}

/* AAF-shadow eq. 1, as for AAF: only the visibility is smooth enough to filter, so the
 * direct light is divided by the unoccluded irradiance r(x) too. */
static bool fsf_light_factor(ReconMethod *m, Effect e, const float **factor, float *min_factor, Diag *d)
{
    (void)d;
    *factor = NULL;
    *min_factor = 0.0f;
    if (e != EFFECT_SOFT_SHADOWS) return true;
    int n = m->g->width * m->g->height;
    fsf_unoccluded_irradiance(m->renderer, n, m->g->hit, m->g->pos4, m->g->nrm4, m->shade);
    float shade_max = 0.0f;
    for (int i = 0; i < n; ++i) shade_max = fmaxf(shade_max, m->shade[i]);
    *factor = m->shade;
    *min_factor = MIN_SHADE_REL * shade_max;
    return true;
}

/* The store's samples as the filter's input: light coordinates along the light's axes and
 * each sample's direct light demodulated like its pixel's mean (value4 / raw mean). */
static bool gather(const ReconMethod *m, const float *value4, unsigned char *usable, float *y_m, float *v, int *count)
{
    const SampleStore *st = m->store;
    const float *lf = sample_store_field(st, SAMPLE_FIELD_LIGHT), *dir = sample_store_field(st, SAMPLE_FIELD_DIRECT);
    if (!lf || !dir) return false;
    int cap = sample_store_capacity(st);
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    vec3 c = m->light.centre_world, u = m->light.axis_world[0], w = m->light.axis_world[1];
    for (size_t i = 0; i < n; ++i) {
        int cnt = sample_store_count(st, i);
        count[i] = cnt;
        double mean[3] = {0, 0, 0};
        for (int k = 0; k < cnt; ++k)
            for (int ch = 0; ch < 3; ++ch) mean[ch] += dir[(i * (size_t)cap + (size_t)k) * 3 + (size_t)ch];
        float scale[3];
        for (int ch = 0; ch < 3; ++ch) {
            double s = mean[ch] > 0.0 ? value4[4 * i + (size_t)ch] * (double)cnt / mean[ch] : 0.0;
            scale[ch] = isfinite(s) ? (float)s : 0.0f;
        }
        usable[i] = value4[4 * i + 3] > 0.0f && cnt > 0 && m->g->hit[i] && !m->g->mixed[i];
        for (int k = 0; k < cnt; ++k) {
            size_t slot = i * (size_t)cap + (size_t)k;
            const float *s = lf + 5 * slot;
            vec3 q = v3_sub(v3(s[0], s[1], s[2]), c);
            /* a sample without a shadow ray (no light point): mid-light */
            bool has = s[3] > 0.0f;
            y_m[2 * slot] = has ? v3_dot(q, u) : 0.0f;
            y_m[2 * slot + 1] = has ? v3_dot(q, w) : 0.0f;
            for (int ch = 0; ch < 3; ++ch) {
                float val = dir[slot * 3 + (size_t)ch] * scale[ch];
                v[slot * 3 + (size_t)ch] = isfinite(val) ? val : 0.0f;
            }
        }
    }
    return true;
}

static bool fsf_filter_light(ReconMethod *m, Effect e, float *value4, double *kernel_seconds, Diag *d)
{

    *kernel_seconds = 0.0;
    if (e != EFFECT_SOFT_SHADOWS) return true;
    int w = m->g->width, h = m->g->height, cap = sample_store_capacity(m->store);
    size_t n = (size_t)w * (size_t)h, slots = n * (size_t)cap;
    unsigned char *usable = malloc(n);
    int *count = malloc(n * sizeof(int));
    /* at least one slot's floats: fsf_cl_run uploads one for an empty store */
    float *y_m = malloc((slots + 1) * 2 * sizeof(float)), *v = malloc((slots + 1) * 3 * sizeof(float));
    float *k_lo = malloc(n * sizeof(float)), *k_hi = malloc(n * sizeof(float)), *out4 = malloc(n * 4 * sizeof(float));
    FsfPixel *px = malloc(n * sizeof(FsfPixel));
    bool ok = usable && count && y_m && v && k_lo && k_hi && out4 && px;
    if (!ok) diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF buffers");
    if (ok && !gather(m, value4, usable, y_m, v, count)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "FSF: the per-sample store lacks the light or direct field");
    }
    FsfParamsIn in = {m->g, m->store, &m->light, usable, m->mu};
    if (ok && !fsf_pixel_params(&in, px, k_lo, k_hi)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF parameters");
    }
    FsfSamples s = {w, h, cap, count, y_m, v};
    FsfGrid grid = fsf_grid_default(m->light.half_m[0], m->light.half_m[1]);
    FsfGuides gd = fsf_guides_default(m->g->pos4, m->g->nrm4, usable);
    if (ok) {
        if (m->cl) {
            ok = fsf_cl_run(m->cl, &s, &grid, px, &gd, out4, kernel_seconds, d);
        } else if (!fsf_filter_factored(&s, &grid, px, &gd, out4)) {
            ok = false;
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF passes");
        }
    }
    for (size_t i = 0; ok && i < n; ++i) {
        m->eta_aov[i] = px[i].eta_m[0];
        m->sigma_aov[i] = px[i].sigma_px[0];
        m->spread_aov[i] = k_hi[i] - k_lo[i];
        if (!usable[i] || !(out4[4 * i + 3] > 0.0f)) continue;
        float r[3];
        bool finite = true;
        for (int ch = 0; ch < 3; ++ch) {
            r[ch] = out4[4 * i + (size_t)ch] / out4[4 * i + 3];
            finite = finite && isfinite(r[ch]);
        }
        if (!finite) { /* counted; the pixel keeps its unfiltered mean */
            m->nonfinite++;
            continue;
        }
        for (int ch = 0; ch < 3; ++ch) value4[4 * i + (size_t)ch] = r[ch];
    }
    if (ok && m->nonfinite > 0)
        fprintf(stderr, "wedge: warning: FSF: %lld pixels had a non-finite filtered value and kept their mean\n",
                m->nonfinite);
    free(usable), free(count), free(y_m), free(v), free(k_lo), free(k_hi), free(out4), free(px);
    return ok;
}

static int fsf_aovs(ReconMethod *m, ReconAov *out, int max)
{
    int count = 0;
    if (count < max) out[count++] = (ReconAov){"fsf.eta_m_per_px", m->eta_aov, "light metres per pixel step"};
    if (count < max) out[count++] = (ReconAov){"fsf.sigma_px", m->sigma_aov, "filter sigma in pixels"};
    if (count < max) out[count++] = (ReconAov){"fsf.k_spread", m->spread_aov, "slope spread (light m per receiver m)"};
    return count;
}

const ReconMethodClass recon_method_fsf = {
    .name = "fsf",
    .title = "fast 4D sheared filtering (FSF): soft shadows, per-sample store, four 1D passes, fixed samples (default 16)",
    .effects = EFFECT_BIT(EFFECT_SOFT_SHADOWS),
    .adaptive = false,
    .sample_fields = SAMPLE_FIELD_LIGHT | SAMPLE_FIELD_DIRECT,
    .ray_geometry = EFFECT_BIT(EFFECT_SOFT_SHADOWS),
    .pass1_spp = fsf_pass1_spp,
    .create = fsf_create,
    .open_device = fsf_open_device,
    .light_factor = fsf_light_factor,
    .filter_light = fsf_filter_light,
    .aovs = fsf_aovs,
    .destroy = fsf_destroy,
};
