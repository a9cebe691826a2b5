/* SampleRecord and SampleSink: the sink sees every camera sample exactly once, never from
 * two threads at once for the same pixel (so per-pixel statistics need no locks); with record_ray_geometry the shadow and bounce rays carry
 * their geometry, checked against a closed form: a plane (y = 0) under a square light
 * (y = 2) with a square occluder half-way (y = 1) directly below the light. For the point
 * under the centre, any shadow ray that is blocked meets the occluder at exactly half its
 * length (similar triangles between parallel planes), and a bounce ray with direction d
 * hits the occluder at 1/d.y or the light at 2/d.y or escapes. Without the option no ray
 * geometry is recorded. renderer_light_info describes the lights the records index. */
#include <signal.h>

#include "check.h"
#include "render_test_util.h"

static const char *SCENE =
    "LookAt 0 0.8 -3  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ %s ]\n"
    "Film \"rgb\" \"integer xresolution\" [ %d ] \"integer yresolution\" [ %d ]\n"
    "Sampler \"independent\" \"integer pixelsamples\" [ %d ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 2 ]\n"
    "WorldBegin\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -0.15 1 -0.15  0.15 1 -0.15  0.15 1 0.15  -0.15 1 0.15 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
    " Shape \"trianglemesh\" \"point3 P\" [ -0.5 2 -0.5  0.5 2 -0.5  0.5 2 0.5  -0.5 2 0.5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n";

typedef struct {
    int width;
    int *count;
    int *in_flight;  /* per pixel: a call is running (atomic) */
    int concurrent;  /* calls that found another call on the same pixel (atomic) */
    int shadow_total, shadow_blocked, shadow_bad;
    int bounce_total, bounce_bad;
    int records_with_geometry;
    bool check_geometry;
} SinkState;

static void sink_add(void *ctx, int px, int py, const SampleRecord *r)
{
    SinkState *s = ctx;
    int i = py * s->width + px;
    /* no two threads may be inside add() for the same pixel at once */
    if (__atomic_exchange_n(&s->in_flight[i], 1, __ATOMIC_ACQ_REL)) __atomic_add_fetch(&s->concurrent, 1, __ATOMIC_RELAXED);
    s->count[i]++;
    for (volatile int spin = 0; spin < 200; ++spin) {
    } /* widen the window a race would need */
    __atomic_store_n(&s->in_flight[i], 0, __ATOMIC_RELEASE);
    if (r->shadow_count || r->bounce_count) s->records_with_geometry++;
    if (!s->check_geometry || !r->hit) return;
    for (int k = 0; k < r->shadow_count; ++k) {
        const ShadowRayRecord *sr = &r->shadow[k];
        s->shadow_total++;
        if (!(sr->d_light_world >= 2.0f - 1e-3f && sr->d_light_world <= 2.2f)) s->shadow_bad++;
        if (isfinite(sr->d_occluder_world)) {
            s->shadow_blocked++;
            if (fabsf(sr->d_occluder_world / sr->d_light_world - 0.5f) > 1e-3f) s->shadow_bad++;
        }
        if (fabsf(sr->light_p_world.y - 2.0f) > 1e-5f) s->shadow_bad++;
    }
    for (int k = 0; k < r->bounce_count; ++k) {
        const BounceRayRecord *b = &r->bounce[k];
        s->bounce_total++;
        if (isfinite(b->d_hit_world)) {
            float h = b->d_hit_world * b->dir_world.y;
            if (fabsf(h - 1.0f) > 1e-3f && fabsf(h - 2.0f) > 1e-3f) s->bounce_bad++;
        }
    }
}

/* A sink that keeps, per pixel, the sum of its first 4 records' weighed radiance (red), in
 * sample order and in double, as the frame's first slice sums it. */
typedef struct {
    int width;
    int *seen;
    double *first4;
} First4Sink;

static void first4_add(void *ctx, int px, int py, const SampleRecord *r)
{
    First4Sink *f = ctx;
    size_t i = (size_t)py * (size_t)f->width + (size_t)px;
    if (f->seen[i]++ < 4) f->first4[i] += r->L.x;
}

/* A sink that raises the cancel flag after a number of samples (Ctrl-C in a test). */
typedef struct {
    volatile sig_atomic_t *cancel;
    long long seen, limit;
} CancelSink;

static void cancel_add(void *ctx, int px, int py, const SampleRecord *r)
{
    (void)px, (void)py, (void)r;
    CancelSink *c = ctx;
    if (__atomic_add_fetch(&c->seen, 1, __ATOMIC_RELAXED) >= c->limit) *c->cancel = 1;
}

int main(void)
{
    /* closed-form geometry at the single pixel under the light */
    {
        char text[4096];
        snprintf(text, sizeof text, SCENE, "0.02", 1, 1, 2048);
        RenderOptions o = {0};
        o.seed = 17;
        o.record_ray_geometry = true;
        TestRender t;
        CHECK(test_render(text, &o, &t));
        int count = 0, in_flight = 0;
        SinkState s = {.width = 1, .count = &count, .in_flight = &in_flight, .check_geometry = true};
        SampleSink sink = {sink_add, &s};
        frame_clear(&t.frame);
        render_pass(t.r, 0, NULL, 2048, &t.frame, &sink);
        fprintf(stderr, "shadow rays %d (blocked %d, bad %d), bounce rays %d (bad %d)\n", s.shadow_total, s.shadow_blocked,
                s.shadow_bad, s.bounce_total, s.bounce_bad);
        CHECK(count == 2048);
        CHECK(s.shadow_total == 2048); /* one light sample per camera sample, always the area light */
        CHECK(s.shadow_blocked > 100 && s.shadow_blocked < s.shadow_total); /* penumbra: partly blocked */
        CHECK(s.shadow_bad == 0);
        CHECK(s.bounce_total == 2048);
        CHECK(s.bounce_bad == 0);
        /* the light list: the 1 x 1 quad light is two triangles of one shape facing down */
        CHECK(renderer_light_count(t.r) == 2);
        RenderLightInfo a, b;
        CHECK(renderer_light_info(t.r, 0, &a) && renderer_light_info(t.r, 1, &b));
        CHECK(a.kind == RENDER_LIGHT_AREA && b.kind == RENDER_LIGHT_AREA && a.shape == b.shape && a.shape >= 0);
        CHECK_NEAR(a.area_world + b.area_world, 1.0, 1e-6);
        CHECK_NEAR(a.normal_world.y, -1.0, 1e-6);
        CHECK_NEAR(a.center_world.y, 2.0, 1e-6);
        CHECK_NEAR(a.radiance.x, 4.0, 1e-6);
        /* the triangles' vertices: on the light's plane, wound so that their normal is the
         * emitting side's, with the triangle's area, together covering the quad */
        const RenderLightInfo *ab[2] = {&a, &b};
        double covered = 0.0;
        for (int t = 0; t < 2; ++t) {
            const RenderLightInfo *li = ab[t];
            CHECK(li->is_triangle);
            for (int k = 0; k < 3; ++k) CHECK_NEAR(li->tri_world[k].y, 2.0, 1e-6);
            vec3 c = v3_cross(v3_sub(li->tri_world[1], li->tri_world[0]), v3_sub(li->tri_world[2], li->tri_world[0]));
            CHECK(v3_dot(c, li->normal_world) > 0.0f);
            CHECK_NEAR(0.5 * v3_length(c), li->area_world, 1e-6);
            covered += 0.5 * v3_length(c);
        }
        CHECK_NEAR(covered, 1.0, 1e-6);
        CHECK(!renderer_light_info(t.r, 2, &a));
        test_render_free(&t);
    }
    /* every sample once, from the pixel's thread; nothing recorded without the option */
    {
        enum { W = 37, H = 29, SPP = 3 };
        char text[4096];
        snprintf(text, sizeof text, SCENE, "40", W, H, SPP);
        RenderOptions o = {0};
        o.seed = 2, o.threads = 2;
        TestRender t;
        CHECK(test_render(text, &o, &t));
        int *count = calloc(W * H, sizeof(int)), *in_flight = calloc(W * H, sizeof(int));
        SinkState s = {.width = W, .count = count, .in_flight = in_flight};
        SampleSink sink = {sink_add, &s};
        render_pass(t.r, 1, NULL, SPP, &t.frame, &sink);
        int wrong = 0;
        for (int i = 0; i < W * H; ++i) wrong += count[i] != SPP;
        CHECK(wrong == 0);
        CHECK(s.concurrent == 0);
        CHECK(s.records_with_geometry == 0);
        /* switched on for a later pass */
        renderer_set_record_ray_geometry(t.r, true);
        memset(count, 0, W * H * sizeof(int));
        render_pass(t.r, 2, NULL, SPP, &t.frame, &sink);
        CHECK(s.records_with_geometry > W * H / 4);
        free(count);
        free(in_flight);
        test_render_free(&t);
    }
    /* cancelled during the first round ([0, 64)): the rows it did not reach get samples
     * [0, 4) in a completion round, so every pixel has 4 or 64 samples, and a pixel with 4
     * holds exactly the first 4 samples of the uninterrupted render */
    {
        enum { W = 40, H = 30, SPP = 64 };
        char text[4096];
        snprintf(text, sizeof text, SCENE, "40", W, H, 1);
        RenderOptions o = {0};
        o.seed = 5, o.threads = 2;
        TestRender full;
        CHECK(test_render(text, &o, &full));
        frame_clear(&full.frame);
        int *seen = calloc(W * H, sizeof(int));
        double *first4 = calloc(W * H, sizeof(double));
        First4Sink fs = {W, seen, first4};
        SampleSink sink4 = {first4_add, &fs};
        CHECK(render_pass(full.r, 0, NULL, SPP, &full.frame, &sink4));
        volatile sig_atomic_t cancel = 0;
        o.cancel = &cancel;
        TestRender t;
        CHECK(test_render(text, &o, &t));
        frame_clear(&t.frame);
        CancelSink cs = {&cancel, 0, 2 * W * H}; /* about a thirtieth of the first round */
        SampleSink sink = {cancel_add, &cs};
        CHECK(!render_pass(t.r, 0, NULL, SPP, &t.frame, &sink));
        int with4 = 0, with64 = 0, same = 0;
        for (int i = 0; i < W * H; ++i) {
            if (t.frame.spp[i] == 4.0f) {
                with4++;
                same += t.frame.color[3 * i] == (float)first4[i];
            }
            if (t.frame.spp[i] == (float)SPP) {
                with64++;
                same += t.frame.color[3 * i] == full.frame.color[3 * i];
            }
        }
        fprintf(stderr, "cancelled in the first round: %d pixels with 4 samples, %d with %d\n", with4, with64, SPP);
        CHECK(with4 + with64 == W * H);
        CHECK(with4 > W * H / 2 && with64 > 0);
        CHECK(same == W * H);
        CHECK(test_frame_finite(&t.frame));
        free(seen);
        free(first4);
        test_render_free(&t);
        test_render_free(&full);
    }
    /* cancelled later in the first round: every pixel still has at least 4 samples */
    {
        enum { W = 40, H = 30, SPP = 64 };
        char text[4096];
        snprintf(text, sizeof text, SCENE, "40", W, H, 1);
        volatile sig_atomic_t cancel = 0;
        RenderOptions o = {0};
        o.seed = 5, o.threads = 2, o.cancel = &cancel;
        TestRender t;
        CHECK(test_render(text, &o, &t));
        frame_clear(&t.frame);
        CancelSink cs = {&cancel, 0, 5 * W * H};
        SampleSink sink = {cancel_add, &cs};
        CHECK(!render_pass(t.r, 0, NULL, SPP, &t.frame, &sink));
        int below = 0;
        double total = 0.0;
        for (int i = 0; i < W * H; ++i) {
            below += t.frame.spp[i] < 4.0f;
            total += t.frame.spp[i];
        }
        fprintf(stderr, "cancelled: %.0f samples, %d pixels below 4 spp\n", total, below);
        CHECK(below == 0);
        CHECK(total < 0.5 * W * H * SPP);
        CHECK(test_frame_finite(&t.frame));
        test_render_free(&t);
    }
    CHECK_DONE();
}
