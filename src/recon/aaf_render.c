/* The AAF rendering pipeline (see aaf_render.h). */
#include "recon/aaf_render.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "recon/aaf_filter.h"
#include "recon/aaf_params.h"
#include "recon/aaf_pixel_params.h"
#include "recon/aaf_stats.h"
#include "recon/cl_runtime.h"

/* AAF-shadow Sec. 6: 9 light samples; AAF-GI Sec. 5: 16 hemisphere samples. Defocus uses 16
 * lens samples to see the pixel's range of depths. */
#define PASS1_SPP_SHADOWS 9
#define PASS1_SPP_OTHER 16
/* AAF-shadow Sec. 6: unoccluded pixels borrow from a 5 pixel radius. */
#define BORROW_RADIUS_PX 5
/* Filter taps up to 2 beta (95% of a Gaussian's mass; the rest is renormalised away). */
#define RADIUS_SIGMAS 2.0f
/* Mixed pixels (aaf_stats.c: samples on different surfaces over the shutter or lens, which
 * includes antialiased silhouettes) are left out of the world-space filters and are plain
 * Monte Carlo; they get this many times mu times the pass-1 count (32 at mu 1, 64 at mu 2 with
 * 16 in pass 1), so that their noise does not stand out against the filtered neighbours and
 * still falls as mu grows (consistency; with a fixed count they were the error floor of the
 * mu sweep on the soft-shadow bench scene). */
#define MIXED_SPP_PER_MU 2.0f
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

/* The light the filters must not blur (SampleRecord.unfiltered) is taken out of the direct and
 * indirect means here and added back after filtering. The stats saw the same samples as the
 * frame (the sink ran in both passes), so their counts are the frame's. */
static void means_split_unfiltered(Means *m, const AafStats *st, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        float inv = st->samples[i] > 0 ? 1.0f / (float)st->samples[i] : 0.0f;
        for (int k = 0; k < 3; ++k) {
            size_t j = 3 * i + (size_t)k;
            float ud = st->unf_direct_sum[j] * inv, ui = st->unf_indirect_sum[j] * inv;
            m->unf_direct[j] = isfinite(ud) ? ud : 0.0f;
            m->unf_indirect[j] = isfinite(ui) ? ui : 0.0f;
            m->direct[j] -= m->unf_direct[j];
            m->indirect[j] -= m->unf_indirect[j];
        }
    }
}

/* value4 = radiance / (albedo * shade): what the filters assume smooth. shade (NULL: 1) is the
 * unoccluded irradiance r(x) for direct light, so that what is filtered is the visibility
 * (AAF-shadow eq. 1). Usable where there is a surface with non-black albedo and shade above
 * shade_min; elsewhere the raw radiance, unusable (kept as it is, not shared). */
static void demodulate(size_t n, const float *radiance3, const float *albedo3, const float *shade, float shade_min,
                       const unsigned char *hit, const unsigned char *mixed, float *value4)
{
    for (size_t i = 0; i < n; ++i) {
        const float *a = albedo3 + 3 * i;
        float sh = shade ? shade[i] : 1.0f;
        bool ok = hit[i] && !mixed[i] && a[0] > MIN_ALBEDO && a[1] > MIN_ALBEDO && a[2] > MIN_ALBEDO && sh > shade_min;
        for (int k = 0; k < 3; ++k) value4[4 * i + k] = ok ? radiance3[3 * i + k] / (a[k] * sh) : radiance3[3 * i + k];
        value4[4 * i + 3] = ok ? 1.0f : 0.0f;
    }
}

/* Adds albedo * shade * filtered value (or the raw radiance where it was not demodulated). */
static void remodulate_add(size_t n, const float *value4, const float *albedo3, const float *shade, float *out3)
{
    for (size_t i = 0; i < n; ++i) {
        float sh = shade ? shade[i] : 1.0f;
        for (int k = 0; k < 3; ++k)
            out3[3 * i + k] += value4[4 * i + 3] != 0.0f ? albedo3[3 * i + k] * sh * value4[4 * i + k] : value4[4 * i + k];
    }
}

static void beta_to_px(size_t n, const float *beta, const float *pixel_world, float *beta_px)
{
    for (size_t i = 0; i < n; ++i) {
        float b = pixel_world ? (pixel_world[i] > 0.0f ? beta[i] / pixel_world[i] : 0.0f) : beta[i];
        beta_px[i] = isfinite(b) ? b : (float)AAF_FILTER_RADIUS_CAP_PX;
    }
}

static long long guard_finite(float *a, size_t n)
{
    long long bad = 0;
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(a[i])) {
            a[i] = 0.0f;
            ++bad;
        }
    return bad;
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

    AafShadowConfig shadow_cfg = aaf_shadow_config_default();
    AafIndirectConfig indirect_cfg = aaf_indirect_config_default();
    AafDefocusConfig defocus_cfg = aaf_defocus_config_default();
    if (o->mu > 0.0f) shadow_cfg.mu = indirect_cfg.mu = defocus_cfg.mu = o->mu;

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
    bool complete = render_pass(r, 0, NULL, res->pass1_spp, frame, any ? &sink : NULL);
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
            /* Far from any occluder/reflector: radius 2 beta within the borrow radius, and
             * shrinking with mu like every other width (aaf_pixel_params.h). */
            float far_beta_px = (float)BORROW_RADIUS_PX / fmaxf(mu, 2.0f);
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
        stats.collect_rays = false; /* parameters come from pass 1; pass 2 refines the guides */
        t_pass2 = wall_seconds();
        complete = render_pass(r, 1, spp_extra, 0, frame, &sink);
        t_pass2 = wall_seconds() - t_pass2;
    }
    if (!means_resolve(frame, &means, !complete || !any, &res->guarded_events)) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for AAF buffers");
        goto done;
    }
    if (complete && any) means_split_unfiltered(&means, &stats, n);
    for (size_t i = 0; i < n; ++i) res->spp[i] = frame->spp[i];
    res->spp_avg = frame_spp_avg(frame);
    if (!complete || !any) {
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

    /* ---- filters ---- */
    aaf_derive_guides(&stats, &derived); /* the guides of both passes */
    if (!opener_join(&opener, d)) goto done;
    rt = opener.rt;
    filter = opener.filter;
    opener.rt = NULL;
    opener.filter = NULL;
    snprintf(res->device, sizeof res->device, "%s", cl_runtime_device_label(rt));
    if (!aaf_filter_set_guides(filter, w, h, derived.pos4, derived.nrm4, d)) goto done;
    AafFilterRules world_rules = aaf_filter_rules_default(AAF_DIST_WORLD);
    double kernel_s = 0.0;

    /* Direct light: the visibility (direct / (albedo r(x))) is filtered, with distances in the
     * plane of the light (eq. 12), and multiplied back by albedo r(x) (eq. 1). */
    for (size_t i = 0; i < 3 * n; ++i) res->rgb[i] = means.emission[i];
    if (on[AAF_EFFECT_SHADOWS]) {
        aaf_unoccluded_irradiance(&derived, shade);
        float shade_max = 0.0f;
        for (size_t i = 0; i < n; ++i) shade_max = fmaxf(shade_max, shade[i]);
        demodulate(n, means.direct, means.albedo, derived.light_known ? shade : NULL, MIN_SHADE_REL * shade_max,
                   derived.hit, derived.mixed, value4);
        aaf_filter_make_params((int)n, beta[AAF_EFFECT_SHADOWS], derived.pixel_world, RADIUS_SIGMAS,
                               AAF_FILTER_RADIUS_CAP_PX, param);
        if (!aaf_filter_run(filter, value4, derived.plane4, param, &world_rules, filtered4, &kernel_s, d)) goto done;
        res->seconds_kernels += kernel_s;
        remodulate_add(n, filtered4, means.albedo, derived.light_known ? shade : NULL, res->rgb);
    } else {
        for (size_t i = 0; i < 3 * n; ++i) res->rgb[i] += means.direct[i];
    }
    /* Indirect light: irradiance (albedo divided out), distances in each receiver's tangent
     * plane (AAF-GI eq. 16). */
    if (on[AAF_EFFECT_INDIRECT]) {
        demodulate(n, means.indirect, means.albedo, NULL, 0.0f, derived.hit, derived.mixed, value4);
        aaf_filter_make_params((int)n, beta[AAF_EFFECT_INDIRECT], derived.pixel_world, RADIUS_SIGMAS,
                               AAF_FILTER_RADIUS_CAP_PX, param);
        if (!aaf_filter_run(filter, value4, NULL, param, &world_rules, filtered4, &kernel_s, d)) goto done;
        res->seconds_kernels += kernel_s;
        remodulate_add(n, filtered4, means.albedo, NULL, res->rgb);
    } else {
        for (size_t i = 0; i < 3 * n; ++i) res->rgb[i] += means.indirect[i];
    }
    for (size_t i = 0; i < 3 * n; ++i) res->rgb[i] += means.unf_direct[i] + means.unf_indirect[i];
    /* Defocus: the primary radiance itself is filtered, in pixels, across objects. */
    if (on[AAF_EFFECT_DEFOCUS]) {
        for (size_t i = 0; i < n; ++i) {
            for (int k = 0; k < 3; ++k) value4[4 * i + k] = res->rgb[3 * i + k];
            value4[4 * i + 3] = 1.0f;
        }
        AafFilterRules pixel_rules = aaf_filter_rules_default(AAF_DIST_PIXEL);
        aaf_filter_make_params((int)n, beta[AAF_EFFECT_DEFOCUS], NULL, RADIUS_SIGMAS, AAF_FILTER_RADIUS_CAP_PX, param);
        /* Each pixel's sharpest CoC slope (the end of its range nearest 0; 0 if the range
         * straddles the focal plane): the kernel keeps sharper neighbours out of a blur, e.g.
         * an in-focus object's edge pixels out of the defocused background behind it. */
        for (size_t i = 0; i < n; ++i) {
            float lo = derived.coc_min[i], hi = derived.coc_max[i];
            float sharp = (lo <= 0.0f && hi >= 0.0f) ? 0.0f : (fabsf(lo) < fabsf(hi) ? lo : hi);
            slope4[4 * i] = isfinite(sharp) && lo <= hi ? sharp : 0.0f;
            slope4[4 * i + 1] = slope4[4 * i + 2] = slope4[4 * i + 3] = 0.0f;
        }
        if (!aaf_filter_run(filter, value4, slope4, param, &pixel_rules, filtered4, &kernel_s, d)) goto done;
        res->seconds_kernels += kernel_s;
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) res->rgb[3 * i + k] = filtered4[4 * i + k];
    }
    for (int e = 0; e < AAF_EFFECT_COUNT; ++e)
        if (on[e]) beta_to_px(n, beta[e], e == AAF_EFFECT_DEFOCUS ? NULL : derived.pixel_world, res->beta_px[e]);
    res->guarded_events += guard_finite(res->rgb, 3 * n);
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
