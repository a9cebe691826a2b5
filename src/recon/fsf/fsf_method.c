/* Fast 4D sheared filtering (FSF, seeds/000) of soft shadows as a reconstruction method
 * (recon/method.h).
 *
 *   samples  a fixed count in pass 1 (16 per pixel; FSF section 5 uses 4-16); the pipeline's
 *            per-sample store keeps each sample's shadow-ray geometry (light point, d_light,
 *            d_occ) and its direct light. The plan adds FSF_LENS_STRADDLE_EXTRA_SPP at defocus
 *            pixels whose lens slopes straddle the focal plane (fsf_lens_plan.h), nothing
 *            elsewhere or for the other effects. Under a --spp budget pass 1 takes
 *            FSF_BUDGET_PASS1_SHARE of it (_LENS where FSF filters defocus, _BOUNCE where its
 *            only shading filter is the indirect light's; the store keeps those samples) and
 *            the plan places the rest by the Lagrange allocation n ~ sqrt(v / A), v a pixel's
 *            pass-1 variance, A its filter's effective pixel count (fsf_budget_plan.h,
 *            recon/sample_rate.h)
 *   filter   the demodulated direct light: each sample's direct light scaled by its pixel's
 *            demodulation (the pipeline's value over the raw mean: albedo and the unoccluded
 *            irradiance r(x) divided out), filtered by the 4D sheared filter (fsf_filter.h)
 *            with per-pixel shear and widths (fsf_params.h): parameters on the host, the four
 *            passes in OpenCL (fsf_cl.h; fsf_filter_factored when no device was opened)
 *   defocus  the composite radiance (a camera effect, filtered after compositing): each
 *            sample's radiance scaled to its pixel's composite value, the lens point in place
 *            of the light point, screen axes as gather directions (fsf_lens.h); the same
 *            four passes
 *   indirect the demodulated indirect light (divided by the albedo only, as AAF-GI's): each
 *            sample's indirect light scaled by its pixel's demodulation, the bounce
 *            direction's v-plane coordinate in place of the light point (fsf_bounce.h) for
 *            the widths; filtered by the passes' two spatial gathers alone (fsf_flat.h: with
 *            every sample inside the box the shear changed nothing but the node
 *            interpolation, and the transfer weight that would make it count lost), in OpenCL
 *            (fsf_flat_cl.h; fsf_filter_flat when no device was opened). The
 *            pipeline filters it apart from the direct light and adds the two (FSF appendix)
 *   AOVs     fsf.eta_m_per_px (the shear along the light's first axis, light metres per pixel
 *            step), fsf.sigma_px (the width along it), fsf.k_spread (k_hi - k_lo); for
 *            defocus fsf.defocus.eta_lens_per_px (the shear, unit lens per pixel step),
 *            fsf.defocus.sigma_px, fsf.defocus.k_spread, fsf.defocus.straddle (1: the
 *            slope range straddles the focal plane); for indirect light
 *            fsf.indirect.shear (v units per pixel step along t1: the reprojection's shear,
 *            which the filter does not apply), fsf.indirect.sigma_px,
 *            fsf.indirect.k_spread (k_hi - k_lo, v units per receiver metre) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/background.h"
#include "recon/fsf/fsf_bounce.h"
#include "recon/fsf/fsf_bounce_kept.h"
#include "recon/fsf/fsf_budget_plan.h"
#include "recon/fsf/fsf_cl.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/fsf/fsf_flat.h"
#include "recon/fsf/fsf_flat_cl.h"
#include "recon/fsf/fsf_lens.h"
#include "recon/fsf/fsf_lens_plan.h"
#include "recon/fsf/fsf_light.h"
#include "recon/fsf/fsf_params.h"
#include "recon/fsf/fsf_profile.h"
#include "recon/fsf/fsf_scratch.h"
#include "recon/method.h"
#include "recon/sample_rate.h"

/* FSF section 5: 4 to 16 samples per pixel; 16 = a 4 x 4 grid over the light. */
#define FSF_DEFAULT_SPP 16
/* Pixels whose unoccluded irradiance is below this fraction of the frame's largest keep their
 * own light (dividing by it is unstable), as with AAF. */
#define MIN_SHADE_REL 1.0e-3f

struct ReconMethod {
    const Renderer *renderer;
    bool black_background;       /* an escaped ray sees black: the lens filter leaves such pixels (background.h) */
    const GBuffer *g;
    SampleStore *store;
    FsfLight light;
    float mu;
    FsfCl *cl;
    FsfFlatCl *flat_cl;          /* the indirect light's two passes on the device (frames with indirect light) */
    float *shade;                /* unoccluded irradiance (the light factor) */
    float *share;                /* FSF's light's share of it (FSF_MIN_LIGHT_SHARE), NULL until computed */
    FsfShadeInputs shade_from;   /* the guides shade and share were last found from (the plan's), or none */
    FsfSlopeWindows windows;     /* the plan's slope windows (block NULL: none), valid while the store's
                                  * counts and the guides' object ids equal these: */
    int *windows_count;
    float *windows_obj;
    EffectMask effects;
    float *eta_aov, *sigma_aov, *spread_aov;
    float *lens_eta_aov, *lens_sigma_aov, *lens_spread_aov; /* defocus */
    float *straddle_aov;         /* defocus: 1 where the lens slopes straddle the focal plane */
    unsigned char *straddle;     /* the plan's straddlers, found at the first plan */
    FsfPixel *lens_px;           /* the plan's lens parameters, which the filter reuses ... */
    float *lens_k_lo, *lens_k_hi;
    bool lens_planned;           /* ... when set */
    bool planned;                /* straddle (and want_spp) and pass1_spp are set */
    int budget_spp;              /* --spp (0: none) */
    float *lum4;                 /* under a budget: pass 1's luminance moments per pixel (sample_rate_add) */
    int pass;                    /* the pass being traced (begin_pass) */
    float *want_spp;             /* under a budget: each pixel's count by the allocation (real; found once) */
    int pass1_spp;               /* the samples every pixel had at the first plan */
    float *ind_eta_aov, *ind_sigma_aov, *ind_spread_aov;    /* indirect light */
    FsfBounceKept bounce_kept;   /* the plan's indirect-light parameters, for the filter */
    long long nonfinite;         /* filtered pixels whose result was not finite (kept unfiltered) */
    FsfProfile prof;             /* WEDGE_FSF_PROFILE's stage times (fsf_profile.h) */
    FsfScratch scratch;          /* the plan's and the filterings' arrays (fsf_scratch.h) ... */
    bool scratch_ok;             /* ... once allocated */
};

static int fsf_pass1_spp(EffectMask effects)
{
    (void)effects;
    return FSF_DEFAULT_SPP;
}

/* Under a budget (fsf_budget_plan.h): the lens filter reads every pixel's stored samples,
 * the shading filters those of the pixels they filter (the indirect light's nearly all); and
 * where other lights than FSF's have a sizeable share of the power, the shadow filter leaves
 * much of the frame to Monte Carlo, which one stratified pass serves best: all of the budget in
 * pass 1. */
static float fsf_budget_pass1_share(const Renderer *r, EffectMask effects)
{
    bool shadows = effect_in(effects, EFFECT_SOFT_SHADOWS);
    if (shadows && fsf_light_power_share(r) < FSF_MIN_LIGHT_SHARE) return 1.0f;
    if (effect_in(effects, EFFECT_DEFOCUS)) return FSF_BUDGET_PASS1_SHARE_LENS;
    return !shadows && effect_in(effects, EFFECT_INDIRECT) ? FSF_BUDGET_PASS1_SHARE_BOUNCE : FSF_BUDGET_PASS1_SHARE;
}

/* The store fields each effect's filter reads: a frame keeps only its effects' (the union of
 * all three is 18 floats a sample, 22 MB more at 256x256 and 16 spp than soft shadows alone). */
#define FSF_FIELDS_SHADOWS (SAMPLE_FIELD_LIGHT | SAMPLE_FIELD_DIRECT)
#define FSF_FIELDS_DEFOCUS (SAMPLE_FIELD_LENS | SAMPLE_FIELD_DEPTH | SAMPLE_FIELD_RADIANCE)
/* the indirect filter reads each pixel's value, not its samples' light (fsf_flat.h) */
#define FSF_FIELDS_INDIRECT SAMPLE_FIELD_BOUNCE

static unsigned fsf_sample_fields_for(EffectMask effects)
{
    return (effect_in(effects, EFFECT_SOFT_SHADOWS) ? FSF_FIELDS_SHADOWS : 0u) |
           (effect_in(effects, EFFECT_DEFOCUS) ? FSF_FIELDS_DEFOCUS : 0u) |
           (effect_in(effects, EFFECT_INDIRECT) ? FSF_FIELDS_INDIRECT : 0u);
}

static void fsf_destroy(ReconMethod *m)
{
    if (!m) return;
    fsf_cl_destroy(m->cl);
    fsf_flat_cl_destroy(m->flat_cl);
    fsf_scratch_free(&m->scratch);
    free(m->shade);
    free(m->share);
    fsf_shade_inputs_free(&m->shade_from);
    fsf_slope_windows_free(&m->windows);
    free(m->windows_count);
    free(m->windows_obj);
    free(m->eta_aov);
    free(m->sigma_aov);
    free(m->spread_aov);
    free(m->lens_eta_aov);
    free(m->lens_sigma_aov);
    free(m->lens_spread_aov);
    free(m->straddle_aov);
    free(m->straddle);
    free(m->lum4);
    free(m->want_spp);
    free(m->lens_px);
    fsf_bounce_kept_free(&m->bounce_kept);
    free(m->lens_k_lo);
    free(m->lens_k_hi);
    free(m->ind_eta_aov);
    free(m->ind_sigma_aov);
    free(m->ind_spread_aov);
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
        m->lens_eta_aov = calloc(n, sizeof(float));
        m->lens_sigma_aov = calloc(n, sizeof(float));
        m->lens_spread_aov = calloc(n, sizeof(float));
        m->straddle_aov = calloc(n, sizeof(float));
        m->straddle = calloc(n, 1);
        m->ind_eta_aov = calloc(n, sizeof(float));
        m->ind_sigma_aov = calloc(n, sizeof(float));
        m->ind_spread_aov = calloc(n, sizeof(float));
    }
    if (!m || !m->shade || !m->eta_aov || !m->sigma_aov || !m->spread_aov || !m->lens_eta_aov || !m->lens_sigma_aov ||
        !m->lens_spread_aov || !m->straddle_aov || !m->straddle || !m->ind_eta_aov || !m->ind_sigma_aov || !m->ind_spread_aov) {
        fsf_destroy(m);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF buffers");
        return false;
    }
    /* the light frame only when soft shadows are filtered (a defocus-only scene may have none) */
    if (effect_in(s->effects, EFFECT_SOFT_SHADOWS) && !fsf_light_from_renderer(s->renderer, &m->light, d)) {
        fsf_destroy(m);
        return false;
    }
    if (effect_in(s->effects, EFFECT_SOFT_SHADOWS) && !(m->light.fill >= FSF_MIN_LIGHT_FILL))
        fprintf(stderr,
                "wedge: warning: FSF: the brightest area light fills %.0f%% of its bounding rectangle, and FSF's "
                "shadow filter assumes a rectangular light: its soft shadows are left unfiltered (--filter maaf or aaf "
                "filter lights of any shape)\n",
                100.0 * (double)m->light.fill);
    m->renderer = s->renderer;
    m->black_background = recon_background_is_black(s->renderer);
    m->g = s->gbuffer;
    m->store = s->store;
    m->mu = s->mu > 0.0f ? s->mu : 1.0f;
    m->effects = s->effects;
    m->budget_spp = s->spp_budget;
    if (m->budget_spp > 0 && !(m->lum4 = calloc(4 * n, sizeof(float)))) {
        fsf_destroy(m);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF buffers");
        return false;
    }
    *out = m;
    return true;
}

/* The plan's lens parameters (fsf_lens_straddlers), kept for the filter. */
static bool plan_lens(ReconMethod *m)
{
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    m->lens_px = malloc(n * sizeof(FsfPixel));
    m->lens_k_lo = malloc(n * sizeof(float)), m->lens_k_hi = malloc(n * sizeof(float));
    return m->lens_px && m->lens_k_lo && m->lens_k_hi &&
           (m->lens_planned = fsf_lens_straddlers(m->g, m->store, m->mu, m->black_background, m->lens_px,
                                                  m->lens_k_lo, m->lens_k_hi, m->straddle));
}

static void fsf_begin_pass(ReconMethod *m, int pass)
{
    m->pass = pass;
}

/* Under a budget, pass 1's samples measure each pixel's variance for the plan. */
static void fsf_add_sample(ReconMethod *m, int px, int py, const SampleRecord *r)
{
    if (!m->lum4 || m->pass != 0 || px < 0 || py < 0 || px >= m->g->width || py >= m->g->height) return;
    size_t i = (size_t)py * (size_t)m->g->width + (size_t)px;
    sample_rate_add(m->lum4 + 4 * i, v3_luminance(r->L));
}

/* The moments, gathered from the ranks that own the pixels in a distributed frame (dist.h). */
static int fsf_shared(ReconMethod *m, DistArray *out, int max)
{
    int count = 0;
    if (m->lum4 && count < max) out[count++] = (DistArray){m->lum4, 4 * sizeof(float)};
    return count;
}

/* The slope windows of the shadow parameters (fsf_shadow_windows), found for the plan and kept
 * with what they depend on: the store's samples (append-only: its counts say whether any were
 * added) and the guides' object ids. None kept when out of memory (the filter finds its own). */
static void keep_windows(ReconMethod *m)
{
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    m->windows_count = malloc(n * sizeof(int)), m->windows_obj = malloc(n * sizeof(float));
    if (!m->windows_count || !m->windows_obj || !fsf_shadow_windows(m->g, m->store, &m->windows)) {
        free(m->windows_count), free(m->windows_obj);
        m->windows_count = NULL, m->windows_obj = NULL;
        return;
    }
    for (size_t i = 0; i < n; ++i)
        m->windows_count[i] = sample_store_count(m->store, i), m->windows_obj[i] = m->g->nrm4[4 * i + 3];
}

/* The kept windows for the store and guides as they are now, or NULL (then fsf_pixel_params
 * finds them anew): when the store gained samples, none; when pass 2 gave some pixels an object
 * id (a first hit) or another one, the kept windows updated around their rows. */
static const FsfSlopeWindows *kept_windows(ReconMethod *m)
{
    if (!m->windows.block) return NULL;
    int w = m->g->width, h = m->g->height, y0 = h, y1 = -1;
    for (size_t i = 0; i < (size_t)w * (size_t)h; ++i) {
        if (m->windows_count[i] != sample_store_count(m->store, i)) return NULL;
        if (memcmp(&m->windows_obj[i], &m->g->nrm4[4 * i + 3], sizeof(float)) != 0) {
            int y = (int)(i / (size_t)w);
            y0 = y < y0 ? y : y0, y1 = y;
            m->windows_obj[i] = m->g->nrm4[4 * i + 3];
        }
    }
    if (y1 >= 0) fsf_slope_windows_update(&m->windows, w, h, m->windows_obj, y0, y1);
    return &m->windows;
}

/* The frame's arrays (fsf_scratch.h), allocated at their first use; NULL (d set) when out of
 * memory. */
static FsfScratch *scratch(ReconMethod *m, Diag *d)
{
    if (m->scratch_ok) return &m->scratch;
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    if ((m->scratch_ok = fsf_scratch_alloc(&m->scratch, n, sample_store_capacity(m->store)))) return &m->scratch;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF buffers");
    return NULL;
}

/* The frame's arrays with the samples' light too (FsfScratch.v): the filters that read it, the
 * shadows' and the lens'; NULL (d set) when out of memory. */
static FsfScratch *scratch_with_values(ReconMethod *m, Diag *d)
{
    FsfScratch *b = scratch(m, d);
    if (!b || fsf_scratch_values(b, (size_t)m->g->width * (size_t)m->g->height, sample_store_capacity(m->store)))
        return b;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF buffers");
    return NULL;
}

/* A light that is not a rectangle (FSF_MIN_LIGHT_FILL): no pixel's light is FSF's to filter. */
static void share_of_filterable_light(ReconMethod *m, size_t n)
{
    if (m->light.fill >= FSF_MIN_LIGHT_FILL) return;
    for (size_t i = 0; i < n; ++i) m->share[i] = 0.0f;
}

/* Under a budget: each pixel's count (fsf_budget_plan.h), from pass 1's samples: the Lagrange
 * allocation of the budget by the count factors sqrt(v / A). A: the
 * narrowest shading filter's effective pixel count (the shadow or indirect-light filter; 0
 * where one passes the pixel through), and where FSF filters defocus the lens filter's added
 * (it blurs the shading filters' output: the composed Gaussian's area is at least the sum,
 * docs/algorithms.md 10), except at the straddlers, which it leaves to Monte Carlo. */
static bool plan_counts(ReconMethod *m, Diag *d)
{
    const GBuffer *g = m->g;
    size_t n = (size_t)g->width * (size_t)g->height;
    bool indirect = effect_in(m->effects, EFFECT_INDIRECT);
    float *bounce = NULL;
    if (!(m->want_spp = malloc(n * sizeof(float)))) goto oom;
    float *area = m->want_spp; /* the areas first, then the factors in place, then the counts */
    for (size_t i = 0; i < n; ++i) area[i] = INFINITY; /* INFINITY: no shading filter reads the pixel */
    if (effect_in(m->effects, EFFECT_SOFT_SHADOWS)) {
        if (!m->share && !(m->share = malloc(n * sizeof(float)))) goto oom;
        /* with r(x) too (the same cost), kept with its guides: the filter recomputes only the
         * pixels whose guides pass 2 changed */
        fsf_irradiance_and_share(m->renderer, m->light.shape, (int)n, g->hit, g->pos4, g->nrm4, m->shade, m->share);
        share_of_filterable_light(m, n);
        fsf_shade_inputs_free(&m->shade_from);
        fsf_shade_inputs_keep(&m->shade_from, (int)n, g->hit, g->pos4, g->nrm4); /* out of memory: all recomputed */
        fsf_profile_mark(&m->prof, "share");
        if (!m->windows.block) keep_windows(m);
        FsfScratch *sc = scratch(m, d);
        if (!sc) goto fail;
        if (!fsf_shadow_area(g, m->store, &m->light, m->share, m->mu, m->windows.block ? &m->windows : NULL, sc, area))
            goto oom;
        fsf_profile_mark(&m->prof, "area");
    }
    /* the indirect filter's own areas, kept apart for the rule below */
    if (indirect && !(bounce = malloc(n * sizeof(float)))) goto oom;
    for (size_t i = 0; indirect && i < n; ++i) bounce[i] = INFINITY;
    FsfScratch *bsc = indirect ? scratch(m, d) : NULL;
    if (indirect && !bsc) goto fail;
    if (indirect && !fsf_bounce_area(g, m->store, m->mu, bsc, bounce)) {
        free(bounce);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the FSF plan (or no bounce field)");
        return false;
    }
    if (indirect) fsf_profile_mark(&m->prof, "bounce_area");
    if (indirect) fsf_bounce_keep(&m->bounce_kept, m->store, bsc->px, bsc->k_lo, bsc->k_hi, n);
    for (size_t i = 0; i < n; ++i) {
        float shade = indirect ? fminf(area[i], bounce[i]) : area[i];
        shade = shade == INFINITY ? 0.0f : shade;
        if (m->lens_planned) area[i] = m->straddle[i] ? 0.0f : shade + fsf_pixel_area_px(&m->lens_px[i]);
        else area[i] = shade;
    }
    /* texture edges: at most FSF_TEXTURE_AREA_PX, as if their filter averaged few pixels */
    fsf_texture_area(g, m->lens_planned ? m->lens_px : NULL, area);
    if (!sample_rate_factors(m->lum4, g->width, g->height, area)) goto oom;
    fsf_profile_mark(&m->prof, "factors");
    float *factor = m->want_spp;
    /* Pixels the indirect filter filters keep pass 1's count where soft shadows are filtered
     * too and no lens filter follows: there the allocation's extras raised far_light_bounce's
     * relMSE 1.18x / 1.07x at 16 / 64 spp (2026-11-30, fsf12). Where the indirect light is
     * FSF's only filter they follow the allocation as every other pixel: the filter reads the
     * pixel's full mean (fsf_flat.h: its sums are the stored count times the mean, so a pixel's
     * extras lower its own noise in every gather that reads it). On indirect.pbrt, with pass 1
     * at 7/8, relMSE 0.89x / 0.92x / 0.91x / 0.94x at 8 / 16 / 32 / 64 spp, hotspot_bounce 0.73x /
     * 0.85x at 16 / 64; with 13/16 (FSF_BUDGET_PASS1_SHARE_BOUNCE) more (docs/benchmarks.md;
     * before the reach and 7/8, fsf11, it had cost 1.71x / 1.05x at 8 / 16). */
    bool keep_pass1 = indirect && !m->lens_planned && effect_in(m->effects, EFFECT_SOFT_SHADOWS);
    for (size_t i = 0; keep_pass1 && i < n; ++i)
        if (bounce[i] > 0.0f && bounce[i] != INFINITY) factor[i] = 0.0f;
    /* in place: each count reads its own factor only once the search is over */
    sample_rate_counts(factor, n, (float)m->pass1_spp, FSF_BUDGET_CAP_RATIO * (float)m->pass1_spp,
                       (double)m->budget_spp, m->want_spp);
    fsf_profile_mark(&m->prof, "counts");
    free(bounce);
    return true;
oom:
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the FSF plan");
fail:
    free(bounce);
    return false;
}

/* FSF section 5: pass 1's count everywhere, FSF_LENS_STRADDLE_EXTRA_SPP more where the lens
 * slopes straddle the focal plane. Under a --spp budget pass 1 had fsf_budget_pass1_share of
 * it, and the rest follows each pixel's count factor (fsf_budget_plan.h). Both depend
 * on pass 1's stored samples and FSF's own knob only, so they are found once (the pipeline may
 * plan several times: a budget search, progressive steps); the search's mu does not change
 * FSF's filter (m->mu) and so not the plan. */
static bool fsf_plan(ReconMethod *m, float mu, const float *spp_now, int *spp_total, Diag *d)
{
    (void)mu;
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    if (!m->planned) {
        fsf_profile_begin(&m->prof);
        m->pass1_spp = n ? (int)spp_now[0] : 0;
        if (effect_in(m->effects, EFFECT_DEFOCUS) && !plan_lens(m)) {
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the FSF plan (or no depth field)");
            return false;
        }
        fsf_profile_mark(&m->prof, "lens");
        if (m->budget_spp > 0 && !plan_counts(m, d)) return false;
        m->planned = true;
        fsf_profile_print(&m->prof, "plan");
    }
    if (m->budget_spp > 0)
        fsf_budget_plan(m->want_spp, n, spp_now, spp_total);
    else
        fsf_lens_plan(m->straddle, n, m->pass1_spp, FSF_LENS_STRADDLE_EXTRA_SPP, spp_now, spp_total);
    return true;
}

static bool fsf_open_device(ReconMethod *m, ClRuntime *rt, Diag *d)
{
    if (!m->cl && !(m->cl = fsf_cl_create(rt, d))) return false;
    if (effect_in(m->effects, EFFECT_INDIRECT) && !m->flat_cl && !(m->flat_cl = fsf_flat_cl_create(rt, d))) return false;
    return true;
}

/* AAF-shadow eq. 1, as for AAF: only the visibility is smooth enough to filter, so the
 * direct light is divided by the unoccluded irradiance r(x) too. Indirect light: no factor
 * besides the albedo (as AAF-GI's): it is the irradiance itself that is filtered. */
static bool fsf_light_factor(ReconMethod *m, Effect e, const float **factor, float *min_factor, Diag *d)
{
    *factor = NULL;
    *min_factor = 0.0f;
    if (e != EFFECT_SOFT_SHADOWS) return true;
    int n = m->g->width * m->g->height;
    /* several area lights: where FSF's light is not (almost) all of a pixel's light, the
     * pixel is left out (fsf_light.h); the share comes with r(x) in one pass */
    if (!m->share && !(m->share = malloc((size_t)n * sizeof(float)))) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF's light share");
        return false;
    }
    fsf_profile_begin(&m->prof);
    if (m->shade_from.hit)
        fsf_irradiance_and_share_since(m->renderer, m->light.shape, n, m->g->hit, m->g->pos4, m->g->nrm4,
                                       &m->shade_from, m->shade, m->share);
    else
        fsf_irradiance_and_share(m->renderer, m->light.shape, n, m->g->hit, m->g->pos4, m->g->nrm4, m->shade, m->share);
    share_of_filterable_light(m, (size_t)n);
    fsf_profile_mark(&m->prof, "irradiance");
    fsf_profile_print(&m->prof, "light_factor");
    float shade_max = 0.0f;
    for (int i = 0; i < n; ++i) shade_max = fmaxf(shade_max, m->shade[i]);
    *factor = m->shade;
    *min_factor = MIN_SHADE_REL * shade_max;
    return true;
}

/* The store's samples as the filter's input: light coordinates along the light's axes and
 * each sample's direct light demodulated like its pixel's mean (value4 / raw mean). */
static bool gather(const ReconMethod *m, const float *value4, unsigned char *usable, float *y_m, float *v, int *count,
                   long long *nonfinite)
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
        usable[i] = value4[4 * i + 3] > 0.0f && cnt > 0 && m->g->hit[i] && !m->g->mixed[i] &&
                    (!m->share || m->share[i] >= FSF_MIN_LIGHT_SHARE) && !fsf_pixel_creased(m->g, i);
        if (!usable[i]) continue; /* no pass reads its samples (fsf_filter.h) */
        for (int k = 0; k < cnt; ++k) {
            size_t slot = i * (size_t)cap + (size_t)k;
            const float *s = lf + 5 * slot;
            vec3 q = v3_sub(v3(s[0], s[1], s[2]), c);
            /* a sample without a shadow ray (no light point): mid-light */
            bool has = s[3] > 0.0f;
            y_m[2 * slot] = has ? v3_dot(q, u) : 0.0f;
            y_m[2 * slot + 1] = has ? v3_dot(q, w) : 0.0f;
        }
        float scale[3];
        fsf_match_pixel_on_light(value4 + 4 * i, dir + i * (size_t)cap * 3, y_m + 2 * i * (size_t)cap, m->light.half_m,
                                 cnt, scale);
        *nonfinite += fsf_scale_samples(dir + i * (size_t)cap * 3, cnt, scale, v + i * (size_t)cap * 3);
        fsf_fill_dark_channels(value4 + 4 * i, dir + i * (size_t)cap * 3, cnt, v + i * (size_t)cap * 3);
    }
    return true;
}

/* The four passes (flat: the two spatial passes of fsf_flat.h), on the device when one was
 * opened, else on the host; then each usable pixel's value4 rgb
 * replaced by its filtered one (rgb / weight); non-finite results keep the input, counted.
 * keep_left_out: pixels with both widths 0 keep value4 (for the lens, whose profile square
 * would drop some of their own samples; the light's profile keeps them all). */
static bool run_filter(ReconMethod *m, const FsfSamples *s, const FsfGrid *grid, const FsfPixel *px,
                       const FsfGuides *gd, bool keep_left_out, bool flat, float *out4, float *value4,
                       double *kernel_seconds, Diag *d)
{
    bool ok = true;
    if (flat && m->flat_cl) { /* the indirect light: two spatial passes over each pixel's value and
                               * stored count (fsf_flat.h), as fsf_flat.cl's kernels */
        ok = fsf_flat_cl_run(m->flat_cl, value4, s->count, s->width, s->height, grid, px, gd, out4, kernel_seconds, d);
        for (int rep = fsf_profile_repeats(&m->prof); ok && rep > 0; --rep) /* a measuring aid: the same out4 */
            ok = fsf_flat_cl_run(m->flat_cl, value4, s->count, s->width, s->height, grid, px, gd, out4, kernel_seconds, d);
        fsf_profile_mark(&m->prof, "flat_cl");
        fsf_profile_add(&m->prof, "k_flat", *kernel_seconds);
    } else if (flat) { /* the same in C, on the host threads (no device) */
        ok = fsf_filter_flat(value4, s->count, s->width, s->height, grid, px, gd, out4);
        for (int rep = fsf_profile_repeats(&m->prof); ok && rep > 0; --rep) /* as above */
            ok = fsf_filter_flat(value4, s->count, s->width, s->height, grid, px, gd, out4);
        if (!ok) diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF's indirect-light passes");
        fsf_profile_mark(&m->prof, "flat");
    } else if (m->cl) {
        ok = fsf_cl_run(m->cl, s, grid, px, gd, out4, kernel_seconds, d);
        for (int rep = fsf_profile_repeats(&m->prof); ok && rep > 0; --rep) /* a measuring aid: the same out4 */
            ok = fsf_cl_run(m->cl, s, grid, px, gd, out4, kernel_seconds, d);
        fsf_profile_mark(&m->prof, "cl_run");
        FsfClProfile k = fsf_cl_profile(m->cl);
        fsf_profile_add(&m->prof, "cl_setup", k.setup_wall), fsf_profile_add(&m->prof, "cl_queue", k.queue_wall);
        fsf_profile_add(&m->prof, "k_taps", k.taps), fsf_profile_add(&m->prof, "k_bins", k.bins);
        fsf_profile_add(&m->prof, "k_1a", k.pass1a), fsf_profile_add(&m->prof, "k_1b", k.pass1b);
        fsf_profile_add(&m->prof, "k_2a", k.pass2a), fsf_profile_add(&m->prof, "k_2b", k.pass2b);
    } else if (!fsf_filter_factored(s, grid, px, gd, out4)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF passes");
    }
    size_t n = (size_t)s->width * (size_t)s->height;
    long long before = m->nonfinite;
    for (size_t i = 0; ok && i < n; ++i) {
        if (!gd->usable[i] || !(out4[4 * i + 3] > 0.0f)) continue;
        if (keep_left_out && px[i].sigma_px[0] == 0.0f && px[i].sigma_px[1] == 0.0f) continue;
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
    if (ok && m->nonfinite > before)
        fprintf(stderr, "wedge: warning: FSF: %lld pixels had a non-finite filtered value and kept their mean\n",
                m->nonfinite - before);
    fsf_profile_mark(&m->prof, "result");
    return ok;
}

/* Values that came out NaN or infinite (samples once scaled to their pixel, fsf_scale_samples;
 * the indirect light's pixel values, fsf_flat_nonfinite_inputs) enter the filter as 0: said,
 * with their count. what names them ("direct-light sample", "indirect-light pixel", ...). */
static void warn_nonfinite_values(const char *what, long long nonfinite)
{
    if (nonfinite > 0)
        fprintf(stderr, "wedge: warning: FSF: %lld %s values were NaN or infinite and were filtered as 0\n", nonfinite,
                what);
}

/* The passes on one effect's inputs, then its AOVs: the shear and the width along the first
 * axis, the slope spread. */
static bool filter_and_record(ReconMethod *m, const FsfScratch *b, const FsfGrid *grid, const FsfGuides *gd,
                              bool keep_left_out, bool flat, float *value4, float *eta_aov, float *sigma_aov,
                              float *spread_aov, double *kernel_seconds, Diag *d)
{
    int w = m->g->width, h = m->g->height;
    FsfSamples s = {w, h, sample_store_capacity(m->store), b->count, b->y, b->v};
    bool ok = run_filter(m, &s, grid, b->px, gd, keep_left_out, flat, b->out4, value4, kernel_seconds, d);
    for (size_t i = 0; ok && i < (size_t)w * (size_t)h; ++i) {
        eta_aov[i] = b->px[i].eta_m[0];
        sigma_aov[i] = b->px[i].sigma_px[0];
        spread_aov[i] = b->k_hi[i] - b->k_lo[i];
    }
    return ok;
}

/* The light's frame for its geometric term (fsf_geo_term.h); mean_g: the per-pixel means. */
static FsfGeoTerm geo_term_of(const FsfLight *l, const float *mean_g)
{
    FsfGeoTerm t;
    const vec3 *v[4] = {&l->centre_world, &l->axis_world[0], &l->axis_world[1], &l->normal_world};
    float *o[4] = {t.centre, t.axis[0], t.axis[1], t.normal};
    for (int k = 0; k < 4; ++k) o[k][0] = v[k]->x, o[k][1] = v[k]->y, o[k][2] = v[k]->z;
    t.mean_g = mean_g;
    for (int a = 0; a < 2; ++a) t.ramp_m[a] = l->ramp_m[a], t.pose_m[a] = l->pose_m[a], t.motion_m[a] = l->motion_m[a];
    return t;
}

static bool filter_shadows(ReconMethod *m, float *value4, double *kernel_seconds, Diag *d)
{
    fsf_profile_begin(&m->prof);
    FsfScratch *b = scratch_with_values(m, d);
    if (!b) return false;
    fsf_profile_mark(&m->prof, "alloc");
    bool ok = true;
    long long nonfinite = 0;
    if (!gather(m, value4, b->usable, b->y, b->v, b->count, &nonfinite)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "FSF: the per-sample store lacks the light or direct field");
    }
    warn_nonfinite_values("direct-light sample", nonfinite);
    fsf_profile_mark(&m->prof, "gather");
    FsfParamsIn in = {m->g, m->store, &m->light, b->usable, m->mu, kept_windows(m)};
    if (ok && !fsf_pixel_params(&in, b->px, b->k_lo, b->k_hi)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF parameters");
    }
    fsf_profile_mark(&m->prof, "params");
    FsfGrid grid = fsf_light_grid(&m->light);
    FsfGuides gd = fsf_guides_default(m->g->pos4, m->g->nrm4, b->usable);
    /* under a budget the collapsed pixels' extras enter their own image (fsf_budget_plan.h) */
    size_t n = (size_t)m->g->width * (size_t)m->g->height;
    float *mean4 = NULL;
    if (ok && m->budget_spp > 0 && !(mean4 = malloc(n * 4 * sizeof(float)))) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF's pixel means");
    }
    if (mean4) memcpy(mean4, value4, n * 4 * sizeof(float));
    /* form 4: each sample weighted by its pixel's geometric term at the reprojected light
     * point (fsf_geo_term.h; docs/algorithms.md section 10) */
    FsfGeoTerm geo;
    if (ok && m->g->pos4 && m->g->nrm4) {
        geo = geo_term_of(&m->light, b->mean_g);
        fsf_geo_mean(&geo, m->g->pos4, m->g->nrm4, b->usable, grid.half_m, n, b->mean_g);
        gd.geo = &geo;
    }
    fsf_profile_mark(&m->prof, "geo_mean");
    if (ok)
        ok = filter_and_record(m, b, &grid, &gd, false, false, value4, m->eta_aov, m->sigma_aov, m->spread_aov,
                               kernel_seconds, d);
    fsf_profile_mark(&m->prof, "aovs");
    if (ok && mean4) fsf_blend_collapsed(b->px, b->usable, b->count, m->g, &grid, mean4, value4);
    free(mean4);
    fsf_profile_mark(&m->prof, "blend_free");
    fsf_profile_print(&m->prof, "shadows");
    return ok;
}

/* Indirect light (fsf_bounce.h): the bounce direction's v-plane in place of the light. */
static bool filter_indirect(ReconMethod *m, float *value4, double *kernel_seconds, Diag *d)
{
    fsf_profile_begin(&m->prof);
    FsfScratch *b = scratch(m, d);
    if (!b) return false;
    bool ok = true;
    /* under a budget the plan's parameters, found from the same stored samples
     * (fsf_bounce_kept.h): then no coordinate is needed */
    size_t n_px = (size_t)m->g->width * (size_t)m->g->height;
    bool reuse = fsf_bounce_kept_take(&m->bounce_kept, m->store, b->px, b->k_lo, b->k_hi, n_px);
    if (!fsf_bounce_coords(m->g, m->store, value4, b->usable, reuse ? NULL : b->y, b->count)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "FSF: the per-sample store lacks the bounce field");
    }
    FsfBounceIn in = {m->g, m->store, b->y, b->usable, m->mu, FSF_BOUNCE_PARALLAX_V, FSF_BOUNCE_H_MIN_FRAC};
    if (ok && !reuse && !fsf_bounce_params(&in, b->px, b->k_lo, b->k_hi)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF indirect parameters");
    }
    if (ok) warn_nonfinite_values("indirect-light pixel", fsf_flat_nonfinite_inputs(value4, b->usable, n_px));
    FsfGrid grid = fsf_bounce_grid();
    FsfGuides gd = fsf_guides_default(m->g->pos4, m->g->nrm4, b->usable);
    fsf_profile_mark(&m->prof, "samples_params");
    if (ok)
        ok = filter_and_record(m, b, &grid, &gd, false, true, value4, m->ind_eta_aov, m->ind_sigma_aov, m->ind_spread_aov,
                               kernel_seconds, d);
    fsf_profile_mark(&m->prof, "aovs_free");
    fsf_profile_print(&m->prof, "indirect");
    return ok;
}

static bool fsf_filter_light(ReconMethod *m, Effect e, float *value4, double *kernel_seconds, Diag *d)
{
    *kernel_seconds = 0.0;
    if (e == EFFECT_SOFT_SHADOWS) return filter_shadows(m, value4, kernel_seconds, d);
    if (e == EFFECT_INDIRECT) return filter_indirect(m, value4, kernel_seconds, d);
    return true;
}

/* Defocus (fsf_lens.h): the composite radiance, the lens in place of the light. Motion, if
 * asked for, is not filtered here (the method does not declare it). */
static bool fsf_filter_radiance(ReconMethod *m, EffectMask effects, float *value4, double *kernel_seconds, Diag *d)
{
    *kernel_seconds = 0.0;
    if (!effect_in(effects, EFFECT_DEFOCUS)) return true;
    int w = m->g->width, h = m->g->height;
    size_t n = (size_t)w * (size_t)h;
    fsf_profile_begin(&m->prof);
    FsfScratch *b = scratch_with_values(m, d);
    if (!b) return false;
    bool ok = true;
    long long nonfinite = 0;
    if (!fsf_lens_samples(m->store, w, h, value4, b->usable, b->y, b->v, b->count, &nonfinite)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "FSF: the per-sample store lacks the lens or radiance field");
    }
    warn_nonfinite_values("radiance sample", nonfinite);
    FsfLensIn in = {m->g, m->store, b->usable, m->mu, m->black_background};
    if (ok && m->lens_planned) { /* the plan's, from the same store: the same ranges */
        memcpy(b->px, m->lens_px, n * sizeof(FsfPixel));
        memcpy(b->k_lo, m->lens_k_lo, n * sizeof(float)), memcpy(b->k_hi, m->lens_k_hi, n * sizeof(float));
    } else if (ok && !fsf_lens_params(&in, b->px, b->k_lo, b->k_hi)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF lens parameters (or no depth field)");
    }
    FsfGrid grid = fsf_lens_grid();
    FsfGuides gd = fsf_guides_unguided(b->usable); /* defocus rejects no neighbour */
    fsf_profile_mark(&m->prof, "samples_params");
    if (ok)
        ok = filter_and_record(m, b, &grid, &gd, true, false, value4, m->lens_eta_aov, m->lens_sigma_aov,
                               m->lens_spread_aov, kernel_seconds, d);
    for (size_t i = 0; ok && i < n; ++i) m->straddle_aov[i] = fsf_lens_straddles(b->k_lo[i], b->k_hi[i]) ? 1.0f : 0.0f;
    fsf_profile_mark(&m->prof, "aovs_free");
    fsf_profile_print(&m->prof, "defocus");
    return ok;
}

static int fsf_aovs(ReconMethod *m, ReconAov *out, int max)
{
    int count = 0;
    if (effect_in(m->effects, EFFECT_SOFT_SHADOWS)) {
        if (count < max) out[count++] = (ReconAov){"fsf.eta_m_per_px", m->eta_aov, "light metres per pixel step"};
        if (count < max) out[count++] = (ReconAov){"fsf.sigma_px", m->sigma_aov, "filter sigma in pixels"};
        if (count < max) out[count++] = (ReconAov){"fsf.k_spread", m->spread_aov, "slope spread (light m per receiver m)"};
    }
    if (effect_in(m->effects, EFFECT_DEFOCUS)) {
        if (count < max)
            out[count++] = (ReconAov){"fsf.defocus.eta_lens_per_px", m->lens_eta_aov, "unit lens per pixel step"};
        if (count < max) out[count++] = (ReconAov){"fsf.defocus.sigma_px", m->lens_sigma_aov, "filter sigma in pixels"};
        if (count < max)
            out[count++] = (ReconAov){"fsf.defocus.k_spread", m->lens_spread_aov, "slope spread (unit lens per pixel)"};
        if (count < max)
            out[count++] = (ReconAov){"fsf.defocus.straddle", m->straddle_aov, "1: slopes straddle the focal plane"};
    }
    if (effect_in(m->effects, EFFECT_INDIRECT)) {
        if (count < max) out[count++] = (ReconAov){"fsf.indirect.shear", m->ind_eta_aov, "v units per pixel step"};
        if (count < max) out[count++] = (ReconAov){"fsf.indirect.sigma_px", m->ind_sigma_aov, "filter sigma in pixels"};
        if (count < max)
            out[count++] = (ReconAov){"fsf.indirect.k_spread", m->ind_spread_aov, "slope spread (v per receiver m)"};
    }
    return count;
}

const ReconMethodClass recon_method_fsf = {
    .name = "fsf",
    .title = "fast 4D sheared filtering (FSF): soft shadows, one-bounce diffuse indirect light and defocus, "
             "per-sample store, four 1D passes, 16 samples plus 36 where defocus straddles the focal plane (--spp N: "
             "3/4 of N in pass 1, 7/8 with defocus, the rest where the filters collapse)",
    .effects = EFFECT_BIT(EFFECT_SOFT_SHADOWS) | EFFECT_BIT(EFFECT_DEFOCUS) | EFFECT_BIT(EFFECT_INDIRECT),
    .adaptive = true,
    .sample_fields = FSF_FIELDS_SHADOWS | FSF_FIELDS_DEFOCUS | FSF_FIELDS_INDIRECT,
    .sample_fields_for = fsf_sample_fields_for,
    .shadow_geometry = EFFECT_BIT(EFFECT_SOFT_SHADOWS), /* occluder distances (shadow parameters) */
    .bounce_geometry = EFFECT_BIT(EFFECT_INDIRECT),     /* reflector distances (indirect parameters) */
    .pass1_spp = fsf_pass1_spp,
    .budget_pass1_share = fsf_budget_pass1_share,
    .create = fsf_create,
    .begin_pass = fsf_begin_pass,
    .add_sample = fsf_add_sample,
    .plan = fsf_plan,
    .open_device = fsf_open_device,
    .light_factor = fsf_light_factor,
    .filter_light = fsf_filter_light,
    .filter_radiance = fsf_filter_radiance,
    .shared = fsf_shared,
    .aovs = fsf_aovs,
    .destroy = fsf_destroy,
};
