/* Multiple axis-aligned filters (MAAF, seeds/003) for soft shadows, indirect light and defocus,
 * as a reconstruction method (recon/method.h). docs/algorithms.md 9 (defocus: 9.8, indirect
 * light: 9.12).
 *
 *   samples  pass 1: 9 per pixel (the paper's count), recording the shadow-ray geometry; the
 *            plan adds most where the filter does not reach (silhouettes, contact shadows:
 *            maaf_plan), filtered pixels keep 9 at the default knob and grow with a budget;
 *            under a --spp budget the design itself is chosen from it (kappa_for_budget)
 *   sink     per pixel: AAF's shadow statistics (the wedge: d1, d2min, d2max, aaf_stats.h) and
 *            the complex sums of eq. 20 for each of the ((2N-1)^2 + 1)/2 components of the 4D
 *            filter (maaf_shadow.h), the light sample's position on the light giving the phase
 *   filter   the direct light divided by albedo and the unoccluded irradiance r(x) (as AAF),
 *            one image pass per axis with every component at once (maaf_filter.h)
 *
 * Defocus (maaf_defocus.h): per pixel the complex sums of each sample's radiance times the
 * lens-factor of its lens point; filter_radiance runs the same image pass on screen guides with
 * each pixel's design from pass 1's circle-of-confusion range. In a scene with shading effects a
 * sample's filterable direct and indirect light are replaced by albedo x its pixel's filtered
 * light (the sums of the rest and of the albedo are kept apart, section 9.8).
 *
 * Indirect light (maaf_indirect.h): per pixel the complex sums of each sample's indirect light
 * times the direction-factor of its bounce direction on the pixel's v-plane; filter_light runs
 * the same image pass with the receiver guides and each pixel's design from its reflector
 * heights (the wedge [h_min, h_max], AAF-GI's z).
 *
 * Motion stays Monte Carlo with --filter maaf. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/zalloc.h"
#include "recon/aaf/aaf_light_sweep.h"
#include "recon/aaf/aaf_params.h"
#include "recon/aaf/aaf_pixel_params.h"
#include "recon/aaf/aaf_stats.h"
#include "recon/composite.h"
#include "recon/maaf/maaf_defocus.h"
#include "recon/maaf/maaf_far_reach.h"
#include "recon/maaf/maaf_filter.h"
#include "recon/maaf/maaf_indirect.h"
#include "recon/maaf/maaf_lights.h"
#include "recon/maaf/maaf_shadow.h"
#include "recon/method.h"
#include "recon/sample_rate.h"

/* seeds/003 Sec. 6.1 and Fig. 9: 9 samples per pixel for soft shadows. */
#define MAAF_SPP_DEFAULT 9
/* The filter knob (--mu): the whole design scaled by it, Omega_y_max = kappa 2 / sigma_light,
 * so every primal width shrinks as 1/kappa (consistency: kappa -> infinity is Monte Carlo).
 * 1 is the paper's; 4 had the lowest error at 9 and 36 spp on the soft-shadow bench scene
 * (docs/algorithms.md 9.7). */
#define MAAF_KAPPA_DEFAULT 4.0f
/* seeds/003 Sec. 6.2 "Pre-filtering": slopes are taken over a 5 x 5 window. Pixels whose
 * window saw no occluder borrow from this radius (AAF-shadow Sec. 6's 5 pixels). */
#define SLOPE_WINDOW_PX 2
#define BORROW_RADIUS_PX 5
/* No reflector within BORROW_RADIUS_PX: the indirect light is filtered with a plain Gaussian
 * of this std (pixels, at the default knob); the shadows' far filter never narrower. */
#define FAR_STD_PX 2.0f
/* The reach of a shadow filter (pixels), below the design's 2 central stds (MAAF_RADIUS_CAP_PX
 * for defocus): the wedge is measured over a 5 x 5 window, and a filter reaching much further
 * assumes it holds where it was not measured. At 64 spp the central std was 9 px (AAF's beta
 * 3.7): caps of 32 / 20 / 12 / 8 / 4 px gave 5.7 / 5.5 / 5.0 / 4.8 / 4.5e-5 on soft_shadows, 8
 * was the best over 16-256 spp there and on thin_occluders (docs/algorithms.md 9.11). The
 * weights are normalised (the 4th channel), so a truncated filter stays unbiased on a constant. */
#define SHADOW_RADIUS_CAP_PX 8.0f
/* The same for the indirect filter (its wedge is measured over the same window). */
#define INDIRECT_RADIUS_CAP_PX 8.0f
/* No occluder within BORROW_RADIUS_PX: visibility is 1 there, and the unshadowed light is
 * filtered with a plain Gaussian whose reach (2 stds, maaf_pixel_param_plain's radius) is the
 * pixel's window free of occluders and of pixels whose albedo varies (maaf_far_reach.h), at most
 * the shadow filters' reach and at least FAR_STD_PX's, at the default knob: std 2 to 4 px. Any
 * width is unbiased over pixels that saw no occluder and whose demodulation is exact, and the
 * widest has the least variance; the fixed 2 px std left the plain pixels' variance ~9x their
 * bias^2 on combined.pbrt (docs/algorithms.md 9.27). */
#define FAR_STD_PER_REACH 0.5f
/* Pixels whose unoccluded irradiance is below this fraction of the frame's largest keep their
 * own direct light (as AAF: dividing by it is unstable). */
#define MIN_SHADE_REL 1.0e-3f
/* Normal rejection: seeds/003 uses 20 degrees, AAF 15; depth tolerance as AAF's. */
#define COS_NORMAL_MIN 0.93969262f
#define DEPTH_TOL_REL 0.05f
/* The plan (maaf_plan): extra samples where the filter does not reach */
#define EXTRA_SPP_PER_MU 8.0f
#define UNFILTERED_STD_PX 0.5f
#define MAAF_PLAN_MU_DEFAULT 2.0f

/* Set (to anything but "0"): every sample goes into every sum, none skipped as unread and the
 * albedo sums accumulated everywhere, as before these savings; test_maaf_sums compares. */
#define MAAF_ALL_SUMS_ENV "WEDGE_MAAF_ALL_SUMS"

/* The knob for a --spp budget (docs/algorithms.md 9.11). The design is fixed before pass 1
 * (eq. 20's sums are taken with it) and cannot follow the budget search's mu, so a budget sets
 * it up front. With the default design a budget only lowered the variance and the design's
 * bias held the error from 16 spp up (soft_shadows 256x256: 4.0e-4 at 16, 4.1e-4 at 32 and
 * 128). Without --mu, kappa stays at the default up to base_spp, then grows as the square root of the
 * budget: the band widens while the samples under a filter stay about constant. */
static float kappa_for_budget(const ReconSetup *s, float kappa_default, int base_spp)
{
    if (s->mu > 0.0f) return s->mu; /* --mu is kappa itself */
    if (s->spp_budget <= base_spp) return kappa_default;
    return kappa_default * sqrtf((float)s->spp_budget / (float)base_spp);
}

/* With shading effects the lens filter sees their filtered light (split sums), and its design
 * kept its best to higher budgets: on combined.pbrt lens kappa 3 was best at 64 spp and 6-12 at
 * 256; alone, on defocus.pbrt, 3-4 at 16, 8 at 64 and 12-16 at 256 (docs/algorithms.md 9.11). */
#define LENS_SPLIT_BASE_SPP 36
/* The indirect design's base when the lens filter blurs its output again (the split sums of
 * 9.8): it narrows sooner. combined.pbrt, 256x256, 16 / 32 spp: relMSE -5% / -4% against base 9
 * (kappa 6 / 8.5 instead of 4 / 5.7); all_effects (not used for the choice) within 0.5%.
 * Alone the base stays 9: on indirect.pbrt base 36 had 10-20% less error at 16-64 spp, but
 * on motion_shading (held out) 9% more at 64 (docs/benchmarks.md, "MAAF on the combined scene,
 * cheaper"). */
#define INDIRECT_SPLIT_BASE_SPP 4

/* Per-pixel x-filters kept between calls: the plan runs once per mu of the budget search
 * (pipeline.c's mu_for_budget: up to 14 times) and the filter once more, and a pixel's filter
 * does not depend on mu, only on pass 1's statistics (derived once) and, for shadows, on the
 * guides (pixel_world), which pass 2 refines: maaf_begin_pass forgets the shadows' filters. */
typedef struct {
    float *param;          /* MAAF_PARAM_STRIDE per pixel */
    float *std_px, *aux;   /* the central std in pixels; shadows: components, defocus: side */
    unsigned char *known;  /* 1: the pixel's entries are set */
} FilterCache;

struct ReconMethod {
    const Renderer *renderer;
    const GBuffer *g;
    EffectMask effects;
    float kappa;                /* the filter knob (MAAF_KAPPA_DEFAULT) */
    /* N per 2D subspace (MaafPairs) and the complex sums per pixel it takes */
    int light_pairs, light_comps; /* the light's axes: ysum */
    int lens_pairs, lens_comps;   /* the lens's: dsum, asum */
    int bounce_pairs;             /* the bounce direction's (its sums are plain: isum) */
    AafLightGeom *geoms;
    AafLightGeom *emitters;      /* r(x)'s, when a light moves (aaf_light_sweep.h); else NULL */
    MaafLight *lights;
    const MaafLight *first_light; /* the first area light: for samples without a shadow ray */
    int light_count;
    AafStats stats;
    bool stats_ok;
    AafDerived derived;
    bool derived_ok;
    int pass1_spp;              /* the samples every pixel had when the first plan was made */
    float *ysum;                /* light_comps * 8 per pixel (eq. 20) */
    float *frame4;              /* the pixel's light axis t1 (its first shadow ray's light), w: FRAME_FROM_* once set */
    float *axis2;               /* and t2 */
    float *guide4;              /* frame4 with w = usable, per filter run */
    float *out4, *shade;
    float *std_px, *components; /* AOVs */
    FilterCache shadow_cache, defocus_cache, indirect_cache;
    /* pixel_wedge's windows, from pass 1's statistics once (wedge_windows): per window radius
     * (SLOPE_WINDOW_PX, BORROW_RADIUS_PX) and pixel the extreme slopes, and whether any pixel
     * there saw an occluder */
    float *wedge_lo[2], *wedge_hi[2];
    unsigned char *wedge_found[2];
    unsigned char *far_reach_px; /* and the occluder-free window's radius (maaf_far_reach.h) */
    MaafFilter *filter;
    long long nonfinite_samples;
    /* per pixel, after the first plan: which of its sums no filter will read (UNREAD_*), so
     * that later passes' samples skip them (mark_unread_sums) */
    unsigned char *unread;
    /* the plan's rule per pixel, without mu (plan_classes), kept across the budget search's
     * plans and forgotten by every later pass */
    unsigned char *plan_class;
    float *plan_factor;         /* PLAN_RATE: the count's factor against pass 1's (recon/sample_rate.h) */
    float *lum4;                /* rate_planned frames: pass 1's luminance moments per pixel (sample_rate_add) */
    bool plan_known;
    bool all_sums;              /* MAAF_ALL_SUMS_ENV: every sum accumulated (the tests' reference) */
    /* defocus (maaf_defocus.h) */
    bool defocus;
    bool split_direct, split_indirect; /* the scene has soft shadows / indirect light: that
                                        * filterable light is left out of dsum, asum is kept */
    MaafLens lens;
    float *dsum;                /* lens_comps * 8 per pixel: radiance minus the split lights */
    float *asum;                /* split: the same sums of the albedo, only where it varies
                                 * inside the pixel (ALBEDO_SUMS_*; unwritten elsewhere) */
    float *albedo4;             /* split: the pixel's first sample's albedo (0 for a miss) and
                                 * its state (w: ALBEDO_SUMS_*) */
    float *dpos4, *dnrm4, *daxis2; /* screen guides */
    float *dstd_px, *dcomponents;  /* AOVs */
    float *coc_pool;            /* 2 per pixel (w x h minima, then maxima): maaf_coc_pool of pass 1's ranges */
    const float *direct4, *direct_factor, *indirect4; /* the shading filters' output (shading_light) */
    /* indirect light (maaf_indirect.h) */
    bool indirect;
    float ikappa;               /* its knob: Omega_v_max = ikappa MAAF_INDIRECT_OMEGA_V */
    MaafLens dirs;              /* the design's band and expectations (no table: indirect_add) */
    float *isum;                /* 4 per pixel: the plain sum of the filterable indirect light */
    float *iframe4, *iaxis2;    /* the pixel's tangent axes t1 (w: 1 once set) and t2 (n = t1 x t2) */
    float *istd_px, *icomponents; /* AOVs */
    /* pixel_heights' terms per pixel (reflector_heights): pass 1's z_min and z_max, NaN where
     * it saw no reflector */
    float *height_lo, *height_hi;
    bool height_made;
    float *indirect_spp;        /* the count each indirect_cache entry was made for */
};

/* Frames whose plan is the Lagrange allocation (recon/sample_rate.h, docs/algorithms.md 9.14,
 * 9.20): those with defocus, and those whose only filtered effect is soft shadows. Frames with
 * indirect light but no defocus keep the plan's classes (their bounce filter was not measured
 * under the allocation). */
static bool rate_planned(EffectMask effects)
{
    if (effect_in(effects, EFFECT_DEFOCUS)) return true;
    return effect_in(effects, EFFECT_SOFT_SHADOWS) && !effect_in(effects, EFFECT_INDIRECT);
}

static int maaf_pass1_spp(EffectMask effects)
{
    (void)effects;
    return MAAF_SPP_DEFAULT;
}

/* Under a --spp budget, frames with the Lagrange allocation (rate_planned: defocus, or soft
 * shadows alone) trace half of it in pass 1 and let the plan's
 * Lagrange allocation (recon/sample_rate.h) place the other half: pass 1 is the allocation's pilot
 * (it measures each pixel's variance and wedges) and its floor, and only the samples above
 * the floor can follow sqrt(v / A). With pass 1 fixed at 9 a budget of 8 had no plan at all
 * and one of 12 a quarter of the budget to place. Half is the usual two-stage split, not
 * fitted (0.4 and 0.7 were each worse at some budgets); against pass 1 = 9 (256x256, seeds
 * 1-3, relMSE): combined 8 / 16 / 32 spp 1.24e-3 / 3.30e-4 / 2.12e-4 -> 6.9e-4 / 3.23e-4 /
 * 1.98e-4 (12 spp +3%), defocus 4.06e-4 / 1.18e-4 / 6.9e-5 -> 2.37e-4 / 1.13e-4 / 7.1e-5
 * (docs/algorithms.md 9.14). At 32 spp pass 1 is 16, seeds/003's own initial count. On
 * soft_shadows (9.20) it also puts more samples under the shadow ray geometry that pass 2
 * does not record. The other frames keep pass 1's 9 (their plan is the classes'). */
#define DEFOCUS_BUDGET_PASS1_SHARE 0.5f
/* Frames whose only MAAF effect is defocus: pass 1 is a third of the budget rounded to an even
 * count, at least 4 and at most 8, and never more than the half (3 at budgets of 5 and 6). There
 * pass 1's products are the pilot variance and the circle-of-confusion ranges, which the pool of
 * 4-neighbours (maaf_coc_pool) makes hold with a few samples; each sample more in the uniform
 * pilot is one the allocation does not place: in issue 16's sweep (docs/algorithms.md 9.25;
 * defocus.pbrt, 256x256, seeds 1-3, relMSE) a larger pilot lowered bias^2 and raised the
 * variance, and the old min(half, 8) lost at 12-16 spp: 12 / 14 / 15 / 16 spp took 6 / 7 / 8 / 8
 * at 1.30e-4 / 1.17e-4 / 1.13e-4 / 1.07e-4, the rule's 4 / 4 / 6 / 6 give 1.23e-4 / 1.10e-4 /
 * 1.06e-4 / 1.02e-4; at 20-32 spp 6-8 tie and 8 wins at 32 (9.21: 8 beat the half's 16 there).
 * Even: the stratified sampler lays a pass's n samples on a rows x cols grid, and odd n is a
 * 1 x n strip (9.24). Frames with soft shadows or indirect light keep the half: pass 1 alone
 * records their ray geometry (9.21). */
#define DEFOCUS_ALONE_PASS1_MIN_SPP 4
#define DEFOCUS_ALONE_PASS1_MAX_SPP 8
static float defocus_alone_pass1_spp(int budget)
{
    int pass1 = 2 * (int)lroundf((float)budget / 6.0f);
    if (pass1 < DEFOCUS_ALONE_PASS1_MIN_SPP) pass1 = DEFOCUS_ALONE_PASS1_MIN_SPP;
    if (pass1 > DEFOCUS_ALONE_PASS1_MAX_SPP) pass1 = DEFOCUS_ALONE_PASS1_MAX_SPP;
    return (float)pass1;
}
/* Frames with defocus and soft shadows or indirect light: pass 1 at least 8 samples at budgets
 * under 16, where the half gave it 4-7. Pass 1's products (each pixel's pilot variance, the
 * shadow wedges and the circle-of-confusion ranges) come from its samples alone, and the plan
 * leaves most pixels at pass 1's count: on combined.pbrt at 12 spp the pixels at that count
 * (43%) went from relMSE 2.06e-4 to 1.27e-4 with pass 1 at 8 instead of 6, bias and variance
 * alike, more than two more samples give a plain mean (docs/algorithms.md 9.23). 8 is the
 * defocus-alone cap's count above. The plan keeps at least a quarter of the budget: with none
 * (pass 1 = 8 at 8 spp) the silhouettes and the focal plane's straddlers had no samples to take
 * and the error was 1.8x. */
#define SHADED_DEFOCUS_PASS1_MIN_SPP 8.0f
#define PLAN_MIN_BUDGET_SHARE 0.25f
/* Frames whose only MAAF effect is soft shadows: pass 1 is the largest even count that leaves the
 * plan at least 3 samples a pixel, at most 8 and at least the power of two at or above half the
 * budget (capped at 4: 1, 2, 4 at budgets of 1-2, 3-4, 5-8). Beyond 8 a larger pilot only takes
 * samples from the Lagrange allocation, which places the samples above it (the narrow shadow
 * filters need 5-10x the wide ones' counts); below half the budget the pilot's variance and
 * wedges are poor. It was at least the paper's 9 until issue 16's sweep (docs/algorithms.md 9.24;
 * soft_shadows, 256x256, seeds 1-3, relMSE): at a budget of 8 the old floor traced 9 (over the
 * budget, no plan: 7.9e-4), pass 1 of 4 gives 1.8e-4; at 16, 7 / 8 / 9 / 10 gave 8.4e-5 / 6.8e-5
 * / 7.7e-5 / 8.3e-5; at 24, 8 / 12 / 16 gave 4.6e-5 / 5.0e-5 / 5.3e-5. The power of two at or
 * above half, at most 8, ran 9 as 8 + 1 and 10 as 8 + 2, worse than 8 spp's 4 + 4 (a higher
 * budget, a worse image): the second sweep (after the lattice sampler, soft_shadows against
 * 4096 spp, thin_occluders, tilted_stack, seeds 1-3, pass 1 of 4-8, mean relMSE) found 6 best
 * at 9 and 10 but for tilted_stack at 10 (soft_shadows 1.40e-4 / 1.23e-4 against 8's 2.11e-4 /
 * 1.43e-4, thin_occluders 7.8e-4 / 6.7e-4 against 1.10e-3 / 8.2e-4; tilted_stack 3.1e-4 /
 * 2.7e-4 against 3.2e-4 / 2.6e-4), 8 best or within 4% from 12 and about tied at 11 (6 or 7 gain 2-8% on
 * soft_shadows and thin_occluders, lose 5-15% on tilted_stack). Odd pilots (5, 7) lost to 6.
 * Held out, textured_glossy at 9 / 10: 2.8e-3 / 2.4e-3 against 8's 4.0e-3 / 3.0e-3. Against it,
 * test_maaf_pipeline's 40x40 penumbra, bias-bound, wants the larger pilot's wedges: 6 + 3 gives
 * 2.45e-3 there, 8 + 1 1.63e-3 (both below 8 spp's 2.59e-3). */
#define SHADOW_ALONE_PASS1_MAX_SPP 8
#define SHADOW_ALONE_PASS1_HALF_CAP_SPP 4
#define SHADOW_ALONE_PLAN_MIN_SPP 3
static float shadow_alone_pass1_spp(int budget)
{
    int half_pow2 = 1;
    while (half_pow2 < SHADOW_ALONE_PASS1_HALF_CAP_SPP && 2 * half_pow2 < budget) half_pow2 *= 2;
    int pass1 = budget - SHADOW_ALONE_PLAN_MIN_SPP;
    pass1 -= pass1 > 0 ? pass1 % 2 : 0;
    if (pass1 < half_pow2) pass1 = half_pow2;
    if (pass1 > SHADOW_ALONE_PASS1_MAX_SPP) pass1 = SHADOW_ALONE_PASS1_MAX_SPP;
    return (float)pass1;
}
static float maaf_budget_pass1_share(const Renderer *r, EffectMask effects)
{
    int budget = renderer_spp(r);
    if (budget <= 0) return DEFOCUS_BUDGET_PASS1_SHARE;
    if (effect_in(effects, EFFECT_DEFOCUS)) {
        bool shaded = effect_in(effects, EFFECT_SOFT_SHADOWS) || effect_in(effects, EFFECT_INDIRECT);
        if (!shaded) return fminf(DEFOCUS_BUDGET_PASS1_SHARE, defocus_alone_pass1_spp(budget) / (float)budget);
        return fmaxf(DEFOCUS_BUDGET_PASS1_SHARE,
                     fminf(SHADED_DEFOCUS_PASS1_MIN_SPP / (float)budget, 1.0f - PLAN_MIN_BUDGET_SHARE));
    }
    if (rate_planned(effects)) return shadow_alone_pass1_spp(budget) / (float)budget;
    return (float)MAAF_SPP_DEFAULT / (float)budget;
}

static bool cache_init(FilterCache *c, size_t n)
{
    /* zeros where no filter was asked: the light passes read every pixel's entry (an unusable
     * pixel's is read but not used), and calloc's pages that are only read cost no fault */
    c->param = calloc(n * MAAF_PARAM_STRIDE, sizeof(float));
    c->std_px = malloc(n * sizeof(float));
    c->aux = malloc(n * sizeof(float));
    c->known = calloc(n, 1);
    return c->param && c->std_px && c->aux && c->known;
}

static void cache_free(FilterCache *c)
{
    free(c->param);
    free(c->std_px);
    free(c->aux);
    free(c->known);
}

static void maaf_destroy(ReconMethod *m)
{
    if (!m) return;
    cache_free(&m->shadow_cache);
    cache_free(&m->defocus_cache);
    cache_free(&m->indirect_cache);
    maaf_lens_free(&m->dirs);
    free(m->isum);
    free(m->iframe4);
    free(m->iaxis2);
    free(m->istd_px);
    free(m->height_lo);
    free(m->height_hi);
    free(m->indirect_spp);
    free(m->icomponents);
    maaf_filter_destroy(m->filter);
    if (m->derived_ok) aaf_derived_free(&m->derived);
    if (m->stats_ok) aaf_stats_free(&m->stats);
    for (int k = 0; k < 2; ++k) free(m->wedge_lo[k]), free(m->wedge_hi[k]), free(m->wedge_found[k]);
    free(m->far_reach_px);
    free(m->geoms);
    free(m->emitters);
    free(m->lights);
    free(m->unread);
    free(m->coc_pool);
    free(m->plan_class);
    free(m->plan_factor);
    free(m->lum4);
    free(m->ysum);
    free(m->frame4);
    free(m->axis2);
    free(m->guide4);
    free(m->out4);
    free(m->shade);
    free(m->std_px);
    free(m->components);
    maaf_lens_free(&m->lens);
    free(m->dsum);
    free(m->asum);
    free(m->albedo4);
    free(m->dpos4);
    free(m->dnrm4);
    free(m->daxis2);
    free(m->dstd_px);
    free(m->dcomponents);
    free(m);
}

static bool maaf_create(const ReconSetup *s, ReconMethod **out, Diag *d)
{
    ReconMethod *m = calloc(1, sizeof *m);
    *out = NULL;
    if (!m) goto oom;
    m->renderer = s->renderer;
    m->g = s->gbuffer;
    m->effects = s->effects;
    m->kappa = kappa_for_budget(s, MAAF_KAPPA_DEFAULT, MAAF_SPP_DEFAULT);
    const char *all = getenv(MAAF_ALL_SUMS_ENV);
    m->all_sums = all && *all && strcmp(all, "0") != 0;
    /* method_options: [0] --maaf-pairs (every subspace), [1..3] the light's, lens's, bounce's */
    const int *opt = s->method_options;
    MaafPairs pairs = maaf_pairs_choose(opt[0], opt[1], opt[2], opt[3]);
    m->light_pairs = pairs.light;
    m->lens_pairs = pairs.lens;
    m->bounce_pairs = pairs.bounce;
    m->light_comps = maaf_component_count(m->light_pairs);
    m->lens_comps = maaf_component_count(m->lens_pairs);
    size_t n = (size_t)m->g->width * (size_t)m->g->height, per = (size_t)m->light_comps * 8, lens_per = (size_t)m->lens_comps * 8;
    m->stats_ok = aaf_stats_init(&m->stats, m->g);
    /* the shadow sums only when shadows are filtered here (each image pass's input is written
     * into the pass's own planes, band by band: light_fill, radiance_fill) */
    bool shadows = effect_in(m->effects, EFFECT_SOFT_SHADOWS);
    EffectMask scene = renderer_effects(s->renderer);
    m->defocus = effect_in(m->effects, EFFECT_DEFOCUS);
    m->split_direct = m->defocus && effect_in(scene, EFFECT_SOFT_SHADOWS);
    m->split_indirect = m->defocus && effect_in(scene, EFFECT_INDIRECT);
    bool split = m->split_direct || m->split_indirect;
    m->indirect = effect_in(m->effects, EFFECT_INDIRECT);
    /* the sums of eq. 20, accumulated by the sampling threads: zalloc's pages are written
     * before they start (zalloc.h; as callocs, 14% of a combined.pbrt frame at 16 spp went to
     * copy-on-write faults under maaf_lens_accumulate and accumulate) */
    m->ysum = shadows ? zalloc(n * per, sizeof(float)) : NULL;
    /* written by the sampling threads too (each pixel's axes, at its first shadow ray), after a
     * read of the flag: as callocs each page took a read fault and then a copy-on-write one */
    m->frame4 = zalloc(4 * n, sizeof(float));
    m->axis2 = zalloc(4 * n, sizeof(float));
    m->guide4 = malloc(4 * n * sizeof(float));
    m->out4 = malloc(4 * n * sizeof(float));
    m->shade = malloc(n * sizeof(float));
    m->std_px = calloc(n, sizeof(float));
    m->components = calloc(n, sizeof(float));
    m->light_count = renderer_light_count(s->renderer);
    size_t lights = m->light_count > 0 ? (size_t)m->light_count : 1;
    m->geoms = calloc(lights, sizeof *m->geoms);
    m->lights = calloc(lights, sizeof *m->lights);
    if (!m->stats_ok || (shadows && !m->ysum) || (shadows && !cache_init(&m->shadow_cache, n)) || !m->frame4 || !m->axis2 || !m->guide4 || !m->out4 || !m->shade ||
        !m->std_px || !m->components || !m->geoms || !m->lights)
        goto oom;
    if (rate_planned(m->effects) && !(m->lum4 = zalloc(4 * n, sizeof(float)))) goto oom;
    if (m->defocus) {
        m->dsum = zalloc(n * lens_per, sizeof(float));
        /* asum's rows are written whole when a pixel's albedo first varies (albedo_add): not
         * zeroed, and the pages of pixels of one albedo are never touched */
        m->asum = split ? malloc(n * lens_per * sizeof(float)) : NULL;
        m->albedo4 = split ? zalloc(4 * n, sizeof(float)) : NULL;
        m->dpos4 = malloc(4 * n * sizeof(float));
        m->dnrm4 = malloc(4 * n * sizeof(float));
        m->daxis2 = malloc(4 * n * sizeof(float));
        m->dstd_px = calloc(n, sizeof(float));
        m->dcomponents = calloc(n, sizeof(float));
        if (!m->dsum || (split && (!m->asum || !m->albedo4)) || !cache_init(&m->defocus_cache, n) || !m->dpos4 || !m->dnrm4 || !m->daxis2 || !m->dstd_px ||
            !m->dcomponents)
            goto oom;
        float lens_kappa = kappa_for_budget(s, MAAF_DEFOCUS_KAPPA_DEFAULT, split ? LENS_SPLIT_BASE_SPP : MAAF_SPP_DEFAULT);
        if (!maaf_lens_design(lens_kappa, m->lens_pairs, &m->lens)) goto oom;
    }
    if (m->indirect) {
        m->isum = zalloc(n * 4, sizeof(float));
        m->iframe4 = zalloc(4 * n, sizeof(float)); /* as frame4 */
        m->iaxis2 = zalloc(4 * n, sizeof(float));
        m->istd_px = calloc(n, sizeof(float));
        m->icomponents = calloc(n, sizeof(float));
        m->height_lo = malloc(n * sizeof(float));
        m->height_hi = malloc(n * sizeof(float));
        m->indirect_spp = malloc(n * sizeof(float));
        if (!m->isum || !m->iframe4 || !m->iaxis2 || !m->istd_px || !m->icomponents || !m->height_lo || !m->height_hi ||
            !m->indirect_spp ||
            !cache_init(&m->indirect_cache, n))
            goto oom;
        m->ikappa = kappa_for_budget(s, MAAF_INDIRECT_KAPPA_DEFAULT, m->split_indirect ? INDIRECT_SPLIT_BASE_SPP : MAAF_SPP_DEFAULT);
        maaf_direction_means(m->ikappa, m->bounce_pairs, &m->dirs);
    }
    aaf_lights_from_renderer(s->renderer, m->geoms, m->light_count);
    m->stats.lights = m->geoms;
    m->stats.light_count = m->light_count;
    m->stats.emitter_count = aaf_light_sweep(s->renderer, m->geoms, m->light_count, &m->emitters);
    m->stats.emitters = m->emitters;
    if (!maaf_lights_from_renderer(s->renderer, m->geoms, m->light_count, m->light_pairs, m->kappa, m->lights)) goto oom;
    for (int l = m->light_count - 1; l >= 0; --l)
        if (m->lights[l].omega_y_max > 0.0f) m->first_light = &m->lights[l];
    *out = m;
    return true;
oom:
    maaf_destroy(m);
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for MAAF buffers");
    return false;
}

static float defocus_filter(ReconMethod *m, int x, int y, float *side);

/* Sums that no filter reads (bits of ReconMethod.unread) */
#define UNREAD_LENS 1u   /* dsum, asum: the pixel has no lens filter */
#define UNREAD_LIGHT 2u  /* ysum: the pixel's direct light is passed through unfiltered */

/* After the first plan (pass 1's statistics, on the rank that planned): the pixels whose sums
 * the image passes will never read, so that the later passes' samples (the plan's extra ones,
 * most of them at silhouettes and near the focal plane) skip their 13 complex components.
 * The pass reads a pixel's sums only where it is the centre of a filter or a neighbour in
 * one, and both need a radius > 0 and the pixel's usable flag (maaf.cl: centre_load, tap_lanes;
 * the C reference alike). A lens filter depends on pass 1's circle-of-confusion ranges alone
 * (derived once, cached): radius 0 there stays 0. The light filter's usable flag is composite.c's
 * (value4): never set on a pixel whose samples saw another object, missed all geometry,
 * hit an unfilterable surface, and each of those, once seen, stays true with more samples
 * (gbuffer.c's mixed rule; its normal and depth spreads can change back,
 * and are left out here). So the images are the same as with every sum accumulated. */
static void mark_unread_sums(ReconMethod *m)
{
    const GBuffer *g = m->g;
    size_t n = (size_t)g->width * (size_t)g->height;
    if (m->all_sums || !m->derived_ok || (!m->unread && !(m->unread = malloc(n)))) return;
    for (int y = 0; y < g->height; ++y)
        for (int x = 0; x < g->width; ++x) {
            size_t i = (size_t)y * g->width + x;
            const GBufferSums *s = &g->sums[i];
            unsigned char u = 0;
            float side;
            if (m->defocus && (defocus_filter(m, x, y, &side), m->defocus_cache.param[i * MAAF_PARAM_STRIDE] <= 0.0f))
                u |= UNREAD_LENS;
            /* a split pixel's first surface is filtered (gbuffer.h): mixed pixels' sums are read */
            if (m->ysum && !g->split_direct && (s->id_mixed || s->unfilterable > 0 || (float)s->hits < g->frame.spp[i]))
                u |= UNREAD_LIGHT;
            m->unread[i] = u;
        }
}

static void maaf_begin_pass(ReconMethod *m, int pass)
{
    /* the wedge comes from pass 1, the pass that records ray geometry */
    m->stats.collect_rays = pass == 0;
    /* later passes refine the guides the shadows' filters read */
    if (pass > 0 && m->shadow_cache.known) memset(m->shadow_cache.known, 0, (size_t)m->g->width * (size_t)m->g->height);
    if (pass > 0 && m->indirect_cache.known) memset(m->indirect_cache.known, 0, (size_t)m->g->width * (size_t)m->g->height);
    if (pass > 0 && !m->unread) mark_unread_sums(m);
    if (pass > 0) m->plan_known = false;
}

/* The albedo sums of the split (docs/algorithms.md 9.8): sum_k c_k a_k per component. Where
 * every sample of a pixel has the same albedo A (one surface, untextured there: most pixels)
 * that is A times the weight channel of dsum, sum_k c_k, so nothing is accumulated: the pixel
 * keeps A (albedo4) and the filter makes the sums from dsum (albedo_sums). Only when a sample
 * brings another albedo are the sums written, A times the earlier samples' weight sums, and
 * accumulated from then on. Equal to accumulating every sample to float rounding (A sum c_k
 * against sum A c_k); it saves half the per-sample sums of a combined frame and the pages of
 * 27 MB. */
#define ALBEDO_SUMS_NONE 0.0f   /* no sample yet */
#define ALBEDO_SUMS_ONE 1.0f    /* every sample so far had albedo4's albedo */
#define ALBEDO_SUMS_KEPT 2.0f   /* asum holds the pixel's sums */

/* Pixel i's albedo sums: asum's where kept, else albedo4's albedo times dsum's weight sums,
 * written to tmp (per floats). */
static const float *albedo_sums(const ReconMethod *m, size_t i, float *tmp)
{
    size_t per = (size_t)m->lens_comps * 8;
    const float *st = m->albedo4 + 4 * i, *ds = m->dsum + i * per;
    if (st[3] == ALBEDO_SUMS_KEPT) return m->asum + i * per;
    if (st[3] == ALBEDO_SUMS_NONE) {
        memset(tmp, 0, per * sizeof(float));
        return tmp;
    }
    for (size_t c = 0; c < per; c += 4) { /* per (re, im) half: A times its weight sum, weight 0 */
        for (int ch = 0; ch < 3; ++ch) tmp[c + ch] = st[ch] * ds[c + 3];
        tmp[c + 3] = 0.0f;
    }
    return tmp;
}

static void albedo_add(ReconMethod *m, size_t i, const float *w, const float a[4])
{
    size_t per = (size_t)m->lens_comps * 8;
    float *st = m->albedo4 + 4 * i, *as = m->asum + i * per;
    if (st[3] == ALBEDO_SUMS_NONE) {
        memcpy(st, a, 3 * sizeof(float));
        st[3] = ALBEDO_SUMS_ONE;
        if (!m->all_sums) return;
    }
    if (st[3] == ALBEDO_SUMS_ONE) {
        if (!m->all_sums && a[0] == st[0] && a[1] == st[1] && a[2] == st[2]) return;
        albedo_sums(m, i, as); /* the earlier samples' sums, A times their weight sums */
        st[3] = ALBEDO_SUMS_KEPT;
    }
    maaf_factors_accumulate(m->lens_comps, w, a, as);
}

/* Defocus sums (eq. 20 with the lens point, maaf_defocus.h): every sample, hit or not. v is
 * flipped: raster y runs against the lens's v (maaf_defocus.h). */
static void defocus_add(ReconMethod *m, size_t i, const SampleRecord *r, const float ud[3], const float ui[3])
{
    float f[4] = {r->L.x, r->L.y, r->L.z, 1.0f};
    if ((m->split_direct || m->split_indirect) && r->hit) {
        /* the filterable lights, as composite.c splits them (maaf_add_sample's f for the direct) */
        if (m->split_direct) f[0] -= r->direct.x - ud[0], f[1] -= r->direct.y - ud[1], f[2] -= r->direct.z - ud[2];
        if (m->split_indirect)
            f[0] -= r->indirect.x - ui[0], f[1] -= r->indirect.y - ui[1], f[2] -= r->indirect.z - ui[2];
    }
    if (!isfinite(f[0]) || !isfinite(f[1]) || !isfinite(f[2]) || !isfinite(r->lens_u + r->lens_v)) {
        ++m->nonfinite_samples;
        return;
    }
    if (m->unread && (m->unread[i] & UNREAD_LENS)) return;
    size_t per = (size_t)m->lens_comps * 8;
    float w[2 * MAAF_COMPS_MAX];
    maaf_lens_factors(&m->lens, r->lens_u, -r->lens_v, w);
    if (m->asum) {
        float a[4] = {r->hit ? r->albedo.x : 0.0f, r->hit ? r->albedo.y : 0.0f, r->hit ? r->albedo.z : 0.0f, 0.0f};
        albedo_add(m, i, w, a); /* before dsum: it may read dsum's sums of the earlier samples */
    }
    maaf_factors_accumulate(m->lens_comps, w, f, m->dsum + i * per);
}

/* Indirect sums (eq. 20 without the bounce direction, docs/algorithms.md 9.12 "The method
 * without directions"): every sample that hit a surface contributes its filterable indirect
 * light (composite.c's split) with the factors' expectation, so every component's sum is its
 * expectation times the plain sum of the samples: only that sum is kept (4 floats per pixel),
 * and the components are made from it at filter time (maaf_filter_light). The directional
 * factors (maaf_direction_accumulate) added bias on the bench scenes and are not used here. */
static void indirect_add(ReconMethod *m, size_t i, const SampleRecord *r, const float ui[3])
{
    float f[4] = {r->indirect.x - ui[0], r->indirect.y - ui[1], r->indirect.z - ui[2], 1.0f};
    if (!isfinite(f[0]) || !isfinite(f[1]) || !isfinite(f[2])) {
        ++m->nonfinite_samples;
        return;
    }
    float *t1 = m->iframe4 + 4 * i, *t2 = m->iaxis2 + 4 * i;
    if (t1[3] == 0.0f) { /* the pixel's frame: its first hit's normal (a plane's pixels share it) */
        float nr[3] = {r->n_shading.x, r->n_shading.y, r->n_shading.z};
        maaf_basis(nr, t1, t2);
        t1[3] = 1.0f;
    }
    float *sum = m->isum + 4 * i;
    for (int ch = 0; ch < 4; ++ch) sum[ch] += f[ch];
}

/* frame4's w: how the pixel's light axes were set (0: not yet) */
#define FRAME_FROM_SHADOW_RAY 1.0f /* at its first sample with a shadow ray */
#define FRAME_FROM_UNKNOWN 2.0f    /* at a sample without one (no shadow ray in the pixel yet) */

static void maaf_add_sample(ReconMethod *m, int px, int py, const SampleRecord *r)
{
    aaf_stats_add(&m->stats, px, py, r);
    /* the parts of the direct and indirect light the filters must not blur (gbuffer_add's
     * split), once for the three sums */
    float ud[3] = {0.0f, 0.0f, 0.0f}, ui[3] = {0.0f, 0.0f, 0.0f};
    if (r->hit) gbuffer_unfiltered_split(r, ud, ui);
    bool inside = px >= 0 && py >= 0 && px < m->g->width && py < m->g->height;
    /* pass 1's samples measure each pixel's variance for the plan */
    if (m->lum4 && m->stats.collect_rays && inside)
        sample_rate_add(m->lum4 + 4 * ((size_t)py * (size_t)m->g->width + (size_t)px), v3_luminance(r->L));
    if (m->defocus && inside) defocus_add(m, (size_t)py * (size_t)m->g->width + (size_t)px, r, ud, ui);
    /* where the frame splits mixed pixels (gbuffer.h), the shading sums take the samples on
     * each pixel's first surface alone */
    size_t at = inside ? (size_t)py * (size_t)m->g->width + (size_t)px : 0;
    if (m->indirect && r->hit && inside && (!m->g->split_indirect || gbuffer_on_first_surface(m->g, at, r)))
        indirect_add(m, at, r, ui);
    if (!r->hit || !effect_in(m->effects, EFFECT_SOFT_SHADOWS)) return;
    if (m->g->split_direct && !(inside && gbuffer_on_first_surface(m->g, at, r))) return;
    const ShadowRayRecord *sr = r->shadow_count > 0 ? &r->shadow[0] : NULL;
    bool known = sr && sr->light_index >= 0 && sr->light_index < m->light_count &&
                 m->lights[sr->light_index].omega_y_max > 0.0f;
    const MaafLight *l = known ? &m->lights[sr->light_index] : m->first_light;
    if (!l) return;
    size_t i = (size_t)py * (size_t)m->g->width + (size_t)px;
    /* the direct light without the part the filters must not blur (gbuffer_add's split) */
    float f[4] = {r->direct.x, r->direct.y, r->direct.z, 1.0f};
    for (int k = 0; k < 3; ++k) f[k] -= ud[k];
    float p[3] = {r->p_world.x, r->p_world.y, r->p_world.z};
    if (!isfinite(f[0]) || !isfinite(f[1]) || !isfinite(f[2])) {
        ++m->nonfinite_samples; /* left out of the sums, reported at filter time */
        return;
    }
    if (m->unread && (m->unread[i] & UNREAD_LIGHT)) return;
    if (!known) { /* no shadow ray: its light point is unknown (maaf_shadow.h) */
        /* the pixel's axes from this sample too: a pixel whose pass-1 samples all drew light
         * points behind its horizon (a face lit at grazing) was left out of its neighbours'
         * filters, and those were the dark ones (docs/algorithms.md 9.23) */
        float *t1 = m->frame4 + 4 * i;
        if (t1[3] == 0.0f && isfinite(p[0] + p[1] + p[2])) {
            maaf_light_axes(l, p, t1, m->axis2 + 4 * i);
            t1[3] = FRAME_FROM_UNKNOWN;
        }
        maaf_accumulate_unknown(m->light_pairs, l, f, m->ysum + i * (size_t)m->light_comps * 8);
        return;
    }
    float L[3] = {sr->light_p_world.x, sr->light_p_world.y, sr->light_p_world.z};
    if (!isfinite(L[0] + L[1] + L[2]) || !isfinite(p[0] + p[1] + p[2])) {
        ++m->nonfinite_samples;
        return;
    }
    float *t1 = m->frame4 + 4 * i, *t2 = m->axis2 + 4 * i;
    if (t1[3] != FRAME_FROM_SHADOW_RAY) { /* the pixel's axes: its first shadow ray's light's */
        maaf_light_axes(l, p, t1, t2);
        t1[3] = FRAME_FROM_SHADOW_RAY;
    }
    float dl[3] = {L[0] - l->center[0], L[1] - l->center[1], L[2] - l->center[2]};
    float y1 = dl[0] * t1[0] + dl[1] * t1[1] + dl[2] * t1[2];
    float y2 = dl[0] * t2[0] + dl[1] * t2[1] + dl[2] * t2[2];
    maaf_accumulate(m->light_pairs, l, y1, y2, f, m->ysum + i * (size_t)m->light_comps * 8);
}

static bool wedge_windows(ReconMethod *m);

static bool ensure_derived(ReconMethod *m, Diag *d)
{
    if (!m->derived_ok) {
        if (!aaf_derive(&m->stats, &m->derived)) {
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for MAAF statistics");
            return false;
        }
        m->derived_ok = true;
        if (m->defocus) {
            size_t n = (size_t)m->g->width * (size_t)m->g->height;
            if (!m->coc_pool && !(m->coc_pool = malloc(2 * n * sizeof(float)))) {
                diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for MAAF statistics");
                return false;
            }
            maaf_coc_pool(m->derived.coc_min, m->derived.coc_max, m->g->width, m->g->height, m->coc_pool, m->coc_pool + n);
        }
    }
    if (effect_in(m->effects, EFFECT_SOFT_SHADOWS) && !m->wedge_found[1] && !wedge_windows(m)) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for MAAF statistics");
        return false;
    }
    return true;
}

static bool maaf_open_device(ReconMethod *m, ClRuntime *rt, Diag *d)
{
    if (m->filter) return true;
    return (m->filter = maaf_filter_create(rt, d)) != NULL;
}

/* AAF-shadow eq. 1, as AAF: only the visibility is smooth enough to filter. */
static bool maaf_method_light_factor(ReconMethod *m, Effect e, const float **factor, float *min_factor, Diag *d)
{
    *factor = NULL;
    *min_factor = 0.0f;
    if (e != EFFECT_SOFT_SHADOWS) return true;
    if (!ensure_derived(m, d)) return false;
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    aaf_unoccluded_irradiance(&m->derived, m->shade);
    float shade_max = 0.0f;
    for (size_t i = 0; i < n; ++i) shade_max = fmaxf(shade_max, m->shade[i]);
    *factor = m->derived.light_known ? m->shade : NULL;
    *min_factor = MIN_SHADE_REL * shade_max;
    return true;
}

/* The pixel's wedge [s_min, s_max] (AAF-shadow eq. 4) over a 5 x 5 window of pixels that saw
 * an occluder (seeds/003's pre-filtering), else over the borrow radius; false when no pixel
 * there did. The window's extremes, not its means (the paper's): the filter reaches into the
 * window, so its wedge must hold every slope there; a mean let a contact shadow's steep slope
 * be averaged with a far occluder's and the spectrum leaked past the filter as bias
 * (soft_shadows 64 spp: relMSE 8.2e-5 -> 5.8e-5, docs/algorithms.md 9.11). */
static bool pixel_wedge(const ReconMethod *m, int x, int y, float *s_min, float *s_max)
{
    size_t i = (size_t)y * (size_t)m->g->width + (size_t)x;
    for (int k = 0; k < 2; ++k)
        if (m->wedge_found[k][i]) {
            *s_min = m->wedge_lo[k][i];
            *s_max = m->wedge_hi[k][i];
            return true;
        }
    return false;
}

/* One axis of a window's extremes: per pixel the smallest lo and largest hi of the pixels within
 * r along rows (or columns) that have found set, and whether any has. */
static void extremes_along(int w, int h, int r, bool rows, const float *lo_in, const float *hi_in,
                           const unsigned char *found_in, float *lo_out, float *hi_out, unsigned char *found_out)
{
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float lo = INFINITY, hi = -INFINITY;
            bool found = false;
            int c = rows ? x : y, end = rows ? w : h;
            for (int k = c - r; k <= c + r; ++k) {
                if (k < 0 || k >= end) continue;
                size_t j = rows ? (size_t)y * w + k : (size_t)k * w + x;
                if (!found_in[j]) continue;
                lo = fminf(lo, lo_in[j]);
                hi = fmaxf(hi, hi_in[j]);
                found = true;
            }
            size_t i = (size_t)y * w + x;
            lo_out[i] = lo, hi_out[i] = hi, found_out[i] = found;
        }
}

/* pixel_wedge's windows for every pixel, separably: the extremes over a square are the
 * extremes over its rows' extremes (min and max do not depend on the order; the first version
 * scanned both squares per pixel and call, 1.7% of a combined frame). */
static bool wedge_windows(ReconMethod *m)
{
    const AafDerived *dv = &m->derived;
    int w = m->g->width, h = m->g->height;
    size_t n = (size_t)w * (size_t)h;
    float *s1 = malloc(n * sizeof(float)), *s2 = malloc(n * sizeof(float)), *row_lo = malloc(n * sizeof(float)),
          *row_hi = malloc(n * sizeof(float));
    unsigned char *seen = malloc(n), *row_found = malloc(n);
    bool ok = s1 && s2 && row_lo && row_hi && seen && row_found;
    float *lo_k[2] = {NULL, NULL}, *hi_k[2] = {NULL, NULL};
    unsigned char *found_k[2] = {NULL, NULL};
    for (int k = 0; k < 2 && ok; ++k) {
        lo_k[k] = malloc(n * sizeof(float));
        hi_k[k] = malloc(n * sizeof(float));
        found_k[k] = malloc(n);
        ok = lo_k[k] && hi_k[k] && found_k[k];
    }
    for (size_t j = 0; j < n && ok; ++j) { /* s1 steepest (occluder nearest the light), s2 shallowest */
        seen[j] = dv->d2min[j] > 0.0f && dv->d1[j] > 0.0f; /* an occluder */
        if (seen[j]) aaf_shadow_slopes(dv->d1[j], dv->d2min[j], dv->d2max[j], &s1[j], &s2[j]);
    }
    for (int k = 0; k < 2 && ok; ++k) {
        int r = k == 0 ? SLOPE_WINDOW_PX : BORROW_RADIUS_PX;
        extremes_along(w, h, r, true, s2, s1, seen, row_lo, row_hi, row_found);
        extremes_along(w, h, r, false, row_lo, row_hi, row_found, lo_k[k], hi_k[k], found_k[k]);
    }
    /* the far filter's window: no occluder, no pixel whose albedo varies inside it (there the
     * demodulation by the mean albedo is not exact, docs/algorithms.md 9.27), and no surface
     * pixel whose light pass 1 did not check (no shadow ray, 9.28) */
    if (ok) maaf_far_marks(n, seen, m->g->salbedo_varies, m->g->hit, m->stats.shadow_rays, seen);
    if (ok && !m->far_reach_px) ok = (m->far_reach_px = malloc(n)) != NULL;
    if (ok) ok = maaf_far_reach(seen, w, h, (int)SHADOW_RADIUS_CAP_PX, m->far_reach_px);
    free(s1), free(s2), free(row_lo), free(row_hi), free(seen), free(row_found);
    for (int k = 0; k < 2; ++k) {
        if (!ok) { /* all or nothing: ensure_derived asks again */
            free(lo_k[k]), free(hi_k[k]), free(found_k[k]);
            lo_k[k] = hi_k[k] = NULL, found_k[k] = NULL;
        }
        m->wedge_lo[k] = lo_k[k], m->wedge_hi[k] = hi_k[k], m->wedge_found[k] = found_k[k];
    }
    return ok;
}

/* Pixel (x, y)'s x-filter into pr (MAAF_PARAM_STRIDE floats): the MAAF design of its wedge, or
 * a plain Gaussian where no occluder is near. Returns the central std in pixels (0: not
 * filtered) and the number of 4D components in *components. */
static float pixel_filter(const ReconMethod *m, int x, int y, float *pr, float *components)
{
    size_t i = (size_t)y * (size_t)m->g->width + (size_t)x;
    float s_min, s_max, pw = m->g->spixel_world[i], std_px;
    /* the pixel's light's band (AAF's per-pixel sigma), the knob scaling the whole design */
    float sigma = m->derived.sigma_light ? m->derived.sigma_light[i] : 0.0f;
    float wy = sigma > 0.0f ? 2.0f * m->kappa / sigma : (m->first_light ? m->first_light->omega_y_max : 0.0f);
    if (pixel_wedge(m, x, y, &s_min, &s_max)) {
        std_px = maaf_pixel_param(s_min, s_max, wy, m->light_pairs, 1.0f, pw, pr);
        pr[0] = fminf(pr[0], SHADOW_RADIUS_CAP_PX);
        *components = std_px > 0.0f ? (float)((2 * m->light_pairs - 1) * (2 * m->light_pairs - 1)) : 0.0f;
    } else {
        /* 1/sqrt(kappa), not 1/kappa: the budget raises these pixels' counts about as
         * kappa^2, so the samples under the filter still grow (as kappa), as AAF's far rule
         * has them grow with mu; with 1/kappa they stayed constant and so did the noise */
        float reach_px = fmaxf((float)m->far_reach_px[i], FAR_STD_PX / FAR_STD_PER_REACH);
        float far_px = FAR_STD_PER_REACH * reach_px * sqrtf(MAAF_KAPPA_DEFAULT / m->kappa);
        maaf_pixel_param_plain(far_px, pw, m->light_pairs, pr);
        std_px = pr[0] > 0.0f ? far_px : 0.0f;
        *components = pr[0] > 0.0f ? 1.0f : 0.0f;
    }
    return std_px;
}

/* The pixel's reflector heights [h_min, h_max] (AAF-GI's z along the normal, from pass 1's bounce
 * rays): the means over the pixels of the shadows' window (pixel_wedge) that saw a reflector,
 * before indirect_filter's floor (maaf_indirect_heights); false when none did. The means,
 * as seeds/003 Sec. 6.2 pre-filters, not the window's extremes that the shadows take: the
 * lowest of 25 pixels' 9 bounce heights is far below a pixel's typical nearest reflector, and
 * the filters came out 2-3x narrower than AAF-GI's (indirect bench, 16 spp: relMSE 9.6e-4 with
 * the extremes at the best kappa, 4.3e-4 with the means; docs/algorithms.md 9.12). */
static bool pixel_heights(const ReconMethod *m, int x, int y, float *h_min, float *h_max)
{
    int w = m->g->width, h = m->g->height;
    for (int r = SLOPE_WINDOW_PX; r <= BORROW_RADIUS_PX; r += BORROW_RADIUS_PX - SLOPE_WINDOW_PX) {
        double lo = 0.0, hi = 0.0;
        int count = 0;
        /* the window inside the image, in the same order as before */
        int x0 = x - r < 0 ? 0 : x - r, x1 = x + r >= w ? w - 1 : x + r;
        int y0 = y - r < 0 ? 0 : y - r, y1 = y + r >= h ? h - 1 : y + r;
        for (int yy = y0; yy <= y1; ++yy)
            for (int xx = x0; xx <= x1; ++xx) {
                size_t j = (size_t)yy * w + xx;
                float zlo = m->height_lo[j];
                if (zlo != zlo) continue; /* no reflector */
                lo += zlo;
                hi += m->height_hi[j];
                ++count;
            }
        if (count) {
            *h_min = (float)(lo / count);
            *h_max = (float)(hi / count);
            return true;
        }
    }
    return false;
}

/* pixel_heights' terms of every pixel, once (not once per window that holds the pixel: 25 to
 * 121 times). No floor here: the width's floor is the centre pixel's (maaf_indirect_heights). */
static void reflector_heights(ReconMethod *m)
{
    const AafDerived *dv = &m->derived;
    if (m->height_made) return;
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    for (size_t j = 0; j < n; ++j) {
        if (!(dv->zmax[j] >= dv->zmin[j]) || !isfinite(dv->zmax[j])) { /* no reflector */
            m->height_lo[j] = m->height_hi[j] = NAN;
            continue;
        }
        float zlo = aaf_indirect_clamp_zmin(dv->zmin[j], 0.0f, 0.0f); /* positive, never NaN */
        m->height_lo[j] = zlo;
        m->height_hi[j] = fmaxf(dv->zmax[j], zlo);
    }
    m->height_made = true;
}

/* Pixel (x, y)'s indirect x-filter (as pixel_filter for the shadows): the design of its height
 * wedge with Omega_v_max = ikappa 2.8, or a plain Gaussian where no reflector is near. The
 * wedge's floor follows the pixel's current count (maaf_indirect_heights: pass 1's when the
 * plan asks, the final one when the filter runs), so an entry is remade when the count moved. */
static float indirect_filter(ReconMethod *m, int x, int y, const float **pr, float *components)
{
    FilterCache *c = &m->indirect_cache;
    size_t i = (size_t)y * (size_t)m->g->width + (size_t)x;
    float spp = m->g->frame.spp[i];
    if (!c->known[i] || m->indirect_spp[i] != spp) {
        float z_min, z_max, h_min, h_max, pw = m->g->spixel_world[i], *param = c->param + i * MAAF_PARAM_STRIDE;
        reflector_heights(m);
        if (pixel_heights(m, x, y, &z_min, &z_max)) {
            maaf_indirect_heights(z_min, z_max, m->dirs.omega_u_max, m->bounce_pairs, pw, spp, &h_min, &h_max);
            c->std_px[i] = maaf_pixel_param(h_min, h_max, m->dirs.omega_u_max, m->bounce_pairs, 1.0f, pw, param);
            param[0] = fminf(param[0], INDIRECT_RADIUS_CAP_PX);
            c->aux[i] = c->std_px[i] > 0.0f ? (float)((2 * m->bounce_pairs - 1) * (2 * m->bounce_pairs - 1)) : 0.0f;
        } else {
            float far_px = FAR_STD_PX * sqrtf(MAAF_INDIRECT_KAPPA_DEFAULT / m->ikappa);
            maaf_pixel_param_plain(far_px, pw, m->bounce_pairs, param);
            c->std_px[i] = param[0] > 0.0f ? far_px : 0.0f;
            c->aux[i] = param[0] > 0.0f ? 1.0f : 0.0f;
        }
        c->known[i] = 1;
        m->indirect_spp[i] = spp;
    }
    *pr = c->param + i * MAAF_PARAM_STRIDE;
    *components = c->aux[i];
    return c->std_px[i];
}

/* pixel_filter and maaf_defocus_pixel through the caches: *pr points at the cached parameters. */
static float shadow_filter(ReconMethod *m, int x, int y, const float **pr, float *components)
{
    FilterCache *c = &m->shadow_cache;
    size_t i = (size_t)y * (size_t)m->g->width + (size_t)x;
    if (!c->known[i]) {
        c->std_px[i] = pixel_filter(m, x, y, c->param + i * MAAF_PARAM_STRIDE, &c->aux[i]);
        c->known[i] = 1;
    }
    *pr = c->param + i * MAAF_PARAM_STRIDE;
    *components = c->aux[i];
    return c->std_px[i];
}

static float defocus_filter(ReconMethod *m, int x, int y, float *side)
{
    FilterCache *c = &m->defocus_cache;
    size_t i = (size_t)y * (size_t)m->g->width + (size_t)x;
    if (!c->known[i]) {
        size_t n = (size_t)m->g->width * (size_t)m->g->height;
        c->std_px[i] = maaf_defocus_pixel(m->derived.coc_min, m->derived.coc_max, m->coc_pool, m->coc_pool + n, m->g->width,
                                          m->g->height, x, y, m->lens.omega_u_max, m->lens_pairs, c->param + i * MAAF_PARAM_STRIDE,
                                          &c->aux[i]);
        c->known[i] = 1;
    }
    *side = c->aux[i];
    return c->std_px[i];
}

/* Where the filter cannot help, samples can (as AAF, aaf_method.c). Frames without defocus:
 * pixels whose samples saw different surfaces (silhouettes: left out of the filter) and
 * surface pixels whose filter is under UNFILTERED_STD_PX wide (contact shadows) get
 * EXTRA_SPP_PER_MU times mu times pass 1's count, at most 100 mu. Their extra samples come
 * without ray geometry; they are Monte Carlo pixels, and the filter leaves them out as
 * neighbours (sharpness rule). Frames with defocus or with soft shadows alone (rate_planned):
 * every pixel's count from the Lagrange allocation of recon/sample_rate.h, its variance over the
 * area of the filters its light goes through (docs/algorithms.md 9.14, 9.20). */
/* The plan's rule per pixel (plan_class): pass 1's count, the filtered count of the shadow and
 * indirect filters, the rate's count (plan_factor), or the extra count. */
enum { PLAN_PASS1, PLAN_FILTERED, PLAN_RATE, PLAN_EXTRA };


/* Which rule each pixel follows: it depends on the filters, not on mu, so the budget search's
 * plans (up to 14 per frame, pipeline.c's mu_for_budget) classify the pixels once. */
static bool plan_classes(ReconMethod *m)
{
    const GBuffer *g = m->g;
    size_t n = (size_t)g->width * (size_t)g->height;
    if ((!m->plan_class && !(m->plan_class = malloc(n))) ||
        (!m->plan_factor && !(m->plan_factor = malloc(n * sizeof(float)))))
        return false;
    bool shadows = effect_in(m->effects, EFFECT_SOFT_SHADOWS);
    for (int y = 0; y < g->height; ++y)
        for (int x = 0; x < g->width; ++x) {
            size_t i = (size_t)y * g->width + x;
            const float *pr;
            float comps, side;
            bool more = false;
            int cls = PLAN_PASS1;
            float shade_px = INFINITY; /* the narrowest shading filter's std; 0: one passes the pixel through */
            m->plan_factor[i] = 1.0f;
            /* shadows: silhouettes, and surfaces lit directly whose filter is too narrow */
            if (shadows && g->hit[i]) {
                /* glossy receivers keep their own direct light (gbuffer.h): extra samples */
                /* a pixel without a shadow ray in pass 1 (FRAME_FROM_UNKNOWN) takes its filter's
                 * area when that is the plain far filter (no occluder near): its count then does
                 * not depend on whether its own pass 1 found the light, which biased a grazing-lit
                 * face +5%. Beside occluders it counts as unfiltered, as before its axes were set:
                 * there the wedge filter's area moved thin_occluders' counts and its error rose
                 * 5.6% at 16 spp (docs/algorithms.md 9.23). */
                float frame = m->frame4[4 * i + 3];
                float std_px = frame != 0.0f ? shadow_filter(m, x, y, &pr, &comps) : INFINITY;
                if (frame == FRAME_FROM_UNKNOWN && comps > 1.0f) std_px = INFINITY;
                /* a surface edge pass 1 may have missed counts as mixed (gbuffer.h) */
                bool mixed = g->mixed[i] || gbuffer_surface_step(g, i);
                more = mixed || g->glossy[i] || std_px < UNFILTERED_STD_PX;
                shade_px = mixed || g->glossy[i] ? 0.0f : std_px;
                cls = PLAN_FILTERED;
            }
            /* indirect light: the same rule with its own filter */
            if (m->indirect && g->hit[i] && !more) {
                float std_px = m->iframe4[4 * i + 3] != 0.0f ? indirect_filter(m, x, y, &pr, &comps) : INFINITY;
                more = g->mixed[i] || std_px < UNFILTERED_STD_PX;
                shade_px = fminf(shade_px, g->mixed[i] ? 0.0f : std_px);
                cls = PLAN_FILTERED;
            }
            if (m->defocus) {
                /* the area the pixel's light is averaged over: the lens filter's (0 where the
                 * range straddles the focal plane), after the shading filter's unless that
                 * passes the pixel through (a texture edge's antialiasing is no shading
                 * filter's either, gbuffer.h); INFINITY: no shading filter asked (a miss, no
                 * shading effect), the lens filter's alone */
                float lens_px = defocus_filter(m, x, y, &side);
                bool passed = g->hit[i] && (more || shade_px == 0.0f || gbuffer_texture_needs_samples(g, i, lens_px));
                float shade_used_px = passed || shade_px == INFINITY ? 0.0f : shade_px;
                /* the two isotropic blurs compose: their variances add */
                float var_px2 = lens_px * lens_px + shade_used_px * shade_used_px;
                m->plan_factor[i] = sample_rate_area_px(var_px2, var_px2);
                m->plan_class[i] = PLAN_RATE;
                continue;
            }
            /* a texture edge's antialiasing is no shading filter's (gbuffer.h): extra samples */
            more = more || (g->hit[i] && gbuffer_texture_needs_samples(g, i, 0.0f));
            if (m->lum4) {
                /* soft shadows alone: the allocation over the shadow filter's area (a pixel it
                 * passes through, or a miss, counts as the pixel alone); filters of a few
                 * pixels (contact shadows) get more samples than wide ones, not all alike */
                float std_used = more || !(shade_px < INFINITY) ? 0.0f : shade_px;
                m->plan_factor[i] = sample_rate_area_px(std_used * std_used, std_used * std_used);
                m->plan_class[i] = PLAN_RATE;
                continue;
            }
            m->plan_class[i] = more ? PLAN_EXTRA : cls;
        }
    /* rate_planned frames: plan_factor's areas become the Lagrange allocation's count factors
     * against a pixel of typical variance that no filter covers (A = 1), which gets the extra
     * count of the class plan */
    if (m->lum4 && !sample_rate_factors(m->lum4, g->width, g->height, m->plan_factor)) return false;
    m->plan_known = true;
    return true;
}

static bool maaf_plan(ReconMethod *m, float mu, const float *spp_now, int *spp_total, Diag *d)
{
    if (!ensure_derived(m, d)) return false;
    const GBuffer *g = m->g;
    size_t n = (size_t)g->width * (size_t)g->height;
    if (!m->pass1_spp) m->pass1_spp = n ? (int)spp_now[0] : 0;
    int pass1 = m->pass1_spp;
    if (!m->plan_known && !plan_classes(m)) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the MAAF plan");
        return false;
    }
    /* one knob: --mu is kappa, and the plan's mu is AAF's scale (2 at the default kappa) */
    float mu_e = (mu > 0.0f ? mu : m->kappa) * (MAAF_PLAN_MU_DEFAULT / MAAF_KAPPA_DEFAULT);
    int count[PLAN_EXTRA + 1];
    count[PLAN_PASS1] = pass1;
    count[PLAN_RATE] = pass1; /* unused: per pixel below */
    count[PLAN_EXTRA] = aaf_clamp_spp(EXTRA_SPP_PER_MU * mu_e * (float)pass1, pass1, 100.0f * mu_e);
    /* filtered shadow pixels: more samples as mu grows (AAF's rule for its far pixels), or a
     * budget reached only the silhouettes and the rest kept pass 1's noise */
    count[PLAN_FILTERED] = aaf_far_spp(pass1, mu_e);
    /* the rate's reference, a typical pixel no filter covers: the extra count (uncapped; the
     * cap applies per pixel), so default frames keep the old rule's count there. Under a
     * budget mu scales it. */
    float rate_base = EXTRA_SPP_PER_MU * mu_e * (float)pass1;
    for (size_t i = 0; i < n; ++i) {
        int cls = m->plan_class[i];
        spp_total[i] = cls == PLAN_RATE ? aaf_clamp_spp(rate_base * m->plan_factor[i], pass1, 100.0f * mu_e) : count[cls];
    }
    return true;
}

/* Runs the image pass on in and writes its filtered pixels' rgb into value4 (4 floats per
 * pixel); non-finite results keep the pixel's own value and are counted in *nonfinite. */
static bool have_filter(const ReconMethod *m, Diag *d)
{
    if (!m->filter) diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "MAAF filter: the OpenCL device was not opened");
    return m->filter != NULL;
}

static bool run_filter(ReconMethod *m, const MaafFilterInput *in, float *value4, double *kernel_seconds,
                       long long *nonfinite, Diag *d)
{
    if (!have_filter(m, d)) return false;
    const char *dump = getenv(MAAF_DUMP_ENV); /* the input of tests/recon/bench_maaf_filter.c */
    if (dump && *dump) {
        static int dumps = 0;
        char path[4096];
        snprintf(path, sizeof path, "%s.%d", dump, dumps++);
        if (!maaf_filter_dump(in, path)) fprintf(stderr, "wedge: maaf: cannot write %s\n", path);
    }
    if (!maaf_filter_run(m->filter, in, m->out4, kernel_seconds, d)) return false;
    size_t n = (size_t)in->width * (size_t)in->height;
    for (size_t i = 0; i < n; ++i) {
        const float *o = m->out4 + 4 * i;
        if (o[3] == 0.0f) continue;
        if (!isfinite(o[0]) || !isfinite(o[1]) || !isfinite(o[2])) {
            ++*nonfinite;
            continue;
        }
        memcpy(value4 + 4 * i, o, 3 * sizeof(float));
    }
    return true;
}

/* The indirect image pass's bands. Component (p, q)'s sums are its
 * expectation exp(-2 (p^2 + q^2)) times the plain sum (indirect_add), at most e^-8 = 3.4e-4 for
 * the components with |p| or |q| >= 2: the pass runs the sub-design of bands |p|, |q| <= 1 of
 * the pixel's design (its first two bands' parameters; 5 components of 13 at N = 3). */
static int indirect_pass_pairs(const ReconMethod *m)
{
    return m->bounce_pairs < 2 ? m->bounce_pairs : 2;
}

/* What light_fill needs of maaf_filter_light's pass. */
typedef struct {
    const ReconMethod *m;
    bool ind;
    int pass_pairs, pass_comps;
    const float *factor, *sums;
} LightFill;

/* The light pass's sums of image rows [y0, y1) into the pass's planes (MaafPlanesFill): each
 * usable pixel's (maaf_filter_light marked them in guide4) demodulated. */
static void light_fill(void *ctx, const MaafPlanes *planes, int y0, int y1)
{
    const LightFill *lf = ctx;
    const ReconMethod *m = lf->m;
    const GBuffer *g = m->g;
    int w = g->width, pass_comps = lf->pass_comps;
    size_t per = (size_t)m->light_comps * 8;
    float mean[MAAF_COMPS_MAX]; /* the indirect components' expectations: an expf each, once a band */
    for (int c = 0; lf->ind && c < pass_comps; ++c) mean[c] = maaf_direction_mean(lf->pass_pairs, c);
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            float spp = g->frame.spp[i];
            float yd[8 * MAAF_COMPS_MAX];
            if (m->guide4[4 * i + 3] == 0.0f) { /* not usable */
                maaf_planes_put(planes, x, y, NULL);
                continue;
            }
            /* a pixel whose sums no row-pass work item reads in full: the central component
             * alone (maaf_planes_full) */
            int used_comps = maaf_planes_full(planes, x, y) ? pass_comps : 1;
            /* composite.c's demodulation (value4 was made usable only where it is stable):
             * each pixel's sums divided by its own albedo (the diffuse albedo for direct light,
             * gbuffer_direct_albedo) and r(x) */
            float inv[3], asum[3];
            if (gbuffer_pixel_split(g, i) && (lf->ind ? g->split_indirect : g->split_direct)) {
                /* a split pixel: its sums hold its first surface's samples alone (maaf_add_sample),
                 * divided by their count and albedo (gbuffer.h) */
                float light[3];
                gbuffer_first_surface_sums(g, i, !lf->ind, &spp, light, asum);
            } else if (lf->ind) memcpy(asum, g->frame.albedo + 3 * i, sizeof asum);
            else gbuffer_direct_albedo_sum(g, i, asum);
            for (int k = 0; k < 3; ++k) inv[k] = spp / (asum[k] * (lf->factor ? lf->factor[i] : 1.0f));
            if (lf->ind) { /* component c: its expectation x the plain sum */
                const float *ys = lf->sums + 4 * i;
                for (int c = 0; c < used_comps; ++c)
                    for (int ch = 0; ch < 4; ++ch) {
                        float re = mean[c] * ys[ch];
                        yd[8 * c + ch] = ch == 3 ? re : re * inv[ch];
                        yd[8 * c + 4 + ch] = 0.0f;
                    }
            } else {
                /* the weight channel times 1: the same float (the sums hold no signalling NaN),
                 * and a loop without a branch per float vectorises */
                const float *ys = lf->sums + i * per;
                float scale[4] = {inv[0], inv[1], inv[2], 1.0f};
                for (size_t c = 0; c < 8 * (size_t)used_comps; c += 4)
                    for (int ch = 0; ch < 4; ++ch) yd[c + ch] = ys[c + ch] * scale[ch];
            }
            /* under the Lagrange allocation (rate_planned), per-pixel means (eq. 20 per pixel, as
             * the lens sums: 9.8): the plan's counts there vary by 10x between neighbours
             * (recon/sample_rate.h), and with raw sums a pixel's weight in its filters would
             * follow its count, not the design (docs/algorithms.md 9.14; soft_shadows at 32 spp,
             * 9.20: bias 4.4e-5 raw, 2.5e-5 means). Under the class plan the sums stay raw: the
             * extra-sample pixels' own samples are meant to dominate their filter there. */
            if (m->lum4)
                for (int c = 0; c < 8 * used_comps; ++c) yd[c] /= spp;
            maaf_planes_put(planes, x, y, yd);
        }
}

/* Soft shadows (the direct light over albedo and r(x), the light's axes) or indirect light (over
 * albedo, the pixel's tangent axes): the same image pass on the receiver guides. The pixels'
 * guides and filters first, then the pass, which takes the sums band by band (light_fill). */
static bool maaf_filter_light(ReconMethod *m, Effect e, float *value4, double *kernel_seconds, Diag *d)
{
    *kernel_seconds = 0.0;
    bool ind = e == EFFECT_INDIRECT;
    if (ind ? !m->isum : e != EFFECT_SOFT_SHADOWS || !m->ysum) return true;
    if (!ensure_derived(m, d)) return false;
    const GBuffer *g = m->g;
    int w = g->width, h = g->height;
    /* without directions the indirect pass runs the bands |p| <= 1 only (indirect_pass_pairs) */
    int pass_pairs = ind ? indirect_pass_pairs(m) : m->light_pairs, pass_comps = maaf_component_count(pass_pairs);
    const float *factor = !ind && m->derived.light_known ? m->shade : NULL;
    const float *sums = ind ? m->isum : m->ysum, *frame4 = ind ? m->iframe4 : m->frame4, *axis2 = ind ? m->iaxis2 : m->axis2;
    float *std_px = ind ? m->istd_px : m->std_px, *components = ind ? m->icomponents : m->components;
    if (!have_filter(m, d)) return false;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            float spp = g->frame.spp[i];
            bool usable = value4[4 * i + 3] != 0.0f && frame4[4 * i + 3] != 0.0f && spp > 0.0f;
            memcpy(m->guide4 + 4 * i, frame4 + 4 * i, 3 * sizeof(float));
            m->guide4[4 * i + 3] = usable ? 1.0f : 0.0f;
            std_px[i] = 0.0f;
            components[i] = 0.0f;
            if (!usable) continue; /* its parameters (the filter cache's) are not read: usable 0 */
            const float *cached;
            std_px[i] = ind ? indirect_filter(m, x, y, &cached, &components[i]) : shadow_filter(m, x, y, &cached, &components[i]);
            (void)cached;
            if (components[i] > (float)(2 * pass_comps - 1)) components[i] = (float)(2 * pass_comps - 1);
        }
    const float *param = (ind ? &m->indirect_cache : &m->shadow_cache)->param;
    LightFill fill = {m, ind, pass_pairs, pass_comps, factor, sums};
    MaafFilterInput in = {w, h, pass_pairs, NULL, g->spos4, g->snrm4, m->guide4, axis2, param, COS_NORMAL_MIN,
                          DEPTH_TOL_REL, MAAF_SHARP_FACTOR_DEFAULT, light_fill, &fill};
    long long nonfinite = 0;
    if (!run_filter(m, &in, value4, kernel_seconds, &nonfinite, d)) return false;
    if (nonfinite || m->nonfinite_samples)
        fprintf(stderr, "wedge: maaf (%s): %lld non-finite filtered pixels kept their own value, %lld non-finite samples left out\n",
                ind ? "indirect" : "soft shadows", nonfinite, m->nonfinite_samples);
    return true;
}

static void maaf_shading_light(ReconMethod *m, const ReconShadingLight *light)
{
    m->direct4 = light->direct4;
    m->direct_factor = light->direct_factor;
    m->indirect4 = light->indirect4;
}

/* The lens sums of image rows [y0, y1) into the defocus pass's planes (MaafPlanesFill), as
 * maaf_filter_radiance describes. */
static void radiance_fill(void *ctx, const MaafPlanes *planes, int y0, int y1)
{
    ReconMethod *m = ctx;
    const GBuffer *g = m->g;
    size_t w = (size_t)g->width, per = (size_t)m->lens_comps * 8;
    for (size_t i = (size_t)y0 * w; i < (size_t)y1 * w; ++i) {
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        float spp = g->frame.spp[i], inv = spp > 0.0f ? 1.0f / spp : 0.0f;
        const float *src = m->dsum + i * per;
        float o[8 * MAAF_COMPS_MAX];
        if (!(spp > 0.0f) || (m->unread && (m->unread[i] & UNREAD_LENS))) { /* not usable (screen guides), or unread */
            maaf_planes_put(planes, x, y, NULL);
            continue;
        }
        if (m->asum) {
            float alb_tmp[8 * MAAF_COMPS_MAX], raw[3][3], ud[3], ui[3];
            const float *rest = src, *alb = albedo_sums(m, i, alb_tmp);
            memcpy(o, rest, per * sizeof(float));
            gbuffer_unfiltered_means(g, i, ud, ui);
            for (int k = 0; k < 3; ++k) { /* composite.c's raw means of the filterable lights */
                raw[0][k] = spp > 0.0f ? g->frame.direct[3 * i + k] / spp - ud[k] : 0.0f;
                raw[1][k] = spp > 0.0f ? g->frame.indirect[3 * i + k] / spp - ui[k] : 0.0f;
                if (!isfinite(raw[0][k])) raw[0][k] = 0.0f;
                if (!isfinite(raw[1][k])) raw[1][k] = 0.0f;
            }
            /* a split pixel whose first surface was filtered: its composite light (the first
             * surface's filtered share and the others' mean, composite_split_light) over every
             * lens sample, as a light passed through */
            bool split = gbuffer_pixel_split(g, i);
            if (split && m->split_direct && g->split_direct && m->direct4 && m->direct4[4 * i + 3] != 0.0f) {
                composite_split_light(g, i, true, m->direct4 + 4 * i, m->direct_factor ? m->direct_factor[i] : 1.0f, raw[0]);
                maaf_defocus_add_light(NULL, 1.0f, raw[0], rest, alb, per, o);
            } else if (m->split_direct) {
                const float *d4 = m->direct4 ? m->direct4 + 4 * i : NULL;
                float per_total[4];
                /* the albedo sums are the total albedo's, the filtered direct light is per unit
                 * diffuse albedo (gbuffer_direct_albedo): where the pixel's direct light is split
                 * by lobe, per unit total albedo, by the ratio of the pixel's mean albedos (exact
                 * when its samples share one ratio) */
                if (d4 && d4[3] != 0.0f && g->lobe4[4 * i + 3] > 0.0f) {
                    const float *at = g->frame.albedo + 3 * i;
                    float ad[3];
                    gbuffer_direct_albedo_sum(g, i, ad);
                    for (int k = 0; k < 3; ++k) per_total[k] = at[k] > 0.0f ? d4[k] * (ad[k] / at[k]) : 0.0f;
                    per_total[3] = d4[3];
                    d4 = per_total;
                }
                maaf_defocus_add_light(d4, m->direct_factor ? m->direct_factor[i] : 1.0f, raw[0], rest, alb, per, o);
            }
            if (split && m->split_indirect && g->split_indirect && m->indirect4 && m->indirect4[4 * i + 3] != 0.0f) {
                composite_split_light(g, i, false, m->indirect4 + 4 * i, 1.0f, raw[1]);
                maaf_defocus_add_light(NULL, 1.0f, raw[1], rest, alb, per, o);
            } else if (m->split_indirect)
                maaf_defocus_add_light(m->indirect4 ? m->indirect4 + 4 * i : NULL, 1.0f, raw[1], rest, alb, per, o);
            src = o;
        }
        for (size_t c = 0; c < per; ++c) o[c] = src[c] * inv;
        maaf_planes_put(planes, x, y, o);
    }
}

/* Defocus: the lens-weighted radiance sums filtered on screen guides (maaf_defocus.h). When the
 * direct light was filtered here too, each pixel's sums of the rest get its filtered direct
 * light back through the albedo sums: sum_k c_k (L_k - D_k + a_k D_pixel) (LR's substitution,
 * docs/algorithms.md 8.17, with the pixel's own light); where that light was passed through
 * (value4 unusable) its raw mean, times the weight sums. */
static bool maaf_filter_radiance(ReconMethod *m, EffectMask effects, float *value4, double *kernel_seconds, Diag *d)
{
    *kernel_seconds = 0.0;
    if (!effect_in(effects, EFFECT_DEFOCUS) || !m->defocus) return true;
    if (!ensure_derived(m, d)) return false;
    const GBuffer *g = m->g;
    int w = g->width, h = g->height;
    /* Per pixel (radiance_fill): the rest's sums with the shading lights put back (the split), then divided by
     * the pixel's count. Each pixel's sums become means over its own samples: eq. 20's
     * integrals over the lens are Monte Carlo estimates per pixel (seeds/003 Sec. 6.1), so
     * every pixel enters eq. 3's image filter with the same weight whatever its count. With
     * raw sums a pixel weighed by its count, and the plan chose the counts from pass 1's
     * samples, which the sums include: pixels whose first 9 samples hit a small bright
     * emitter got 3-8x the samples of their neighbours that missed it, so the filter
     * over-weighted the lucky ones, more so the larger the budget (bokeh_bright: disks 15% too
     * bright with halos, relMSE 39 at 16 spp and 87 at 32; docs/algorithms.md 9.8). Pixels
     * without a lens filter are read by no pass (mark_unread_sums): zeros. First the pixels'
     * screen guides and filters, then the pass, which takes the sums band by band. */
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            float side = 0.0f;
            m->dstd_px[i] = defocus_filter(m, x, y, &side);
            m->dcomponents[i] = m->dstd_px[i] > 0.0f ? (float)((2 * m->lens_pairs - 1) * (2 * m->lens_pairs - 1)) : 0.0f;
            maaf_screen_guides(x, y, side, g->frame.spp[i] > 0.0f, m->dpos4 + 4 * i, m->dnrm4 + 4 * i, m->guide4 + 4 * i,
                               m->daxis2 + 4 * i);
        }
    if (!have_filter(m, d)) return false;
    MaafFilterInput in = {w, h, m->lens_pairs, NULL, m->dpos4, m->dnrm4, m->guide4, m->daxis2, m->defocus_cache.param,
                          COS_NORMAL_MIN, DEPTH_TOL_REL, MAAF_LENS_SHARP_FACTOR, radiance_fill, m};
    long long nonfinite = 0;
    if (!run_filter(m, &in, value4, kernel_seconds, &nonfinite, d)) return false;
    if (nonfinite)
        fprintf(stderr, "wedge: maaf: %lld non-finite defocus-filtered pixels kept their own value\n", nonfinite);
    return true;
}

static int maaf_shared(ReconMethod *m, DistArray *out, int max)
{
    int count = aaf_stats_arrays(&m->stats, out, max);
    if (m->ysum && count < max) out[count++] = (DistArray){m->ysum, (size_t)m->light_comps * 8 * sizeof(float)};
    if (count < max) out[count++] = (DistArray){m->frame4, 4 * sizeof(float)};
    if (count < max) out[count++] = (DistArray){m->axis2, 4 * sizeof(float)};
    if (m->dsum && count < max) out[count++] = (DistArray){m->dsum, (size_t)m->lens_comps * 8 * sizeof(float)};
    if (m->lum4 && count < max) out[count++] = (DistArray){m->lum4, 4 * sizeof(float)};
    if (m->asum && count < max) out[count++] = (DistArray){m->asum, (size_t)m->lens_comps * 8 * sizeof(float)};
    if (m->albedo4 && count < max) out[count++] = (DistArray){m->albedo4, 4 * sizeof(float)};
    if (m->isum && count < max) out[count++] = (DistArray){m->isum, 4 * sizeof(float)};
    if (m->iframe4 && count < max) out[count++] = (DistArray){m->iframe4, 4 * sizeof(float)};
    if (m->iaxis2 && count < max) out[count++] = (DistArray){m->iaxis2, 4 * sizeof(float)};
    return count;
}

/* One effect's two layers: the central std and the component count. */
static int effect_aovs(const char *effect, const float *std_px, const float *components, ReconAov *out, int count, int max)
{
    const char *names[2] = {"std_px", "components"};
    const char *units[2] = {"central filter std in pixels", "filters"};
    const float *data[2] = {std_px, components};
    for (int k = 0; k < 2 && count < max; ++k, ++count) {
        snprintf(out[count].name, sizeof out[count].name, "maaf.%s.%s", names[k], effect);
        out[count].data = data[k];
        out[count].unit = units[k];
    }
    return count;
}

static int maaf_aovs(ReconMethod *m, ReconAov *out, int max)
{
    int count = effect_aovs("soft_shadows", m->std_px, m->components, out, 0, max);
    if (m->indirect) count = effect_aovs("indirect", m->istd_px, m->icomponents, out, count, max);
    if (m->defocus) count = effect_aovs("defocus", m->dstd_px, m->dcomponents, out, count, max);
    return count;
}

#define MAAF_STR_(x) #x
#define MAAF_STR(x) MAAF_STR_(x)

const ReconMethodClass recon_method_maaf = {
    .name = "maaf",
    .title = "multiple axis-aligned filters (MAAF, seeds/003): soft shadows, indirect light and defocus, (2N-1)^2 offset "
             "Gaussians per effect (N = " MAAF_STR(MAAF_PAIRS_LIGHT_DEFAULT) " light, " MAAF_STR(MAAF_PAIRS_LENS_DEFAULT) " lens, "
             MAAF_STR(MAAF_PAIRS_BOUNCE_DEFAULT) " bounce; --maaf-pairs sets all), 9 spp + extra at silhouettes and near the focal plane",
    .effects = EFFECT_BIT(EFFECT_SOFT_SHADOWS) | EFFECT_BIT(EFFECT_INDIRECT) | EFFECT_BIT(EFFECT_DEFOCUS),
    .adaptive = true,
    .sample_fields = 0,
    .shadow_geometry = EFFECT_BIT(EFFECT_SOFT_SHADOWS), /* occluder distances (shadow parameters) */
    .bounce_geometry = EFFECT_BIT(EFFECT_INDIRECT),     /* reflector distances (indirect parameters) */
    .pass1_spp = maaf_pass1_spp,
    .budget_pass1_share = maaf_budget_pass1_share,
    .create = maaf_create,
    .begin_pass = maaf_begin_pass,
    .add_sample = maaf_add_sample,
    .plan = maaf_plan,
    .open_device = maaf_open_device,
    .light_factor = maaf_method_light_factor,
    .filter_light = maaf_filter_light,
    .shading_light = maaf_shading_light,
    .filter_radiance = maaf_filter_radiance,
    .shared = maaf_shared,
    .aovs = maaf_aovs,
    .destroy = maaf_destroy,
    .filters_split_pixels = true,
};
