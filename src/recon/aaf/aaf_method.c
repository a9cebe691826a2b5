/* Axis-aligned filtering (AAF-shadow, AAF-GI, defocus AAF) as a reconstruction method
 * (recon/method.h).
 *
 *   pass 1   9 samples per pixel for soft shadows alone, 16 when indirect light or defocus is
 *            filtered, recording the shadow and bounce ray geometry (aaf_stats.h)
 *   plan     per effect: filter width beta and samples per pixel n (aaf_pixel_params.h); a
 *            pixel takes the most demanding effect's count
 *   filter   OpenCL (aaf_filter.h): direct light's visibility (the light divided by albedo
 *            and the unoccluded irradiance r(x)) and indirect irradiance in world space, the
 *            composite radiance in pixels for defocus */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/aaf/aaf_filter.h"
#include "recon/aaf/aaf_light_sweep.h"
#include "recon/aaf/aaf_params.h"
#include "recon/aaf/aaf_pixel_params.h"
#include "recon/aaf/aaf_stats.h"
#include "recon/background.h"
#include "recon/method.h"
#include "recon/recon_parallel.h"

/* AAF-shadow Sec. 6: 9 light samples; AAF-GI Sec. 5: 16 hemisphere samples. Defocus uses 16
 * lens samples to see the pixel's range of depths. */
#define PASS1_SPP_SHADOWS 9
#define PASS1_SPP_OTHER 16
/* AAF-shadow Sec. 6: unoccluded pixels borrow from a 5 pixel radius. */
#define BORROW_RADIUS_PX 5
/* Pixels with no occluder (reflector) in their borrow window are filtered out to this radius
 * (2 beta) at mu <= 2, less where one is nearer (aaf_pixel_params.h). Visibility is 1 there,
 * and the unshadowed irradiance varies on the scale of the light's distance, far above 16
 * pixels; the radius stays within the filter's 32-pixel padding at any mu. */
#define FAR_RADIUS_PX 16
/* Filter taps up to 2 beta (95% of a Gaussian's mass; the rest is renormalised away). */
#define RADIUS_SIGMAS 2.0f
/* Mixed pixels (gbuffer.h: samples on different surfaces over the shutter or lens, which
 * includes antialiased silhouettes) are left out of the world-space filters and are plain
 * Monte Carlo; they get this many times mu times the pass-1 count (capped at 100 mu: 144 at
 * mu 2 with 9 in pass 1), so that their noise does not stand out against the filtered
 * neighbours and still falls as mu grows (consistency; with a fixed count they were the error
 * floor of the mu sweep on the soft-shadow bench scene). They are a few percent of the pixels
 * but, being unfiltered, the cheapest error to remove: going from 2 to 8 here cut the
 * soft-shadow bench scene's error by 29% for 10% more samples (docs/algorithms.md 4.1). */
#define MIXED_SPP_PER_MU 8.0f
/* Pixels whose unoccluded irradiance is below this fraction of the frame's largest (facing
 * away from the light, grazing) keep their own direct light: dividing by it is unstable. */
#define MIN_SHADE_REL 1.0e-3f

struct ReconMethod {
    const Renderer *renderer;
    const GBuffer *g;
    EffectMask effects;
    float mu_user;               /* > 0: every effect's mu; else each effect's default */
    AafShadowConfig shadow_cfg;
    AafIndirectConfig indirect_cfg;
    AafDefocusConfig defocus_cfg;
    AafLightGeom *lights;
    AafLightGeom *emitters;      /* r(x)'s, when a light moves (aaf_light_sweep.h); else NULL */
    AafStats stats;
    bool stats_ok;
    AafDerived derived;
    bool derived_ok;
    int pass1_spp;               /* the samples every pixel had when the first plan was made */
    float *beta[EFFECT_COUNT];   /* world (shadows, indirect) or pixels (defocus); NULL: off */
    float *beta_px[EFFECT_COUNT];/* the AOV layers: widths in pixels */
    int *spp_effect;
    float *param, *shade, *slope4;
    AafFilter *filter;
    bool guides_uploaded;        /* this reconstruction's guides are on the device */
    bool shading_guides;         /* those are the shading filters' (spos4, snrm4), not pos4, nrm4 */
};

static int aaf_pass1_spp(EffectMask effects)
{
    return effect_in(effects, EFFECT_INDIRECT) || effect_in(effects, EFFECT_DEFOCUS) ? PASS1_SPP_OTHER
                                                                                     : PASS1_SPP_SHADOWS;
}

static void aaf_destroy(ReconMethod *m)
{
    if (!m) return;
    aaf_filter_destroy(m->filter);
    if (m->derived_ok) aaf_derived_free(&m->derived);
    if (m->stats_ok) aaf_stats_free(&m->stats);
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        free(m->beta[e]);
        free(m->beta_px[e]);
    }
    free(m->spp_effect);
    free(m->param);
    free(m->shade);
    free(m->slope4);
    free(m->lights);
    free(m->emitters);
    free(m);
}

static bool aaf_create(const ReconSetup *s, ReconMethod **out, Diag *d)
{
    ReconMethod *m = calloc(1, sizeof *m);
    *out = NULL;
    if (!m) goto oom;
    m->renderer = s->renderer;
    m->g = s->gbuffer;
    m->effects = s->effects;
    m->mu_user = s->mu;
    m->shadow_cfg = aaf_shadow_config_default();
    m->indirect_cfg = aaf_indirect_config_default();
    m->defocus_cfg = aaf_defocus_config_default();
    m->defocus_cfg.black_background = recon_background_is_black(s->renderer);
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    m->stats_ok = aaf_stats_init(&m->stats, m->g);
    m->stats.collect_coc = effect_in(m->effects, EFFECT_DEFOCUS);
    m->spp_effect = malloc(n * sizeof(int));
    m->param = malloc(2 * n * sizeof(float));
    m->shade = malloc(n * sizeof(float));
    m->slope4 = malloc(4 * n * sizeof(float));
    if (!m->stats_ok || !m->spp_effect || !m->param || !m->shade || !m->slope4) goto oom;
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        if (!effect_in(m->effects, (Effect)e)) continue;
        m->beta[e] = calloc(n, sizeof(float));
        m->beta_px[e] = calloc(n, sizeof(float));
        if (!m->beta[e] || !m->beta_px[e]) goto oom;
    }
    int light_count = renderer_light_count(s->renderer);
    m->lights = calloc(light_count > 0 ? (size_t)light_count : 1, sizeof *m->lights);
    if (m->lights) {
        aaf_lights_from_renderer(s->renderer, m->lights, light_count);
        m->stats.lights = m->lights;
        m->stats.light_count = light_count;
        m->stats.emitter_count = aaf_light_sweep(s->renderer, m->lights, light_count, &m->emitters);
        m->stats.emitters = m->emitters;
    }
    *out = m;
    return true;
oom:
    aaf_destroy(m);
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for AAF buffers");
    return false;
}

static void aaf_begin_pass(ReconMethod *m, int pass)
{
    /* the parameters come from pass 1's ray geometry; later passes refine only the guides */
    m->stats.collect_rays = pass == 0;
    m->guides_uploaded = false;
}

static void aaf_add_sample(ReconMethod *m, int px, int py, const SampleRecord *r) { aaf_stats_add(&m->stats, px, py, r); }

static float effect_mu(const ReconMethod *m, Effect e, float mu)
{
    if (mu > 0.0f) return mu;
    if (m->mu_user > 0.0f) return m->mu_user;
    return e == EFFECT_SOFT_SHADOWS ? m->shadow_cfg.mu : e == EFFECT_INDIRECT ? m->indirect_cfg.mu : m->defocus_cfg.mu;
}

static bool aaf_plan(ReconMethod *m, float mu, const float *spp_now, int *spp_total, Diag *d)
{
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    if (!m->derived_ok) { /* the first plan: pass 1 just ended */
        if (!aaf_derive(&m->stats, &m->derived)) {
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for AAF statistics");
            return false;
        }
        m->derived_ok = true;
        m->pass1_spp = n ? (int)spp_now[0] : 0;
    }
    int pass1 = m->pass1_spp;
    for (size_t i = 0; i < n; ++i) spp_total[i] = pass1;
    AafPixelStats ps = aaf_derived_pixel_stats(&m->derived);
    float mu_max = 0.0f;
    for (int e = 0; e < EFFECT_COUNT; ++e) {
        if (!m->beta[e]) continue;
        float mu_e = effect_mu(m, (Effect)e, mu);
        mu_max = fmaxf(mu_max, mu_e);
        /* Far from any occluder/reflector: radius 2 beta up to FAR_RADIUS_PX (less near one,
         * aaf_pixel_params.h), shrinking with mu like every other width. */
        float far_beta_px = (float)FAR_RADIUS_PX / fmaxf(mu_e, 2.0f);
        /* Their light is still Monte Carlo (the unoccluded direct light of an area light,
         * indirect light from far away): from mu 2 on their samples grow faster than the
         * width shrinks, so that they too converge (the paper's fixed pass-1 count made them
         * the error floor of a mu sweep on the soft-shadow bench scene). */
        int far_spp = aaf_far_spp(pass1, mu_e);
        AafImageConfig ic = {BORROW_RADIUS_PX, pass1, 100.0f * mu_e, far_beta_px, far_spp};
        if (e == EFFECT_SOFT_SHADOWS) {
            AafShadowConfig c = m->shadow_cfg;
            c.mu = mu_e;
            aaf_shadow_params_image(&ps, &c, &ic, m->beta[e], m->spp_effect);
        } else if (e == EFFECT_INDIRECT) {
            AafIndirectConfig c = m->indirect_cfg;
            c.mu = mu_e;
            aaf_indirect_params_image(&ps, &c, &ic, m->g->scene_size_world, m->beta[e], m->spp_effect);
        } else if (e == EFFECT_DEFOCUS) {
            AafDefocusConfig c = m->defocus_cfg;
            c.mu = mu_e;
            aaf_defocus_params_image(&ps, &c, &ic, m->beta[e], m->spp_effect);
        } else {
            continue;
        }
        for (size_t i = 0; i < n; ++i) /* the pixel takes the most demanding effect's count */
            if (m->spp_effect[i] > spp_total[i]) spp_total[i] = m->spp_effect[i];
    }
    bool shadows_filtered = m->beta[EFFECT_SOFT_SHADOWS] != NULL;
    int mixed_spp = aaf_clamp_spp(MIXED_SPP_PER_MU * mu_max * (float)pass1, pass1, 100.0f * mu_max);
    /* glossy receivers keep their own direct light, and a texture edge's antialiasing is no
     * filter's (gbuffer.h): plain Monte Carlo, as mixed pixels; so are pixels a surface edge
     * may clip unseen (gbuffer_surface_step) */
    const float *lens_beta_px = m->beta[EFFECT_DEFOCUS];
    for (size_t i = 0; i < n; ++i) {
        bool texture_aa = gbuffer_texture_needs_samples(m->g, i, lens_beta_px ? lens_beta_px[i] : 0.0f);
        if ((m->g->mixed[i] || gbuffer_surface_step(m->g, i) || texture_aa || (shadows_filtered && m->g->glossy[i])) && mixed_spp > spp_total[i])
            spp_total[i] = mixed_spp;
    }
    return true;
}

static bool aaf_open_device(ReconMethod *m, ClRuntime *rt, Diag *d)
{
    m->filter = aaf_filter_create(rt, d);
    return m->filter && aaf_filter_reserve(m->filter, m->g->width, m->g->height, d);
}

/* shading: the light filters' guides (a split pixel's first surface, gbuffer.h), else the
 * pixels' own (the lens filter's); uploaded again only when the frame has split pixels and the
 * other set is asked for */
static bool upload_guides(ReconMethod *m, bool shading, Diag *d)
{
    bool same = m->g->spos4 == m->g->pos4;
    if (m->guides_uploaded && (same || m->shading_guides == shading)) return true;
    const float *pos4 = shading ? m->g->spos4 : m->g->pos4, *nrm4 = shading ? m->g->snrm4 : m->g->nrm4;
    m->guides_uploaded = aaf_filter_set_guides(m->filter, m->g->width, m->g->height, pos4, nrm4, d);
    m->shading_guides = shading;
    return m->guides_uploaded;
}

/* AAF-shadow eq. 1: the direct light is r(x) (the unoccluded irradiance) times the visibility,
 * and only the visibility is smooth enough to filter. */
static bool aaf_light_factor(ReconMethod *m, Effect e, const float **factor, float *min_factor, Diag *d)
{
    (void)d;
    *factor = NULL;
    *min_factor = 0.0f;
    if (e != EFFECT_SOFT_SHADOWS) return true;
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    aaf_unoccluded_irradiance(&m->derived, m->shade);
    float shade_max = 0.0f;
    for (size_t i = 0; i < n; ++i) shade_max = fmaxf(shade_max, m->shade[i]);
    *factor = m->derived.light_known ? m->shade : NULL;
    *min_factor = MIN_SHADE_REL * shade_max;
    return true;
}

typedef struct {
    const float *beta, *pixel_world;
    float *param;
} ParamsPass;

static void params_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    ParamsPass *pp = ctx;
    aaf_filter_make_params((int)(end - begin), pp->beta + begin, pp->pixel_world ? pp->pixel_world + begin : NULL,
                           RADIUS_SIGMAS, AAF_FILTER_RADIUS_CAP_PX, pp->param + 2 * begin);
}

/* aaf_filter_make_params on both cores. */
static void make_params(size_t n, const float *beta, const float *pixel_world, float *param)
{
    ParamsPass pp = {beta, pixel_world, param};
    recon_parallel_for(n, params_range, &pp);
}

static bool aaf_filter_light(ReconMethod *m, Effect e, float *value4, double *kernel_seconds, Diag *d)
{
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    if (!upload_guides(m, true, d)) return false;
    /* Direct light: distances in the plane of the light (AAF-shadow eq. 12); indirect light:
     * in each receiver's tangent plane (AAF-GI eq. 16). */
    AafFilterRules rules = aaf_filter_rules_default(AAF_DIST_WORLD);
    /* a neighbour with under half the centre's width holds sharper shadow (indirect) detail than
     * the centre's filter passes: the contact shadow at a thin occluder's foot inside the wide
     * penumbra of a high one (docs/algorithms.md 4) */
    rules.sharp_beta_ratio = 0.5f;
    make_params(n, m->beta[e], m->g->spixel_world, m->param);
    const float *plane4 = e == EFFECT_SOFT_SHADOWS ? m->derived.plane4 : NULL;
    return aaf_filter_run(m->filter, value4, plane4, m->param, &rules, value4, kernel_seconds, d);
}

/* Each pixel's sharpest CoC slope (the end of its range nearest 0; 0 if the range straddles
 * the focal plane): the kernel keeps sharper neighbours out of a blur, e.g. an in-focus
 * object's edge pixels out of the defocused background behind it. */
static void sharpest_slopes(const AafDerived *dv, size_t n, float *slope4)
{
    for (size_t i = 0; i < n; ++i) {
        float lo = dv->coc_min[i], hi = dv->coc_max[i];
        float sharp = (lo <= 0.0f && hi >= 0.0f) ? 0.0f : (fabsf(lo) < fabsf(hi) ? lo : hi);
        float *sl = slope4 + 4 * i;
        sl[0] = isfinite(sharp) && lo <= hi ? sharp : 0.0f;
        sl[1] = sl[2] = sl[3] = 0.0f;
    }
}

static bool aaf_filter_radiance(ReconMethod *m, EffectMask effects, float *value4, double *kernel_seconds, Diag *d)
{
    *kernel_seconds = 0.0;
    if (!effect_in(effects, EFFECT_DEFOCUS)) return true;
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    if (!upload_guides(m, false, d)) return false;
    sharpest_slopes(&m->derived, n, m->slope4);
    AafFilterRules rules = aaf_filter_rules_default(AAF_DIST_PIXEL);
    make_params(n, m->beta[EFFECT_DEFOCUS], NULL, m->param);
    return aaf_filter_run(m->filter, value4, m->slope4, m->param, &rules, value4, kernel_seconds, d);
}

static int aaf_shared(ReconMethod *m, DistArray *out, int max) { return aaf_stats_arrays(&m->stats, out, max); }

/* The filter widths in pixels, one layer per filtered effect: aaf.beta_px.<effect>. */
static int aaf_aovs(ReconMethod *m, ReconAov *out, int max)
{
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    int count = 0;
    for (int e = 0; e < EFFECT_COUNT && count < max; ++e) {
        if (!m->beta[e]) continue;
        const float *pw = e == EFFECT_DEFOCUS ? NULL : m->g->spixel_world;
        for (size_t i = 0; i < n; ++i) {
            float b = pw ? (pw[i] > 0.0f ? m->beta[e][i] / pw[i] : 0.0f) : m->beta[e][i];
            m->beta_px[e][i] = isfinite(b) ? b : (float)AAF_FILTER_RADIUS_CAP_PX;
        }
        ReconAov *a = &out[count++];
        snprintf(a->name, sizeof a->name, "aaf.beta_px.%s", effect_name((Effect)e));
        a->data = m->beta_px[e];
        a->unit = "filter width in pixels";
    }
    return count;
}

const ReconMethodClass recon_method_aaf = {
    .name = "aaf",
    .title = "axis-aligned filtering (AAF-shadow, AAF-GI, defocus AAF): per-pixel widths, adaptive samples",
    .effects = EFFECT_BIT(EFFECT_SOFT_SHADOWS) | EFFECT_BIT(EFFECT_DEFOCUS) | EFFECT_BIT(EFFECT_INDIRECT),
    .adaptive = true,
    .sample_fields = 0,
    /* defocus needs only each sample's depth: without shadows or indirect light the shadow
     * rays stay occlusion queries */
    .shadow_geometry = EFFECT_BIT(EFFECT_SOFT_SHADOWS), /* occluder distances (shadow parameters) */
    .bounce_geometry = EFFECT_BIT(EFFECT_INDIRECT),     /* reflector distances (indirect parameters) */
    .pass1_spp = aaf_pass1_spp,
    .create = aaf_create,
    .begin_pass = aaf_begin_pass,
    .add_sample = aaf_add_sample,
    .plan = aaf_plan,
    .open_device = aaf_open_device,
    .light_factor = aaf_light_factor,
    .filter_light = aaf_filter_light,
    .filter_radiance = aaf_filter_radiance,
    .shared = aaf_shared,
    .aovs = aaf_aovs,
    .destroy = aaf_destroy,
    .filters_split_pixels = true,
};
