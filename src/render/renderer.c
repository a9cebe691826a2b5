/* Render passes over tiles on a pool of threads (see renderer.h). */
#include "render/renderer.h"

#include <math.h>
#include <pthread.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/clock.h"
#include "core/env_knob.h"
#include "render/integrator.h"
#include "render/light.h"
#include "render/material.h"
#include "render/tracer.h"

enum { TILE_PX = 16 };
/* A render round's samples of a pixel (run_pass). Each round sets every pixel's sampler up
 * again (its dimension seeds, grid rotations and tables, in every wave the pixel's samples
 * fall in), so fewer, longer rounds cost less a sample: at 256 spp one round of 256 instead
 * of four of 64 took 3.4% of envlight's instructions (docs/benchmarks.md, "Issue 22,
 * fifty-second round"). A round's length only sets how coarse a cancel's stopping point
 * and a progress display's steps are; images do not depend on it (frame_slice_end). */
enum { ROUND_SAMPLES = 256 };

struct Renderer {
    SceneDesc *scene;
    RenderOptions opt;
    int width, height, spp, threads;
    int overscan_px;              /* renderer_set_overscan: width, height include 2 of it */
    SamplerKind sampler;
    Camera camera;
    Tracer tracer;
    LightSet lights;
    MaterialTable materials;
    IntegratorScene isc;
    PixelFilter pixel_filter;
    EffectMask effects;
    RenderStats stats;
};

/* What the frame's readers take from a sample decides both shortcuts: a frame that reads no
 * first-hit fields skips filling them, and only such a frame may take a Lambert vertex's constant
 * sky from its bounce ray alone (design.md 12.30: the filters' sky terms need the light sample). */
static void apply_frame_reads(IntegratorScene *isc, unsigned reads)
{
    isc->skip_first_hit_fields = !render_reads_first_hit(reads);
    isc->sky_bounce_alone = !render_reads_first_hit(reads);
}

bool renderer_create(SceneDesc *scene, const RenderOptions *opt, Renderer **out, Diag *err)
{
    *out = NULL;
    Renderer *r = calloc(1, sizeof *r);
    if (!r) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return false;
    }
    r->scene = scene;
    r->opt = *opt;
    r->width = opt->width > 0 ? opt->width : scene->film.xres;
    r->height = opt->height > 0 ? opt->height : scene->film.yres;
    r->spp = opt->spp > 0 ? opt->spp : scene->sampler.spp;
    if (r->spp <= 0) r->spp = 16;
    if (r->width <= 0 || r->height <= 0) {
        diag_set(err, WEDGE_EXIT_INPUT, scene->film.loc, "film resolution must be positive, got %dx%d", r->width, r->height);
        free(r);
        return false;
    }
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    r->threads = opt->threads > 0 ? opt->threads : (cores > 0 ? (int)cores : 1);
    r->sampler = opt->sampler_set ? opt->sampler : sampler_kind_from_pbrt(scene->sampler.type ? scene->sampler.type : "zsobol");

    if (!camera_init_times(&r->camera, &scene->camera, r->width, r->height, scene->transform_start_time,
                           scene->transform_end_time, err))
        goto fail;
    if (!materials_build(scene, &r->materials, err)) goto fail;
    if (!tracer_build(&r->tracer, scene, r->threads, err)) goto fail;
    if (!lights_build(&r->lights, scene, &r->tracer, err)) goto fail;
    r->stats.seconds_build = r->tracer.seconds_build;
    /* Shading finds a sphere's or disk's uv (an atan2 and an acos per hit) only where its
     * material reads it. */
    for (int l = 0; l < r->tracer.layer_count; ++l)
        for (int g = 0; g < r->tracer.layers[l].geom_count; ++g) {
            Geom *geom = &r->tracer.layers[l].geoms[g];
            geom->uv_unread = geom->kind != GEOM_INSTANCE && !material_reads_uv(&r->materials, geom->material);
        }

    IntegratorScene *isc = &r->isc;
    isc->camera = &r->camera;
    isc->tracer = &r->tracer;
    isc->lights = &r->lights;
    isc->materials = &r->materials;
    isc->max_depth = scene->integrator.max_depth;
    /* the lens and shutter dimensions are sampled exactly when the scene's one effect
     * analysis (scene/effects.c, also read by `wedge info`) found defocus and motion */
    scene_analyze_effects(scene);
    r->effects = scene->effects;
    isc->sample_lens = effect_in(r->effects, EFFECT_DEFOCUS) && r->camera.lens_radius_world > 0.0f;
    isc->sample_time = effect_in(r->effects, EFFECT_MOTION);
    isc->shutter_open = scene->camera.shutter_open;
    isc->shutter_close = scene->camera.shutter_close;
    isc->xform_time_start = scene->transform_start_time;
    isc->xform_time_end = scene->transform_end_time;
    if (!(isc->xform_time_end > isc->xform_time_start)) isc->xform_time_start = 0.0f, isc->xform_time_end = 1.0f;
    isc->record_ray_geometry = isc->record_bounce_geometry = opt->record_ray_geometry;
    isc->record_motion = opt->record_motion;
    apply_frame_reads(isc, opt->reads);
    isc->materials_lambert_only = material_table_lambert_only(&r->materials);
    isc->time01_fixed = integrator_fixed_time01(isc);
    isc->delta_lights_by_path = env_knob_switch("WEDGE_DELTA_BY_PATH", false);
    /* --pixel-filter, else the scene's PixelFilter statement, else wedge's box (pbrt-v4's
     * default would be a gaussian: docs/rendering.md, "Pixel filters") */
    const char *pf_name = opt->pixel_filter ? opt->pixel_filter : scene->filter.loc.line > 0 ? scene->filter.type : "box";
    const ParamSet *pf_params = opt->pixel_filter ? NULL : scene->filter.loc.line > 0 ? &scene->filter.params : NULL;
    if (!pixel_filter_init(&r->pixel_filter, pf_name, pf_params, scene->filter.loc, err)) goto fail;
    isc->pixel_filter = &r->pixel_filter;

    *out = r;
    return true;
fail:
    renderer_destroy(r);
    return false;
}

void renderer_destroy(Renderer *r)
{
    if (!r) return;
    pixel_filter_free(&r->pixel_filter);
    lights_free(&r->lights);
    tracer_free(&r->tracer);
    materials_free(&r->materials);
    free(r);
}

int renderer_width(const Renderer *r) { return r->width; }
int renderer_height(const Renderer *r) { return r->height; }
int renderer_spp(const Renderer *r) { return r->spp; }
int renderer_threads(const Renderer *r) { return r->threads; }
int renderer_max_depth(const Renderer *r) { return r->isc.max_depth; }
SamplerKind renderer_sampler(const Renderer *r) { return r->sampler; }
EffectMask renderer_effects(const Renderer *r) { return r->effects; }
const Camera *renderer_camera(const Renderer *r) { return &r->camera; }
const IntegratorScene *renderer_integrator_scene(const Renderer *r) { return &r->isc; }
RenderStats renderer_stats(const Renderer *r) { return r->stats; }
long renderer_triangle_count(const Renderer *r) { return r->tracer.triangle_count; }
long long renderer_embree_peak_bytes(const Renderer *r) { return r->tracer.embree_bytes_peak; }

int renderer_overscan_px(const Renderer *r) { return r->overscan_px; }

bool renderer_set_overscan(Renderer *r, int margin_px, Diag *err)
{
    if (margin_px < 0) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "overscan must be >= 0 pixels, got %d", margin_px);
        return false;
    }
    int w = r->width - 2 * r->overscan_px, h = r->height - 2 * r->overscan_px;
    const SceneDesc *s = r->scene;
    /* the visible image's camera, as renderer_create built it: its screen window */
    Camera base;
    if (!camera_init_times(&base, &s->camera, w, h, s->transform_start_time, s->transform_end_time, err)) return false;
    Camera cam = base;
    if (margin_px > 0) {
        /* M pixels' worth of screen on each side (in double: the window's ends are then
         * within an ulp of the visible one's plus M pixel steps) */
        CameraDesc d = s->camera;
        double dx = ((double)base.screen_max[0] - (double)base.screen_min[0]) / (double)w;
        double dy = ((double)base.screen_max[1] - (double)base.screen_min[1]) / (double)h;
        d.has_screen_window = true;
        d.screen_window[0] = (float)((double)base.screen_min[0] - margin_px * dx);
        d.screen_window[1] = (float)((double)base.screen_max[0] + margin_px * dx);
        d.screen_window[2] = (float)((double)base.screen_min[1] - margin_px * dy);
        d.screen_window[3] = (float)((double)base.screen_max[1] + margin_px * dy);
        if (!camera_init_times(&cam, &d, w + 2 * margin_px, h + 2 * margin_px, s->transform_start_time,
                               s->transform_end_time, err))
            return false;
    }
    r->camera = cam; /* isc.camera points here */
    r->overscan_px = margin_px;
    r->width = w + 2 * margin_px;
    r->height = h + 2 * margin_px;
    return true;
}

void renderer_set_record_ray_geometry(Renderer *r, bool on) { r->isc.record_ray_geometry = r->isc.record_bounce_geometry = on; }
void renderer_set_record_bounce_geometry(Renderer *r, bool on) { r->isc.record_bounce_geometry = on; }
void renderer_set_record_motion(Renderer *r, bool on) { r->isc.record_motion = on; }
void renderer_set_reads(Renderer *r, unsigned reads)
{
    r->opt.reads = reads;
    apply_frame_reads(&r->isc, reads);
}
unsigned renderer_reads(const Renderer *r) { return r->opt.reads; }

int renderer_light_count(const Renderer *r) { return r->lights.count; }

bool renderer_light_info(const Renderer *r, int li, RenderLightInfo *info)
{
    return renderer_light_info_at(r, li, -1.0f, info);
}

/* shutter_u < 0: the pose at time01 0 (renderer_light_info's, as it always was). */
bool renderer_light_info_at(const Renderer *r, int li, float shutter_u, RenderLightInfo *info)
{
    if (li < 0 || li >= r->lights.count) return false;
    const Light *l = &r->lights.lights[li];
    memset(info, 0, sizeof *info);
    info->shape = -1;
    info->radiance = l->L;
    info->two_sided = l->two_sided;
    info->area_world = l->area_world;
    switch (l->kind) {
    case LIGHT_AREA: {
        info->kind = RENDER_LIGHT_AREA;
        const Geom *g = &r->tracer.layers[l->layer].geoms[l->geom];
        info->shape = g->shape;
        info->moving = l->instance >= 0 && r->tracer.instances[l->instance].moving;
        float time01 = 0.0f;
        if (info->moving && shutter_u >= 0.0f)
            time01 = r->isc.sample_time ? integrator_shutter_time01(&r->isc, fminf(shutter_u, 1.0f)) : r->isc.time01_fixed;
        Mat4 w = l->instance >= 0 ? tracer_world_from_instance(&r->tracer, l->instance, time01) : mat4_identity();
        if (g->kind == GEOM_TRIANGLES) {
            info->is_triangle = true;
            if (l->instance < 0) {
                info->center_world = v3_add(l->tri_p0, v3_scale(v3_add(l->tri_e1, l->tri_e2), 1.0f / 3.0f));
                info->normal_world = l->tri_n;
                info->tri_world[0] = l->tri_p0;
                info->tri_world[1] = v3_add(l->tri_p0, l->tri_e1);
                info->tri_world[2] = v3_add(l->tri_p0, l->tri_e2);
            } else {
                const uint32_t *ix = g->index + 3 * (size_t)l->prim;
                const vec3 *V = (const vec3 *)g->p;
                vec3 c = v3_scale(v3_add(v3_add(V[ix[0]], V[ix[1]]), V[ix[2]]), 1.0f / 3.0f);
                info->center_world = mat4_apply_point(&w, c);
                vec3 n = v3_normalize(v3_cross(v3_sub(V[ix[1]], V[ix[0]]), v3_sub(V[ix[2]], V[ix[0]])));
                if (g->flip_normal) n = v3_neg(n);
                Mat4 inv;
                info->normal_world = mat4_inverse(&w, &inv) ? v3_normalize(mat4_apply_normal(&inv, n)) : n;
                for (int k = 0; k < 3; ++k) info->tri_world[k] = mat4_apply_point(&w, V[ix[k]]);
            }
            if (v3_dot(v3_cross(v3_sub(info->tri_world[1], info->tri_world[0]), v3_sub(info->tri_world[2], info->tri_world[0])),
                       info->normal_world) < 0.0f) { /* the stated winding: swap to match the normal */
                vec3 t = info->tri_world[1];
                info->tri_world[1] = info->tri_world[2];
                info->tri_world[2] = t;
            }
        } else {
            Mat4 m = mat4_mul(&w, &g->geom_from_object), inv;
            info->center_world = mat4_apply_point(&m, v3(0.0f, 0.0f, g->kind == GEOM_DISK ? (float)g->height : 0.0f));
            if (g->kind == GEOM_DISK && mat4_inverse(&m, &inv)) {
                vec3 n = v3_normalize(mat4_apply_normal(&inv, v3(0.0f, 0.0f, 1.0f)));
                info->normal_world = g->flip_normal ? v3_neg(n) : n;
            }
        }
        break;
    }
    case LIGHT_POINT: info->kind = RENDER_LIGHT_POINT; info->center_world = l->p_world; break;
    case LIGHT_SPOT:
        info->kind = RENDER_LIGHT_SPOT;
        info->center_world = l->p_world;
        info->normal_world = l->w_world;
        break;
    case LIGHT_DISTANT: info->kind = RENDER_LIGHT_DISTANT; info->normal_world = l->w_world; break;
    case LIGHT_INFINITE: info->kind = RENDER_LIGHT_INFINITE; break;
    }
    return true;
}

/* ---- one pass ---- */

typedef struct {
    Renderer *r;
    int pass;
    int spp_before;             /* render_pass_more: samples each pixel took before (else 0) */
    const int *spp_pp;
    int spp_uniform;
    Frame *frame;
    const SampleSink *sink;
    bool sum_guides;            /* add the frame's albedo, normal, depth and hits (render_reads.h) */
    bool sum_parts;             /* add its direct, indirect and emission: the frame holds them */
    int tiles_x, tile_count;
    int sample_begin, sample_end; /* the round: sample indices [begin, end) of every pixel */
    /* The first round ([0,ROUND_SAMPLES), or all of a short pass) of an interruptible pass:
     * per tile, how many of its rows the round has finished (NULL: the first round is
     * [0,4)). When the pass is cancelled in
     * that round, a completion round gives the rows it did not reach samples [0,4), and
     * ignores the cancel (run_pass). */
    int *tile_rows_done;
    bool completing;
    int next_tile;              /* atomic */
    long long samples_done;     /* atomic */
    long long rays_done;        /* atomic */
    int workers_done;           /* atomic */
    int cancelled;              /* atomic */
    pthread_mutex_t stats_lock;
    IntegratorStats stats;
} PassJob;

static bool cancel_requested(const PassJob *job)
{
    return !job->completing && job->r->opt.cancel && *job->r->opt.cancel;
}

typedef double v2df __attribute__((vector_size(2 * sizeof(double))));
enum { SLICE_RADIANCE = 12 }; /* floats of SampleRadiance summed as one run (add_slice) */

/* The sums of one frame slice of a pixel while its records come in (add_slice). */
typedef struct {
    v2df rad2[SLICE_RADIANCE / 2];
    double al[3], nn[3], depth, hits;
    int count;
} SliceSums;

/* A worker's wave: the pixels queued for it and their records. A pixel's samples of a round
 * may be split between waves (queue_pixel), so that every wave but a tile's last is full:
 * the slice open at a split is then carried over to the next wave in double, unrounded,
 * and added to the frame once, as if the pixel had stayed in one wave. (A round longer than
 * a wave puts a pixel alone in a middle wave: it continues the carried slice and, ending
 * inside another, carries that one on; its first slice is read before its last is written.) */
typedef struct {
    Wave *wave;
    WavePixel pixel[WAVE_SAMPLES];
    int pixel_count, sample_count;
    bool last_continues; /* the last queued pixel has more samples in the next wave */
    bool carrying;       /* carry holds the open slice of the first queued pixel */
    SliceSums carry;
    /* their records: rad when the render keeps the radiance alone (integrator_radiance_only
     * and no sink), else rec */
    RadianceRecord rad[WAVE_SAMPLES];
    SampleRecord rec[WAVE_SAMPLES];
} WaveQueue;

/* The frame's slices of a pixel's sample indices in a pass: [0,4) [4,8) [8,16) [16,32)
 * [32,64), then 64 at a time. Each slice of a pixel is summed in double and added to the
 * frame with one float addition per sum, so the slices fix the frame's rounding; they were
 * the render rounds before [0,64) became one (run_pass), and keeping them keeps every image
 * bit for bit. A round's bounds are slice bounds. The end of the slice that starts at
 * `begin`: */
static int frame_slice_end(int begin) { return begin == 0 ? 4 : (begin < 64 ? 2 * begin : begin + 64); }

/* The start of the slice that holds sample index i (i >= 0). */
static int frame_slice_begin(int i)
{
    if (i < 4) return 0;
    if (i >= 64) return i - i % 64;
    int b = 4;
    while (2 * b <= i) b *= 2;
    return b;
}

/* SampleRadiance's L, emission, direct and indirect follow each other without padding:
 * add_slice sums them as one run of 12 floats. */
_Static_assert(sizeof(SampleRadiance) == 4 * sizeof(vec3) && sizeof(vec3) == 3 * sizeof(float),
               "L, emission, direct, indirect are one run of 12 floats");
typedef float v2sf __attribute__((vector_size(2 * sizeof(float))));

/* Two floats at p (4-byte aligned) widened to doubles, exactly. GCC turns the portable
 * convertvector of a 64-bit vector into two scalar cvtss2sd and an unpcklpd; SSE2's
 * cvtps2pd does it in one instruction from memory. */
static inline v2df widen_float_pair(const char *p)
{
#if defined(__SSE2__)
    double bits;
    memcpy(&bits, p, sizeof bits);
    return (v2df)_mm_cvtps_pd(_mm_castpd_ps(_mm_set_sd(bits)));
#else
    v2sf pair;
    memcpy(&pair, p, sizeof pair);
    return __builtin_convertvector(pair, v2df);
#endif
}

/* Adds records rec[0 .. count) of pixel (px, py), one frame slice or a part of one, to the
 * slice's sums carry_in (NULL: the slice starts here), in sample order, and hands them to the
 * sink in that order; or, with rec NULL, the records of the radiance alone rad[0 .. count)
 * (no sink, no guides: integrator_radiance_only). Then adds the sums to the frame, or, with
 * carry_out (the slice goes on in the next wave), leaves them there. Inlined into flush_wave
 * with one of rec and rad NULL. */
static inline __attribute__((always_inline)) void add_slice(PassJob *job, int px, int py, SampleRecord *rec,
                                                            RadianceRecord *rad, int count, const SliceSums *carry_in,
                                                            SliceSums *carry_out)
{
    /* Radiance sums, per component in sample order as before (the same doubles): the run
     * L, emission, direct, indirect of each record, converted and added two components at
     * a time (six cvtps2pd and addpd instead of twelve scalar pairs). Started element by
     * element, not by an array initialiser and a copy over it: GCC made that a `rep stos` on
     * the stack, whose stores the loads of the sums that follow waited for (perf: ~18% of
     * flush_wave at 16 spp, a slice per 4-8 samples) */
    v2df rad2[SLICE_RADIANCE / 2];
    for (int c = 0; c < SLICE_RADIANCE / 2; ++c) rad2[c] = carry_in ? carry_in->rad2[c] : (v2df){0.0, 0.0};
    double al[3], nn[3], depth = carry_in ? carry_in->depth : 0.0, hits = carry_in ? carry_in->hits : 0.0;
    for (int ch = 0; ch < 3; ++ch) al[ch] = carry_in ? carry_in->al[ch] : 0.0, nn[ch] = carry_in ? carry_in->nn[ch] : 0.0;
    int slice_count = count + (carry_in ? carry_in->count : 0);
    for (int i = 0; i < count; ++i) {
        const SampleRadiance *R;
        if (rec) {
            pixel_filter_weigh_record(&rec[i]);
            R = &rec[i].radiance;
        } else {
            if (rad[i].filter_weight != 1.0f) pixel_filter_weigh_radiance(&rad[i].radiance, rad[i].filter_weight);
            R = &rad[i].radiance;
        }
        const char *run = (const char *)R;
        for (int c = 0; c < SLICE_RADIANCE / 2; ++c) rad2[c] += widen_float_pair(run + c * sizeof(v2sf));
        if (!rec) continue;
        const SampleRecord *r = &rec[i];
        if (job->sum_guides && r->hit) {
            al[0] += r->albedo.x, al[1] += r->albedo.y, al[2] += r->albedo.z;
            nn[0] += r->n_shading.x, nn[1] += r->n_shading.y, nn[2] += r->n_shading.z;
            if (isfinite(r->depth_cam)) depth += r->depth_cam, hits += 1.0;
        }
        if (job->sink && job->sink->add) job->sink->add(job->sink->ctx, px, py, r);
    }
    if (carry_out) {
        memcpy(carry_out->rad2, rad2, sizeof rad2);
        memcpy(carry_out->al, al, sizeof al);
        memcpy(carry_out->nn, nn, sizeof nn);
        carry_out->depth = depth, carry_out->hits = hits;
        carry_out->count = slice_count;
        return;
    }
    Frame *f = job->frame;
    size_t i1 = (size_t)py * (size_t)f->width + (size_t)px, i3 = 3 * i1;
    double sums[SLICE_RADIANCE];
    memcpy(sums, rad2, sizeof sums);
    const double *c = sums, *em = sums + 3, *di = sums + 6, *in = sums + 9;
    for (int ch = 0; ch < 3; ++ch) f->color[i3 + ch] += (float)c[ch];
    if (job->sum_parts)
        for (int ch = 0; ch < 3; ++ch) {
            f->direct[i3 + ch] += (float)di[ch];
            f->indirect[i3 + ch] += (float)in[ch];
            f->emission[i3 + ch] += (float)em[ch];
        }
    if (rec && job->sum_guides) {
        for (int ch = 0; ch < 3; ++ch) {
            f->albedo[i3 + ch] += (float)al[ch];
            f->normal[i3 + ch] += (float)nn[ch];
        }
        f->depth[i1] += (float)depth;
        f->hits[i1] += (float)hits;
    }
    f->spp[i1] += (float)slice_count;
}

/* Integrates the queued pixels and adds their samples to the frame, slice by slice
 * (frame_slice_end), and to the sink in sample order. */
static long long flush_wave(PassJob *job, WaveQueue *q, IntegratorStats *st)
{
    if (q->pixel_count == 0) return 0;
    Renderer *r = job->r;
    WaveSampling ws = {r->sampler, r->opt.seed, job->pass};
    /* a render whose users read the radiance alone (render_reads.h) keeps it alone: 52 bytes
     * a sample instead of a 232-byte record */
    bool radiance_only = !job->sink && integrator_radiance_only(&r->isc);
    int n = radiance_only ? integrate_wave_radiance(&r->isc, q->wave, &ws, q->pixel, q->pixel_count, q->rad, st)
                          : integrate_wave(&r->isc, q->wave, &ws, q->pixel, q->pixel_count, q->rec, st);
    int done = 0;
    bool carried = q->carrying;
    q->carrying = false;
    for (int k = 0; k < q->pixel_count; ++k) {
        const WavePixel *wp = &q->pixel[k];
        bool continues = k == q->pixel_count - 1 && q->last_continues;
        /* the pass's sample indices of this pixel's records: [s, end) */
        for (int s = wp->index_first - wp->spp_before, end = s + wp->count; s < end;) {
            int slice = frame_slice_begin(s), slice_end = frame_slice_end(slice);
            int e = slice_end < end ? slice_end : end;
            /* the open slice of a pixel split between waves: continued from the last wave
             * (the first pixel, starting inside a slice), or carried over to the next */
            const SliceSums *in = carried && k == 0 && s != slice ? &q->carry : NULL;
            SliceSums *out = continues && e == end && e < slice_end ? &q->carry : NULL;
            if (radiance_only) add_slice(job, wp->px, wp->py, NULL, q->rad + done, e - s, in, out);
            else add_slice(job, wp->px, wp->py, q->rec + done, NULL, e - s, in, out);
            if (out) q->carrying = true;
            done += e - s;
            s = e;
        }
    }
    q->pixel_count = q->sample_count = 0;
    q->last_continues = false;
    return n;
}

/* Queues the samples of this round of a pixel that has spp samples in the pass (the
 * sampler set covers all spp, after spp_before earlier ones when it continues them: a
 * round takes a slice): as many as the wave has room for, and when that is not all, the
 * rest in the next wave, after integrating this one. Returns the samples integrated by
 * that flush. */
static long long queue_pixel(PassJob *job, WaveQueue *q, int px, int py, int spp, IntegratorStats *st)
{
    int first = job->sample_begin, last = job->sample_end < spp ? job->sample_end : spp;
    long long done = 0;
    int before = job->spp_before;
    while (first < last) {
        if (q->sample_count == WAVE_SAMPLES) done += flush_wave(job, q, st);
        int room = WAVE_SAMPLES - q->sample_count, take = last - first < room ? last - first : room;
        q->pixel[q->pixel_count++] = (WavePixel){px, py, before, before + spp, before + first, take};
        q->sample_count += take;
        q->last_continues = take < last - first;
        first += take;
    }
    return done;
}

static void *pass_worker(void *arg)
{
    PassJob *job = arg;
    Renderer *r = job->r;
    IntegratorStats st = {0};
    WaveQueue *q = malloc(sizeof *q);
    Wave *wave = wave_create();
    if (!q || !wave) { /* no scratch space: the pass ends incomplete, as cancelled */
        __atomic_store_n(&job->cancelled, 1, __ATOMIC_RELAXED);
        free(q);
        wave_free(wave);
        __atomic_add_fetch(&job->workers_done, 1, __ATOMIC_RELEASE);
        return NULL;
    }
    q->wave = wave;
    q->pixel_count = q->sample_count = 0;
    q->last_continues = q->carrying = false;
    for (;;) {
        if (cancel_requested(job)) {
            __atomic_store_n(&job->cancelled, 1, __ATOMIC_RELAXED);
            break;
        }
        int tile = __atomic_fetch_add(&job->next_tile, 1, __ATOMIC_RELAXED);
        if (tile >= job->tile_count) break;
        int x0 = (tile % job->tiles_x) * TILE_PX, y0 = (tile / job->tiles_x) * TILE_PX;
        int x1 = x0 + TILE_PX < r->width ? x0 + TILE_PX : r->width;
        int y1 = y0 + TILE_PX < r->height ? y0 + TILE_PX : r->height;
        long long samples = 0;
        long long rays_before = st.rays_primary + st.rays_shadow + st.rays_indirect + st.rays_bsdf;
        /* a completion round starts below the rows the first round finished */
        int y = job->completing ? y0 + job->tile_rows_done[tile] : y0;
        for (; y < y1; ++y) {
            if (cancel_requested(job)) { /* Ctrl-C: stop after the current row */
                __atomic_store_n(&job->cancelled, 1, __ATOMIC_RELAXED);
                break;
            }
            for (int x = x0; x < x1; ++x) {
                int spp = job->spp_pp ? job->spp_pp[(size_t)y * (size_t)r->width + (size_t)x] : job->spp_uniform;
                if (spp <= 0) continue;
                samples += queue_pixel(job, q, x, y, spp, &st);
            }
        }
        samples += flush_wave(job, q, &st); /* a wave never spans two tiles */
        if (job->tile_rows_done && !job->completing) job->tile_rows_done[tile] = y - y0; /* rows y0 .. y-1 done */
        __atomic_add_fetch(&job->samples_done, samples, __ATOMIC_RELAXED);
        __atomic_add_fetch(&job->rays_done, st.rays_primary + st.rays_shadow + st.rays_indirect + st.rays_bsdf - rays_before,
                           __ATOMIC_RELAXED);
    }
    wave_free(wave);
    free(q);
    pthread_mutex_lock(&job->stats_lock);
    job->stats.rays_primary += st.rays_primary;
    job->stats.rays_shadow += st.rays_shadow;
    job->stats.rays_indirect += st.rays_indirect;
    job->stats.rays_bsdf += st.rays_bsdf;
    job->stats.rays_bsdf_skipped += st.rays_bsdf_skipped;
    job->stats.guarded_events += st.guarded_events;
    pthread_mutex_unlock(&job->stats_lock);
    __atomic_add_fetch(&job->workers_done, 1, __ATOMIC_RELEASE);
    return NULL;
}

/* One round of a pass: every pixel's sample indices [begin, end), tiles handed out to n
 * threads (or done here when no thread starts), progress reported while they run. */
static void run_round(PassJob *job, int begin, int end, pthread_t *tid, int n, long long total, double t0)
{
    const Renderer *r = job->r;
    job->sample_begin = begin;
    job->sample_end = end;
    job->next_tile = 0;
    job->workers_done = 0;
    int started = 0;
    if (tid)
        for (; started < n; ++started)
            if (pthread_create(&tid[started], NULL, pass_worker, job) != 0) break;
    if (started == 0) pass_worker(job); /* no threads available: do it here */
    /* Only a progress display needs the calling thread to wake up; poll often enough
     * that the end of a short round is noticed quickly. */
    while (r->opt.progress && started > 0 && __atomic_load_n(&job->workers_done, __ATOMIC_ACQUIRE) < started) {
        RenderProgress p = {__atomic_load_n(&job->samples_done, __ATOMIC_RELAXED), total,
                            __atomic_load_n(&job->rays_done, __ATOMIC_RELAXED), clock_wall_seconds() - t0};
        r->opt.progress(r->opt.progress_ctx, &p);
        struct timespec ts = {0, 10 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    for (int i = 0; i < started; ++i) pthread_join(tid[i], NULL);
}

static bool run_pass(Renderer *r, int pass, int spp_before, const int *spp_per_pixel, int spp_uniform, Frame *frame,
                     const SampleSink *sink)
{
    if (!frame || frame->width != r->width || frame->height != r->height) return false; /* caller bug */
    double t0 = clock_wall_seconds();
    PassJob job;
    memset(&job, 0, sizeof job);
    int spp_max = spp_uniform;
    job.r = r;
    job.pass = pass;
    job.spp_before = spp_before > 0 ? spp_before : 0;
    job.spp_pp = spp_per_pixel;
    job.spp_uniform = spp_uniform;
    job.frame = frame;
    job.sink = sink;
    /* the sums the frame holds (frame_init_planes), the guides only where the users read them */
    job.sum_guides = render_reads_frame_guides(r->opt.reads) && frame->albedo;
    job.sum_parts = frame->direct != NULL;
    if (!job.sum_guides) frame->guides_skipped = true;
    job.tiles_x = (r->width + TILE_PX - 1) / TILE_PX;
    job.tile_count = job.tiles_x * ((r->height + TILE_PX - 1) / TILE_PX);
    pthread_mutex_init(&job.stats_lock, NULL);
    long long total = 0;
    if (spp_per_pixel) {
        spp_max = 0;
        for (size_t i = 0; i < (size_t)r->width * (size_t)r->height; ++i) {
            total += spp_per_pixel[i] > 0 ? spp_per_pixel[i] : 0;
            if (spp_per_pixel[i] > spp_max) spp_max = spp_per_pixel[i];
        }
    } else {
        total = (long long)r->width * r->height * (spp_uniform > 0 ? spp_uniform : 0);
    }

    /* The pass runs in rounds over the whole image, each taking the next ROUND_SAMPLES of
     * every pixel's sample indices, and a remainder of fewer than 64 with the round before
     * it ([0,65), [0,256) [256,300)), so a round takes 64 to 319 of a pixel's samples (all
     * of them up to 319 spp): a round of 1 (65 spp) set every pixel's sampler up for one sample,
     * in waves of 256 pixels (docs/benchmarks.md, "CPU per sample at counts that are not
     * whole rounds"). Each round sets a pixel's sampler up and builds its per-dimension
     * tables again, so a round should be long: a first
     * round of [0,4) then [4,64) (until 2026-11-28 also [4,8) [8,16) [16,32) [32,64)) cost
     * 5-9% of a 64-spp render in set-ups and in runs too short to fill the vectorised loops
     * (docs/benchmarks.md, "Issue 22, seventh round" and "ninth round"). An interrupted
     * render must still have at least 4 samples in every pixel (a complete image at a lower
     * sample count): when the pass is cancelled during its first round, a completion round
     * gives the rows that round did not reach their samples [0,4), whatever the cancel
     * flag says (a second Ctrl-C kills wedge render); that makes a cancel in the first
     * round slower to take effect, by the time 4 samples of the rows not reached take. The
     * old cuts remain as the frame's slices (frame_slice_end), which is all the images depend on, so images do not depend
     * on the rounds; the rounds depend only on the sample counts, so images stay identical
     * for any number of threads; within a round a pixel belongs to one thread. Without
     * memory for the rows' counts the first round is [0,4), as before. */
    int n = r->threads > 0 ? r->threads : 1;
    pthread_t *tid = calloc((size_t)n, sizeof *tid);
    if (spp_max > 4) job.tile_rows_done = calloc((size_t)job.tile_count, sizeof *job.tile_rows_done);
    for (int begin = 0, end; begin < spp_max && !job.cancelled; begin = end) {
        end = begin == 0 ? (job.tile_rows_done ? ROUND_SAMPLES : 4) : (begin < 64 ? 64 : begin + ROUND_SAMPLES);
        if (end >= 64 && spp_max - end < 64) end = spp_max; /* a short remainder joins this round */
        run_round(&job, begin, end, tid, n, total, t0);
        if (begin == 0 && job.cancelled && job.tile_rows_done) {
            job.completing = true; /* [0,4) where the cancelled first round did not reach */
            run_round(&job, 0, 4, tid, n, total, t0);
        }
    }
    free(tid);
    free(job.tile_rows_done);
    if (r->opt.progress) {
        RenderProgress p = {job.samples_done, total, job.rays_done, clock_wall_seconds() - t0};
        r->opt.progress(r->opt.progress_ctx, &p);
    }
    pthread_mutex_destroy(&job.stats_lock);
    r->stats.rays_primary += job.stats.rays_primary;
    r->stats.rays_shadow += job.stats.rays_shadow;
    r->stats.rays_indirect += job.stats.rays_indirect;
    r->stats.rays_bsdf += job.stats.rays_bsdf;
    r->stats.rays_bsdf_skipped += job.stats.rays_bsdf_skipped;
    r->stats.guarded_events += job.stats.guarded_events;
    r->stats.samples += job.samples_done;
    r->stats.seconds_trace += clock_wall_seconds() - t0;
    return !job.cancelled;
}

bool render_pass(Renderer *r, int pass, const int *spp_per_pixel, int spp_uniform, Frame *frame, const SampleSink *sink)
{
    return run_pass(r, pass, 0, spp_per_pixel, spp_uniform, frame, sink);
}

bool render_pass_more(Renderer *r, int pass, int spp_before, const int *spp_more, Frame *frame, const SampleSink *sink)
{
    return run_pass(r, pass, spp_before, spp_more, 0, frame, sink);
}
