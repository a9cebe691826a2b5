/* The AAF rendering pipeline (see aaf_render.h). */
#include "recon/aaf/aaf_render.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "recon/aaf/aaf_filter.h"
#include "recon/aaf/aaf_params.h"
#include "recon/aaf/aaf_pixel_params.h"
#include "recon/aaf/aaf_stats.h"
#include "recon/cl_runtime.h"
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
/* Mixed pixels (aaf_stats.c: samples on different surfaces over the shutter or lens, which
 * includes antialiased silhouettes) are left out of the world-space filters and are plain
 * Monte Carlo; they get this many times mu times the pass-1 count (capped at 100 mu: 144 at
 * mu 2 with 9 in pass 1), so that their noise does not stand out against the filtered
 * neighbours and still falls as mu grows (consistency; with a fixed count they were the error
 * floor of the mu sweep on the soft-shadow bench scene). They are a few percent of the pixels
 * but, being unfiltered, the cheapest error to remove: going from 2 to 8 here cut the
 * soft-shadow bench scene's error by 29% for 10% more samples (docs/algorithms.md 4.1). */
#define MIXED_SPP_PER_MU 8.0f
/* Albedo below this is treated as black: the irradiance cannot be recovered there. */
#define MIN_ALBEDO 1.0e-4f
/* Pixels whose unoccluded irradiance is below this fraction of the frame's largest (facing
 * away from the light, grazing) keep their own direct light: dividing by it is unstable. */
#define MIN_SHADE_REL 1.0e-3f

const char *aaf_effect_name(int effect)
{
    static const char *names[AAF_EFFECT_COUNT] = {"shadows", "indirect", "defocus"};
    return effect >= 0 && effect < AAF_EFFECT_COUNT ? names[effect] : "?";
}

AafRenderOptions aaf_render_options_default(void)
{
    AafRenderOptions o;
    memset(&o, 0, sizeof o);
    for (int e = 0; e < AAF_EFFECT_COUNT; ++e) o.want[e] = true;
    return o;
}

void aaf_render_result_free(AafRenderResult *res)
{
    free(res->rgb);
    for (int e = 0; e < AAF_EFFECT_COUNT; ++e) free(res->beta_px[e]);
    free(res->spp);
    memset(res, 0, sizeof *res);
}

static double wall_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static AafCameraModel camera_model(const Camera *c)
{
    AafCameraModel m;
    m.lens_radius_world = c->lens_radius_world;
    m.focal_distance_world = c->focal_distance_world;
    /* screen units per pixel, times tan(fov/2): world size of one pixel at camera depth 1 */
    m.pixel_angle = (c->screen_max[0] - c->screen_min[0]) / (float)c->width_px * c->tan_half_fov;
    return m;
}

/* An environment ("infinite") light is the only radiance a ray that escapes the scene sees. */
static bool has_light_at_infinity(const Renderer *r)
{
    RenderLightInfo info;
    for (int l = 0; l < renderer_light_count(r); ++l)
        if (renderer_light_info(r, l, &info) && info.kind == RENDER_LIGHT_INFINITE) return true;
    return false;
}

/* Per-pixel means of the frame's sums (3 floats per pixel). */
typedef struct {
    float *color, *direct, *indirect, *emission, *albedo;
    float *unf_direct, *unf_indirect; /* SampleRecord.unfiltered, split (aaf_stats_add) */
} Means;

static void means_free(Means *m)
{
    free(m->unf_direct);
    free(m->unf_indirect);
    free(m->color);
    free(m->direct);
    free(m->indirect);
    free(m->emission);
    free(m->albedo);
}

/* with_color: also the total colour (only needed when nothing is filtered). */
static bool means_resolve(const Frame *f, Means *m, bool with_color, long long *guarded)
{
    size_t n3 = 3 * (size_t)f->width * (size_t)f->height;
    m->color = malloc((with_color ? n3 : 3) * sizeof(float));
    m->direct = malloc(n3 * sizeof(float));
    m->indirect = malloc(n3 * sizeof(float));
    m->emission = malloc(n3 * sizeof(float));
    m->albedo = malloc(n3 * sizeof(float));
    m->unf_direct = calloc(n3, sizeof(float));
    m->unf_indirect = calloc(n3, sizeof(float));
    if (!m->color || !m->direct || !m->indirect || !m->emission || !m->albedo || !m->unf_direct || !m->unf_indirect)
        return false;
    if (with_color) *guarded += frame_resolve3(f, f->color, m->color);
    *guarded += frame_resolve3(f, f->direct, m->direct);
    *guarded += frame_resolve3(f, f->indirect, m->indirect);
    *guarded += frame_resolve3(f, f->emission, m->emission);
    *guarded += frame_resolve3(f, f->albedo, m->albedo);
    return true;
}

/* ---- the host-side per-pixel work around the filters, fused and run on both cores ----
 *
 * Two passes over the image replace the earlier chain of whole-image loops (resolve five means,
 * split off the unfiltered light, demodulate, filter, remodulate, add up): `prepare` reads the
 * frame's sums once and writes only what the filters read; `composite` recomputes the few means
 * it needs with the same arithmetic (so the image is bit-identical to the chained version) and
 * writes the output. Each pixel is independent; guard counts are kept per part. */
typedef struct {
    const Frame *frame;
    const AafStats *stats;
    const AafDerived *derived;
    const float *shade;          /* r(x) for direct light (NULL: 1) */
    float shade_min;
    bool on_shadows, on_indirect;
    float *value_direct4, *value_indirect4; /* demodulated inputs of the filters (NULL: off) */
    float *spp_out;
    long long guarded[RECON_PARTS];
} PreparePass;

/* frame_resolve3's per-channel mean (render/frame.c), with the same arithmetic. */
static inline float sum_mean(float sum, float spp, long long *guarded)
{
    float v = spp > 0.0f ? sum / spp : 0.0f;
    if (!isfinite(v)) {
        v = 0.0f;
        ++*guarded;
    }
    return v;
}

/* The light the filters must not blur (SampleRecord.unfiltered), per channel: it is taken out
 * of the direct and indirect means and added back after filtering. The stats saw the same
 * samples as the frame (the sink ran in both passes), so their counts are the frame's. */
static inline void unfiltered_means(const AafStats *st, size_t i, float ud[3], float ui[3])
{
    float inv = st->samples[i] > 0 ? 1.0f / (float)st->samples[i] : 0.0f;
    for (int k = 0; k < 3; ++k) {
        float d = st->unf_direct_sum[3 * i + k] * inv, u = st->unf_indirect_sum[3 * i + k] * inv;
        ud[k] = isfinite(d) ? d : 0.0f;
        ui[k] = isfinite(u) ? u : 0.0f;
    }
}

/* value4 = radiance / (albedo * shade): what the filters assume smooth (shade = r(x) for direct
 * light, so that the visibility is filtered, AAF-shadow eq. 1). Usable where there is a surface
 * with non-black albedo and shade above shade_min; elsewhere the raw radiance, flagged unusable
 * (kept as it is, not shared). */
static inline void demodulate_pixel(const float rad[3], const float a[3], float sh, bool usable, float *value4)
{
    bool ok = usable && a[0] > MIN_ALBEDO && a[1] > MIN_ALBEDO && a[2] > MIN_ALBEDO;
    for (int k = 0; k < 3; ++k) value4[k] = ok ? rad[k] / (a[k] * sh) : rad[k];
    value4[3] = ok ? 1.0f : 0.0f;
}

static void prepare_range(void *ctx, size_t begin, size_t end, int part)
{
    PreparePass *pp = ctx;
    const Frame *f = pp->frame;
    const AafDerived *dv = pp->derived;
    long long guarded = 0;
    for (size_t i = begin; i < end; ++i) {
        float spp = f->spp[i];
        pp->spp_out[i] = spp;
        float a[3], dir[3], ind[3], ud[3], ui[3];
        for (int k = 0; k < 3; ++k) {
            dir[k] = sum_mean(f->direct[3 * i + k], spp, &guarded);
            ind[k] = sum_mean(f->indirect[3 * i + k], spp, &guarded);
            (void)sum_mean(f->emission[3 * i + k], spp, &guarded); /* counted like the others */
            a[k] = sum_mean(f->albedo[3 * i + k], spp, &guarded);
        }
        unfiltered_means(pp->stats, i, ud, ui);
        for (int k = 0; k < 3; ++k) {
            dir[k] -= ud[k];
            ind[k] -= ui[k];
        }
        bool surface = dv->hit[i] && !dv->mixed[i];
        if (pp->on_shadows) {
            float sh = pp->shade ? pp->shade[i] : 1.0f;
            demodulate_pixel(dir, a, sh, surface && sh > pp->shade_min, pp->value_direct4 + 4 * i);
        }
        if (pp->on_indirect) demodulate_pixel(ind, a, 1.0f, surface, pp->value_indirect4 + 4 * i);
    }
    pp->guarded[part] = guarded;
}

typedef struct {
    const Frame *frame;
    const AafStats *stats;
    const AafDerived *derived;
    const float *shade;                           /* as in PreparePass */
    const float *filtered_direct4, *filtered_indirect4; /* NULL: that light was not filtered */
    float *rgb;
    float *defocus_value4, *defocus_slope4;       /* NULL: no defocus filter follows */
} CompositePass;

/* Adds albedo * shade * filtered value, or the raw radiance where it was not demodulated. */
static inline float remodulate(const float *value4, int k, float albedo, float sh)
{
    return value4[3] != 0.0f ? albedo * sh * value4[k] : value4[k];
}

static void composite_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    CompositePass *cp = ctx;
    const Frame *f = cp->frame;
    long long ignored = 0; /* counted by prepare_range already */
    for (size_t i = begin; i < end; ++i) {
        float spp = f->spp[i], ud[3], ui[3], v[3];
        unfiltered_means(cp->stats, i, ud, ui);
        float sh = cp->shade ? cp->shade[i] : 1.0f;
        for (int k = 0; k < 3; ++k) {
            size_t j = 3 * i + (size_t)k;
            float a = sum_mean(f->albedo[j], spp, &ignored);
            /* emission + direct + indirect + unfiltered, added in this order */
            v[k] = sum_mean(f->emission[j], spp, &ignored);
            v[k] += cp->filtered_direct4 ? remodulate(cp->filtered_direct4 + 4 * i, k, a, sh)
                                         : sum_mean(f->direct[j], spp, &ignored) - ud[k];
            v[k] += cp->filtered_indirect4 ? remodulate(cp->filtered_indirect4 + 4 * i, k, a, 1.0f)
                                           : sum_mean(f->indirect[j], spp, &ignored) - ui[k];
            v[k] += ud[k] + ui[k];
        }
        /* the pixel's filter inputs are all read: defocus_value4 may reuse their buffers */
        for (int k = 0; k < 3; ++k) cp->rgb[3 * i + (size_t)k] = v[k];
        if (cp->defocus_value4) {
            float *dv = cp->defocus_value4 + 4 * i;
            dv[0] = v[0];
            dv[1] = v[1];
            dv[2] = v[2];
            dv[3] = 1.0f;
            /* Each pixel's sharpest CoC slope (the end of its range nearest 0; 0 if the range
             * straddles the focal plane): the kernel keeps sharper neighbours out of a blur, e.g.
             * an in-focus object's edge pixels out of the defocused background behind it. */
            float lo = cp->derived->coc_min[i], hi = cp->derived->coc_max[i];
            float sharp = (lo <= 0.0f && hi >= 0.0f) ? 0.0f : (fabsf(lo) < fabsf(hi) ? lo : hi);
            float *sl = cp->defocus_slope4 + 4 * i;
            sl[0] = isfinite(sharp) && lo <= hi ? sharp : 0.0f;
            sl[1] = sl[2] = sl[3] = 0.0f;
        }
    }
}

/* Last pass: the defocus filter's output (if any) into rgb, widths in pixels for the AOVs,
 * and no non-finite value left in the image. */
typedef struct {
    float *rgb;
    const float *defocus_out4;    /* NULL: no defocus filter ran */
    const float *beta[AAF_EFFECT_COUNT];
    const float *pixel_world;
    float *beta_px[AAF_EFFECT_COUNT];
    long long guarded[RECON_PARTS];
} FinishPass;

static void finish_range(void *ctx, size_t begin, size_t end, int part)
{
    FinishPass *fp = ctx;
    long long bad = 0;
    for (size_t i = begin; i < end; ++i) {
        for (int k = 0; k < 3; ++k) {
            float v = fp->defocus_out4 ? fp->defocus_out4[4 * i + (size_t)k] : fp->rgb[3 * i + (size_t)k];
            if (!isfinite(v)) {
                v = 0.0f;
                ++bad;
            }
            fp->rgb[3 * i + (size_t)k] = v;
        }
        for (int e = 0; e < AAF_EFFECT_COUNT; ++e) {
            if (!fp->beta[e]) continue;
            const float *pw = e == AAF_EFFECT_DEFOCUS ? NULL : fp->pixel_world;
            float b = pw ? (pw[i] > 0.0f ? fp->beta[e][i] / pw[i] : 0.0f) : fp->beta[e][i];
            fp->beta_px[e][i] = isfinite(b) ? b : (float)AAF_FILTER_RADIUS_CAP_PX;
        }
    }
    fp->guarded[part] = bad;
}

typedef struct {
    int n;
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
    ParamsPass pp = {(int)n, beta, pixel_world, param};
    recon_parallel_for(n, params_range, &pp);
}

/* Creating the OpenCL context and building the kernels takes 50-150 ms on PoCL: do it on a
 * helper thread while pass 2 traces. */
typedef struct {
    pthread_t thread;
    bool started;
    const char *device_choice;
    int width, height;
    ClRuntime *rt;
    AafFilter *filter;
    Diag diag;
} ClOpener;

static void *opener_main(void *arg)
{
    ClOpener *op = arg;
    op->rt = cl_runtime_create(op->device_choice, &op->diag);
    if (op->rt) {
        op->filter = aaf_filter_create(op->rt, &op->diag);
        if (op->filter && !aaf_filter_reserve(op->filter, op->width, op->height, &op->diag)) {
            aaf_filter_destroy(op->filter);
            op->filter = NULL;
        }
        if (!op->filter) {
            cl_runtime_destroy(op->rt);
            op->rt = NULL;
        }
    }
    return NULL;
}

static void opener_start(ClOpener *op, const char *device_choice, int width, int height)
{
    op->device_choice = device_choice;
    op->width = width;
    op->height = height;
    op->started = pthread_create(&op->thread, NULL, opener_main, op) == 0;
    if (!op->started) opener_main(op); /* no thread: do it now */
}

/* Waits for the helper (if any) and reports its failure into d (may be NULL). */
static bool opener_join(ClOpener *op, Diag *d)
{
    if (op->started) {
        pthread_join(op->thread, NULL);
        op->started = false;
    }
    if (op->rt) return true;
    if (d) *d = op->diag;
    return false;
}

bool aaf_render(Renderer *r, const AafRenderOptions *o, Frame *frame, AafRenderResult *res, Diag *d)
{
    memset(res, 0, sizeof *res);
    double t_filter0 = wall_seconds(), t_pass2 = 0.0;
    int w = renderer_width(r), h = renderer_height(r);
    size_t n = (size_t)w * (size_t)h;
    res->width = w;
    res->height = h;
    Effects fx = renderer_effects(r);
    res->present[AAF_EFFECT_SHADOWS] = fx.soft_shadows;
    res->present[AAF_EFFECT_INDIRECT] = fx.indirect;
    res->present[AAF_EFFECT_DEFOCUS] = fx.defocus;
    bool on[AAF_EFFECT_COUNT];
    bool any = false;
    for (int e = 0; e < AAF_EFFECT_COUNT; ++e) {
        on[e] = res->present[e] && o->want[e];
        res->filters[e] = on[e] ? "aaf" : "none";
        any = any || on[e];
    }
    res->pass1_spp = (on[AAF_EFFECT_INDIRECT] || on[AAF_EFFECT_DEFOCUS]) ? PASS1_SPP_OTHER : PASS1_SPP_SHADOWS;
    if (!any) res->pass1_spp = renderer_spp(r); /* nothing to filter: plain Monte Carlo */
    /* The device opens during pass 2 (opener_start); a wrong --cl-device or a missing driver
     * is found now, before any sample is traced. */
    if (any && !cl_runtime_check_device(o->cl_device, d)) return false;

    AafShadowConfig shadow_cfg = aaf_shadow_config_default();
    AafIndirectConfig indirect_cfg = aaf_indirect_config_default();
    AafDefocusConfig defocus_cfg = aaf_defocus_config_default();
    if (o->mu > 0.0f) shadow_cfg.mu = indirect_cfg.mu = defocus_cfg.mu = o->mu;
    defocus_cfg.black_background = !has_light_at_infinity(r);

    res->rgb = calloc(3 * n, sizeof(float));
    res->spp = calloc(n, sizeof(float));
    AafStats stats;
    AafDerived derived = {0};
    Means means = {0};
    float *beta[AAF_EFFECT_COUNT] = {NULL, NULL, NULL};
    int *spp_effect = malloc(n * sizeof(int)), *spp_extra = calloc(n, sizeof(int));
    float *value4 = malloc(4 * n * sizeof(float)), *param = malloc(2 * n * sizeof(float));
    float *filtered4 = malloc(4 * n * sizeof(float)), *shade = malloc(n * sizeof(float));
    ClRuntime *rt = NULL;
    AafFilter *filter = NULL;
    AafLightGeom *lights = NULL;
    float *slope4 = malloc(4 * n * sizeof(float));
    ClOpener opener;
    memset(&opener, 0, sizeof opener);
    bool ok = false, stats_ok = aaf_stats_init(&stats, w, h, camera_model(renderer_camera(r)));
    if (!res->rgb || !res->spp || !stats_ok || !spp_effect || !spp_extra || !value4 || !param || !filtered4 || !shade ||
        !slope4) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for AAF buffers (%dx%d)", w, h);
        goto done;
    }
    SampleSink sink = {aaf_stats_add, &stats};
    int light_count = renderer_light_count(r);
    lights = calloc(light_count > 0 ? (size_t)light_count : 1, sizeof *lights);
    if (lights) {
        aaf_lights_from_renderer(r, lights, light_count);
        stats.lights = lights;
        stats.light_count = light_count;
    }

    /* ---- pass 1: sparse sampling ---- */
    /* Shadow and bounce ray geometry is for the shadow and indirect filters; defocus needs
     * only each sample's depth, so without them the shadow rays stay occlusion queries. */
    renderer_set_record_ray_geometry(r, on[AAF_EFFECT_SHADOWS] || on[AAF_EFFECT_INDIRECT]);
    bool complete = render_pass(r, 0, NULL, res->pass1_spp, frame, any ? &sink : NULL);
    renderer_set_record_ray_geometry(r, true); /* as the caller set it up (aaf_render.h) */
    t_filter0 = wall_seconds();
    if (complete && any) {
        /* ---- parameters per effect ---- */
        if (!aaf_derive(&stats, &derived)) {
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for AAF statistics");
            goto done;
        }
        AafPixelStats ps = aaf_derived_pixel_stats(&derived);
        for (int e = 0; e < AAF_EFFECT_COUNT; ++e) {
            if (!on[e]) continue;
            beta[e] = calloc(n, sizeof(float));
            res->beta_px[e] = calloc(n, sizeof(float));
            if (!beta[e] || !res->beta_px[e]) {
                diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for AAF maps");
                goto done;
            }
            float mu = e == 0 ? shadow_cfg.mu : e == 1 ? indirect_cfg.mu : defocus_cfg.mu;
            /* Far from any occluder/reflector: radius 2 beta up to FAR_RADIUS_PX (less near
             * one, aaf_pixel_params.h), shrinking with mu like every other width. */
            float far_beta_px = (float)FAR_RADIUS_PX / fmaxf(mu, 2.0f);
            /* Their light is still Monte Carlo (the unoccluded direct light of an area light,
             * indirect light from far away): from mu 2 on their samples grow with mu like the
             * width shrinks, so that they too converge (the paper's fixed pass-1 count made
             * them the error floor of a mu sweep on the soft-shadow bench scene). */
            int far_spp = aaf_clamp_spp((float)res->pass1_spp * fmaxf(1.0f, 0.5f * mu), res->pass1_spp, 100.0f * mu);
            AafImageConfig ic = {BORROW_RADIUS_PX, res->pass1_spp, 100.0f * mu, far_beta_px, far_spp};
            if (e == AAF_EFFECT_SHADOWS) aaf_shadow_params_image(&ps, &shadow_cfg, &ic, beta[e], spp_effect);
            if (e == AAF_EFFECT_INDIRECT)
                aaf_indirect_params_image(&ps, &indirect_cfg, &ic, derived.scene_size_world, beta[e], spp_effect);
            if (e == AAF_EFFECT_DEFOCUS) aaf_defocus_params_image(&ps, &defocus_cfg, &ic, beta[e], spp_effect);
            for (size_t i = 0; i < n; ++i) { /* the pixel takes the most demanding effect's count */
                int extra = spp_effect[i] - res->pass1_spp;
                if (extra > spp_extra[i]) spp_extra[i] = extra;
            }
        }
        float mu_max = 0.0f;
        for (int e = 0; e < AAF_EFFECT_COUNT; ++e)
            if (on[e]) mu_max = fmaxf(mu_max, e == 0 ? shadow_cfg.mu : e == 1 ? indirect_cfg.mu : defocus_cfg.mu);
        int mixed_spp = aaf_clamp_spp(MIXED_SPP_PER_MU * mu_max * (float)res->pass1_spp, res->pass1_spp,
                                      100.0f * mu_max);
        for (size_t i = 0; i < n; ++i) {
            int extra = mixed_spp - res->pass1_spp;
            if (derived.mixed[i] && extra > spp_extra[i]) spp_extra[i] = extra;
        }
        /* ---- pass 2: adaptive sampling, while OpenCL starts up ---- */
        opener_start(&opener, o->cl_device, w, h);
        /* Parameters come from pass 1; pass 2 only refines the guides, so it records no ray
         * geometry: its shadow rays become any-hit occlusion queries instead of closest-hit
         * traces (the same visibility, cheaper per sample). */
        stats.collect_rays = false;
        renderer_set_record_ray_geometry(r, false);
        t_pass2 = wall_seconds();
        /* Pass 2 continues each pixel's pass-1 samples as one sampler set (with Sobol',
         * the first n points of each dimension's sequence): an independent second set
         * integrates worse (docs/sampling.md, "Continuing a pixel's samples"). */
        complete = render_pass_more(r, 0, res->pass1_spp, spp_extra, frame, &sink);
        renderer_set_record_ray_geometry(r, true); /* as the caller set it up (aaf_render.h) */
        t_pass2 = wall_seconds() - t_pass2;
    }
    if (!complete || !any) { /* cancelled, or nothing to filter: the plain mean */
        if (!means_resolve(frame, &means, true, &res->guarded_events)) {
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for AAF buffers");
            goto done;
        }
        for (size_t i = 0; i < n; ++i) res->spp[i] = frame->spp[i];
        res->spp_avg = frame_spp_avg(frame);
        res->cancelled = !complete;
        memcpy(res->rgb, means.color, 3 * n * sizeof(float));
        for (int e = 0; e < AAF_EFFECT_COUNT; ++e) {
            if (!complete) res->filters[e] = "none";
            free(res->beta_px[e]);
            res->beta_px[e] = NULL;
        }
        ok = true;
        goto done;
    }
    res->spp_avg = frame_spp_avg(frame);

    /* ---- filters ---- */
    aaf_derive_guides(&stats, &derived); /* the guides of both passes */
    /* Direct light: the visibility (direct / (albedo r(x))) is filtered, with distances in the
     * plane of the light (eq. 12), and multiplied back by albedo r(x) (eq. 1). Indirect light:
     * irradiance (albedo divided out), distances in each receiver's tangent plane (AAF-GI
     * eq. 16). Both inputs are made in one pass over the frame. */
    const float *shade_used = NULL;
    float shade_min = 0.0f;
    if (on[AAF_EFFECT_SHADOWS]) {
        aaf_unoccluded_irradiance(&derived, shade);
        float shade_max = 0.0f;
        for (size_t i = 0; i < n; ++i) shade_max = fmaxf(shade_max, shade[i]);
        shade_used = derived.light_known ? shade : NULL;
        shade_min = MIN_SHADE_REL * shade_max;
    }
    float *value_direct4 = on[AAF_EFFECT_SHADOWS] ? value4 : NULL;
    float *value_indirect4 = on[AAF_EFFECT_INDIRECT] ? filtered4 : NULL;
    PreparePass prep = {frame, &stats, &derived, shade_used, shade_min, on[AAF_EFFECT_SHADOWS],
                        on[AAF_EFFECT_INDIRECT], value_direct4, value_indirect4, res->spp, {0}};
    recon_parallel_for(n, prepare_range, &prep);
    for (int p = 0; p < RECON_PARTS; ++p) res->guarded_events += prep.guarded[p];

    if (!opener_join(&opener, d)) goto done;
    rt = opener.rt;
    filter = opener.filter;
    opener.rt = NULL;
    opener.filter = NULL;
    snprintf(res->device, sizeof res->device, "%s", cl_runtime_device_label(rt));
    if (!aaf_filter_set_guides(filter, w, h, derived.pos4, derived.nrm4, d)) goto done;
    AafFilterRules world_rules = aaf_filter_rules_default(AAF_DIST_WORLD);
    /* a neighbour with under half the centre's width holds sharper shadow (indirect) detail than
     * the centre's filter passes: the contact shadow at a thin occluder's foot inside the wide
     * penumbra of a high one (docs/algorithms.md 4) */
    world_rules.sharp_beta_ratio = 0.5f;
    double kernel_s = 0.0;
    /* each filter runs in place on its own input buffer */
    if (value_direct4) {
        make_params(n, beta[AAF_EFFECT_SHADOWS], derived.pixel_world, param);
        if (!aaf_filter_run(filter, value_direct4, derived.plane4, param, &world_rules, value_direct4, &kernel_s, d))
            goto done;
        res->seconds_kernels += kernel_s;
    }
    if (value_indirect4) {
        make_params(n, beta[AAF_EFFECT_INDIRECT], derived.pixel_world, param);
        if (!aaf_filter_run(filter, value_indirect4, NULL, param, &world_rules, value_indirect4, &kernel_s, d))
            goto done;
        res->seconds_kernels += kernel_s;
    }
    /* Composite; defocus then filters the primary radiance itself, in pixels, across objects
     * (its input reuses the direct light's buffer, pixel by pixel after reading it). */
    CompositePass comp = {frame, &stats, &derived, shade_used, value_direct4, value_indirect4, res->rgb,
                          on[AAF_EFFECT_DEFOCUS] ? value4 : NULL, on[AAF_EFFECT_DEFOCUS] ? slope4 : NULL};
    recon_parallel_for(n, composite_range, &comp);
    if (on[AAF_EFFECT_DEFOCUS]) {
        AafFilterRules pixel_rules = aaf_filter_rules_default(AAF_DIST_PIXEL);
        make_params(n, beta[AAF_EFFECT_DEFOCUS], NULL, param);
        if (!aaf_filter_run(filter, value4, slope4, param, &pixel_rules, value4, &kernel_s, d)) goto done;
        res->seconds_kernels += kernel_s;
    }
    FinishPass fin;
    memset(&fin, 0, sizeof fin);
    fin.rgb = res->rgb;
    fin.defocus_out4 = on[AAF_EFFECT_DEFOCUS] ? value4 : NULL;
    fin.pixel_world = derived.pixel_world;
    for (int e = 0; e < AAF_EFFECT_COUNT; ++e) {
        fin.beta[e] = on[e] ? beta[e] : NULL;
        fin.beta_px[e] = on[e] ? res->beta_px[e] : NULL;
    }
    recon_parallel_for(n, finish_range, &fin);
    for (int p = 0; p < RECON_PARTS; ++p) res->guarded_events += fin.guarded[p];
    ok = true;

done:
    /* seconds_filter: everything between the passes and after them that is not tracing */
    res->seconds_filter = wall_seconds() - t_filter0 - t_pass2;
    if (!ok) aaf_render_result_free(res);
    opener_join(&opener, NULL);
    aaf_filter_destroy(opener.filter);
    cl_runtime_destroy(opener.rt);
    aaf_filter_destroy(filter);
    cl_runtime_destroy(rt);
    means_free(&means);
    aaf_derived_free(&derived);
    if (stats_ok) aaf_stats_free(&stats);
    for (int e = 0; e < AAF_EFFECT_COUNT; ++e) free(beta[e]);
    free(spp_effect);
    free(spp_extra);
    free(value4);
    free(param);
    free(filtered4);
    free(shade);
    free(lights);
    free(slope4);
    return ok;
}
