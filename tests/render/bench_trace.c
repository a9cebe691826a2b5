/* Tracer benchmark (run by tools/bench-trace; not a ctest):
 *  1. generates a displaced sphere of 2 * N^2 triangles (N = 400: 320K) on a floor under a
 *     square area light, parses it, builds the renderer (Embree build time, memory);
 *  2. renders it with the full renderer (maxdepth 1: camera ray, one light sample with its
 *     shadow ray and one BSDF ray for MIS per sample) and reports rays per second;
 *  3. renders it again recording every ray's geometry through a SampleSink, and replays
 *     exactly those rays with raw rtcIntersect1 / rtcOccluded1 (no shading, no sampling)
 *     on the same Embree scene and thread count: the renderer/raw ratio is the overhead of
 *     everything that is not traversal;
 *  4. the full renderer with maxdepth 2 (one bounce) for reference.
 * With --render-only K it only renders K passes (step 2) and prints the best time per
 * sample: a short, clean run for profilers.
 * Every timing is the best of 5 runs (the development machine is shared); renderer and raw
 * replay alternate, and the median of the 5 per-pair ratios is printed as well.
 * Memory: peak resident set during the build minus the resident set before it (the parsed
 * scene is already in memory then), and Embree's own peak from its memory monitor. */
#include <math.h>
#include <stdarg.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "render/frame.h"
#include "render/renderer.h"
#include "render/tracer.h"
#include "scene/scene_desc.h"

enum { REPEATS = 5 };

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static long rss_kb(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    long pages_total = 0, pages_res = 0;
    if (f) {
        if (fscanf(f, "%ld %ld", &pages_total, &pages_res) != 2) pages_res = 0;
        fclose(f);
    }
    return pages_res * (sysconf(_SC_PAGESIZE) / 1024);
}

static long peak_rss_kb(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss;
}

/* ---- scene text ---- */

typedef struct {
    char *buf;
    size_t len, cap;
} Text;

static void put(Text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(Text *t, const char *fmt, ...)
{
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(t->buf + t->len, t->cap - t->len, fmt, ap);
        va_end(ap);
        if (n >= 0 && (size_t)n < t->cap - t->len) {
            t->len += (size_t)n;
            return;
        }
        t->cap = t->cap ? 2 * t->cap : 1 << 20;
        t->buf = realloc(t->buf, t->cap);
    }
}

static char *make_scene(int n, int res, int spp, int max_depth, const char *sampler_name)
{
    Text t = {0};
    put(&t, "LookAt 0 1.4 -3.6  0 0.9 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n");
    put(&t, "Film \"rgb\" \"integer xresolution\" [ %d ] \"integer yresolution\" [ %d ]\n", res, res);
    put(&t, "Sampler \"%s\" \"integer pixelsamples\" [ %d ]\n", sampler_name, spp);
    put(&t, "Integrator \"path\" \"integer maxdepth\" [ %d ]\nWorldBegin\n", max_depth);
    put(&t, "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\n"
            " Shape \"trianglemesh\" \"point3 P\" [ -0.7 3 -0.7  0.7 3 -0.7  0.7 3 0.7  -0.7 3 0.7 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
            "AttributeEnd\n");
    put(&t, "Shape \"trianglemesh\" \"point3 P\" [ -6 0 -6  6 0 -6  6 0 6  -6 0 6 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n");
    put(&t, "AttributeBegin\n Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.6 0.5 ]\n Translate 0 0.95 0\n");
    put(&t, " Shape \"trianglemesh\" \"point3 P\" [\n");
    const double pi = 3.14159265358979323846;
    for (int j = 0; j <= n; ++j) {
        double th = pi * j / n;
        for (int i = 0; i <= n; ++i) {
            double ph = 2.0 * pi * i / n;
            /* bumpy radius: a few octaves of sinusoids */
            double r = 0.9 + 0.04 * sin(13 * th) * sin(17 * ph) + 0.015 * sin(41 * th + 1.0) * cos(37 * ph) +
                       0.006 * sin(97 * th) * sin(89 * ph + 2.0);
            put(&t, "%.6f %.6f %.6f\n", r * sin(th) * cos(ph), r * cos(th), r * sin(th) * sin(ph));
        }
    }
    put(&t, " ] \"integer indices\" [\n");
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int a = j * (n + 1) + i, b = a + 1, c = a + (n + 1), d = c + 1;
            put(&t, "%d %d %d %d %d %d\n", a, c, b, b, c, d);
        }
    put(&t, " ]\nAttributeEnd\n");
    return t.buf;
}

/* ---- ray capture through the SampleSink ---- */

typedef struct {
    float px, py, lu, lv, time;
    vec3 p;          /* first hit */
    bool hit;
    bool has_shadow, has_bounce;
    vec3 light_p;
    float d_light;
    vec3 dir;
} CapturedSample;

typedef struct {
    CapturedSample *s;
    int *taken;      /* samples seen per pixel (each pixel is owned by one thread) */
    int width, spp;
} Capture;

static void capture_add(void *ctx, int px, int py, const SampleRecord *r)
{
    Capture *c = ctx;
    /* slot per (pixel, sample): each pixel is owned by one thread, samples arrive in order */
    size_t pixel = (size_t)py * (size_t)c->width + (size_t)px;
    if (c->taken[pixel] >= c->spp) return;
    CapturedSample *s = &c->s[pixel * (size_t)c->spp + (size_t)c->taken[pixel]++];
    s->px = r->px_raster, s->py = r->py_raster, s->lu = r->lens_u, s->lv = r->lens_v, s->time = r->time;
    s->hit = r->hit;
    s->p = r->p_world;
    s->has_shadow = r->shadow_count > 0;
    if (s->has_shadow) s->light_p = r->shadow[0].light_p_world, s->d_light = r->shadow[0].d_light_world;
    s->has_bounce = r->bounce_count > 0;
    if (s->has_bounce) s->dir = r->bounce[0].dir_world;
}

typedef struct {
    const Tracer *tr;
    const Camera *cam;
    const CapturedSample *s;
    size_t count;
    size_t *next;    /* shared: next block of samples to replay (dynamic balance, as tiles) */
    long long rays;
} ReplayJob;

enum { REPLAY_BLOCK = 1024 };

static void *replay(void *arg)
{
    ReplayJob *j = arg;
    RTCScene scene = j->tr->layers[0].scene;
    /* Embree's scene is in tracer units (world times the tracer's power-of-two scale, 1
     * for ordinary scenes): origins and distances go in scaled, as tracer.c does */
    float k = j->tr->tracer_from_world;
    long long rays = 0;
    for (;;) {
    size_t begin = __atomic_fetch_add(j->next, REPLAY_BLOCK, __ATOMIC_RELAXED);
    if (begin >= j->count) break;
    size_t end = begin + REPLAY_BLOCK < j->count ? begin + REPLAY_BLOCK : j->count;
    for (size_t i = begin; i < end; ++i) {
        const CapturedSample *s = &j->s[i];
        struct RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        CameraRay cr = camera_generate_ray(j->cam, s->px, s->py, v2(s->lu, s->lv), s->time);
        struct RTCRayHit rh;
        memset(&rh, 0, sizeof rh);
        rh.ray.org_x = k * cr.o_world.x, rh.ray.org_y = k * cr.o_world.y, rh.ray.org_z = k * cr.o_world.z;
        rh.ray.dir_x = cr.d_world.x, rh.ray.dir_y = cr.d_world.y, rh.ray.dir_z = cr.d_world.z;
        rh.ray.tfar = INFINITY, rh.ray.mask = 0xFFFFFFFFu, rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        ++rays;
        if (s->has_shadow) {
            vec3 d = v3_sub(s->light_p, s->p);
            float len = v3_length(d);
            struct RTCRay r;
            memset(&r, 0, sizeof r);
            r.org_x = k * s->p.x, r.org_y = k * s->p.y, r.org_z = k * s->p.z;
            r.dir_x = d.x / len, r.dir_y = d.y / len, r.dir_z = d.z / len;
            r.tnear = k * 1e-4f, r.tfar = k * len * 0.9999f, r.mask = 0xFFFFFFFFu;
            rtcOccluded1(scene, &ctx, &r);
            ++rays;
        }
        if (s->has_bounce) {
            memset(&rh, 0, sizeof rh);
            rh.ray.org_x = k * s->p.x, rh.ray.org_y = k * s->p.y, rh.ray.org_z = k * s->p.z;
            rh.ray.dir_x = s->dir.x, rh.ray.dir_y = s->dir.y, rh.ray.dir_z = s->dir.z;
            rh.ray.tnear = k * 1e-4f, rh.ray.tfar = INFINITY, rh.ray.mask = 0xFFFFFFFFu;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            ++rays;
        }
    }
    }
    j->rays = rays;
    return NULL;
}

int main(int argc, char **argv)
{
    int n = 400, res = 384, spp = 4, threads = 0, render_only = 0;
    const char *sampler_name = "stratified";
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--grid")) n = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--res")) res = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--spp")) spp = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--threads")) threads = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--sampler")) sampler_name = argv[i + 1]; /* stratified or sobol */
        /* --render-only K: only K renderer passes, for profilers (perf record) */
        else if (!strcmp(argv[i], "--render-only")) render_only = atoi(argv[i + 1]);
    }
    if (threads <= 0) threads = (int)sysconf(_SC_NPROCESSORS_ONLN);
    double t0 = now_s();
    char *text = make_scene(n, res, spp, 1, sampler_name);
    size_t text_len = strlen(text);
    SceneDesc scene;
    Diag err = {0};
    if (!scene_parse_string(text, text_len, "<bench>", NULL, &scene, &err)) {
        fprintf(stderr, "parse: %s\n", err.message);
        return 1;
    }
    free(text);
    double t_parse = now_s() - t0;
    long rss_before = rss_kb();

    RenderOptions o = {0};
    o.seed = 1, o.threads = threads;
    Renderer *r;
    double tb = now_s();
    if (!renderer_create(&scene, &o, &r, &err)) {
        fprintf(stderr, "build: %s\n", err.message);
        return 1;
    }
    double t_create = now_s() - tb;
    long peak_after_build = peak_rss_kb();
    long tris = renderer_triangle_count(r);
    long long embree_peak = renderer_embree_peak_bytes(r);
    RenderStats st0 = renderer_stats(r);
    if (render_only > 0) {
        Frame fr;
        frame_init(&fr, renderer_width(r), renderer_height(r));
        double best = INFINITY;
        for (int k = 0; k < render_only; ++k) {
            RenderStats b = renderer_stats(r);
            frame_clear(&fr);
            render_pass(r, 0, NULL, spp, &fr, NULL);
            best = fmin(best, renderer_stats(r).seconds_trace - b.seconds_trace);
        }
        RenderStats a = renderer_stats(r);
        double samples = (double)res * res * spp;
        printf("render only: %d passes, best %.4f s = %.1f ns per sample per thread, %.0f rays per pass\n", render_only, best,
               best * threads / samples * 1e9, (double)(a.rays_primary + a.rays_shadow + a.rays_indirect + a.rays_bsdf + a.rays_bsdf_skipped) / render_only);
        frame_free(&fr);
        renderer_destroy(r);
        scene_desc_free(&scene);
        return 0;
    }

    /* Capture the rays (same seed, same samples) with a second, recording renderer, and
     * build a third Embree scene from the same description for the raw replay (the Renderer
     * is opaque). */
    Frame f;
    frame_init(&f, renderer_width(r), renderer_height(r));
    o.record_ray_geometry = true;
    Renderer *rec_r;
    if (!renderer_create(&scene, &o, &rec_r, &err)) return 1;
    size_t count = (size_t)res * (size_t)res * (size_t)spp;
    Capture cap = {calloc(count, sizeof(CapturedSample)), calloc((size_t)res * (size_t)res, sizeof(int)), res, spp};
    SampleSink sink = {capture_add, &cap};
    frame_clear(&f);
    render_pass(rec_r, 0, NULL, spp, &f, &sink);
    Tracer tr;
    if (!tracer_build(&tr, &scene, threads, &err)) return 1;
    pthread_t tid[64];
    ReplayJob jobs[64];
    int nt = threads < 64 ? threads : 64;

    /* The machine may be shared: renderer and raw replay alternate, REPEATS pairs, so both
     * sides of each pair see about the same load. Reported: the best time of each side and
     * the median of the per-pair ratios. */
    RenderStats st = {0};
    double best_trace = INFINITY, t_raw = INFINITY, pair_ratio[REPEATS];
    long long rays_raw = 0;
    for (int rep = 0; rep < REPEATS; ++rep) {
        RenderStats before = renderer_stats(r);
        frame_clear(&f);
        render_pass(r, 0, NULL, spp, &f, NULL);
        RenderStats after = renderer_stats(r);
        double t_render = after.seconds_trace - before.seconds_trace;
        best_trace = fmin(best_trace, t_render);
        st.rays_primary = after.rays_primary - before.rays_primary;
        st.rays_shadow = after.rays_shadow - before.rays_shadow;
        st.rays_indirect = after.rays_indirect - before.rays_indirect;
        st.rays_bsdf = after.rays_bsdf - before.rays_bsdf; /* a path's last (MIS) ray: traced, and replayed */
        /* last rays that miss the emitters' box: the renderer knows their result without
         * tracing them, the replay traces them; counted for both, so the ratio compares
         * the time of the same work */
        st.rays_bsdf_skipped = after.rays_bsdf_skipped - before.rays_bsdf_skipped;

        size_t next_block = 0;
        double tr0 = now_s();
        for (int k = 0; k < nt; ++k) {
            jobs[k] = (ReplayJob){&tr, renderer_camera(rec_r), cap.s, count, &next_block, 0};
            pthread_create(&tid[k], NULL, replay, &jobs[k]);
        }
        rays_raw = 0;
        for (int k = 0; k < nt; ++k) {
            pthread_join(tid[k], NULL);
            rays_raw += jobs[k].rays;
        }
        double t_replay = now_s() - tr0;
        t_raw = fmin(t_raw, t_replay);
        long long rays_render = st.rays_primary + st.rays_shadow + st.rays_indirect + st.rays_bsdf + st.rays_bsdf_skipped;
        pair_ratio[rep] = (rays_render / t_render) / (rays_raw / t_replay);
    }
    for (int a = 1; a < REPEATS; ++a) /* insertion sort for the median */
        for (int b = a; b > 0 && pair_ratio[b] < pair_ratio[b - 1]; --b) {
            double tmp = pair_ratio[b];
            pair_ratio[b] = pair_ratio[b - 1], pair_ratio[b - 1] = tmp;
        }
    st.seconds_trace = best_trace;
    long long rays_full = st.rays_primary + st.rays_shadow + st.rays_indirect + st.rays_bsdf + st.rays_bsdf_skipped;
    double rate_full = rays_full / st.seconds_trace;
    renderer_destroy(rec_r);
    double rate_raw = rays_raw / t_raw;
    tracer_free(&tr);
    free(cap.s);
    free(cap.taken);
    renderer_destroy(r);

    /* the sampler alone: the dimensions one maxdepth-1 sample draws (film 2D, light pick 1D,
     * light 2D, BSDF 2D), for every sample of the image, on one thread */
    double t_sampler = INFINITY;
    float sink_sum = 0.0f;
    for (int rep = 0; rep < REPEATS; ++rep) {
    double ts0 = now_s();
    for (int py = 0; py < res; ++py)
        for (int px = 0; px < res; ++px) {
            PixelSampler ps;
            sampler_start_pixel(&ps, sampler_kind_from_pbrt(sampler_name), 1, px, py, 0, spp);
            for (int i = 0; i < spp; ++i) {
                sampler_start_sample(&ps, i);
                vec2 a = sampler_2d(&ps);
                float b = sampler_1d(&ps);
                vec2 c = sampler_2d(&ps), d = sampler_2d(&ps);
                sink_sum += a.x + b + c.y + d.x;
            }
        }
    t_sampler = fmin(t_sampler, (now_s() - ts0) / threads); /* the render spreads it over the threads */
    }
    if (sink_sum < 0.0f) printf("%g", sink_sum);

    /* one bounce, for reference */
    scene_desc_free(&scene);
    text = make_scene(n, res, spp, 2, sampler_name);
    if (!scene_parse_string(text, strlen(text), "<bench>", NULL, &scene, &err)) return 1;
    free(text);
    o.record_ray_geometry = false;
    if (!renderer_create(&scene, &o, &r, &err)) return 1;
    frame_clear(&f);
    render_pass(r, 0, NULL, spp, &f, NULL);
    RenderStats st2 = renderer_stats(r);
    long long rays_gi = st2.rays_primary + st2.rays_shadow + st2.rays_indirect + st2.rays_bsdf + st2.rays_bsdf_skipped;
    renderer_destroy(r);
    scene_desc_free(&scene);
    frame_free(&f);

    printf("scene: displaced sphere %ld triangles (+ floor, light), %dx%d, %d spp, %d threads, %s sampler\n", tris, res, res,
           spp, threads, sampler_name);
    printf("scene text: %.1f MB, parse %.2f s\n", text_len / 1e6, t_parse);
    printf("build (meshes + Embree BVH): %.3f s (renderer_create %.3f s)\n", st0.seconds_build, t_create);
    printf("memory: peak RSS during build - RSS before = %.1f MB = %.0f bytes/triangle\n",
           (peak_after_build - rss_before) / 1024.0, (peak_after_build - rss_before) * 1024.0 / (double)tris);
    printf("embree internal peak (memory monitor): %.1f MB = %.0f bytes/triangle\n", embree_peak / 1e6,
           embree_peak / (double)tris);
    printf("renderer (maxdepth 1): %lld rays in %.3f s = %.2f Mrays/s (primary %lld, shadow %lld, bsdf %lld traced + %lld "
           "known to miss the emitters)\n", rays_full, st.seconds_trace, rate_full / 1e6, st.rays_primary, st.rays_shadow,
           st.rays_bsdf, st.rays_bsdf_skipped);
    printf("raw embree, same rays:  %lld rays in %.3f s = %.2f Mrays/s\n", rays_raw, t_raw, rate_raw / 1e6);
    printf("renderer/raw = %.2f (issue 22's target >= 1.0); median of %d alternating pairs %.2f (range %.2f-%.2f)\n",
           rate_full / rate_raw, REPEATS, pair_ratio[REPEATS / 2], pair_ratio[0], pair_ratio[REPEATS - 1]);
    /* The renderer answers the rays known to miss the emitters without tracing them, the
     * replay traces them: per ray that reaches Embree the renderer is this much slower. */
    printf("renderer/raw per traced ray = %.2f (the %lld rays known to miss not counted)\n",
           (double)(rays_full - st.rays_bsdf_skipped) / st.seconds_trace / rate_raw, st.rays_bsdf_skipped);
    printf("sampler share: %.3f s of the renderer's %.3f s (%s, 7 dimensions per sample); "
           "renderer/raw without it = %.2f\n", t_sampler, st.seconds_trace, sampler_name,
           rays_full / (st.seconds_trace - t_sampler) / rate_raw);
    printf("renderer (maxdepth 2): %lld rays in %.3f s = %.2f Mrays/s\n", rays_gi, st2.seconds_trace, rays_gi / st2.seconds_trace / 1e6);
    return 0;
}
