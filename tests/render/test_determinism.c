/* Determinism: the embedded default scene (all four effects) rendered with 1 and with 2
 * threads gives bit-identical frame sums (pixels are seeded from (seed, pixel, pass) and
 * summed by one thread each); a different seed gives a different image; a second pass adds
 * to the first with different samples, and so does a continuation of the first pass; pixels
 * split between waves sum as whole ones. */
#include "check.h"
#include "render/render_reads.h"
#include "render_test_util.h"


static bool frames_identical(const Frame *a, const Frame *b)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    return !memcmp(a->color, b->color, 3 * n * sizeof(float)) && !memcmp(a->direct, b->direct, 3 * n * sizeof(float)) &&
           !memcmp(a->indirect, b->indirect, 3 * n * sizeof(float)) &&
           !memcmp(a->emission, b->emission, 3 * n * sizeof(float)) &&
           !memcmp(a->albedo, b->albedo, 3 * n * sizeof(float)) && !memcmp(a->normal, b->normal, 3 * n * sizeof(float)) &&
           !memcmp(a->depth, b->depth, n * sizeof(float)) && !memcmp(a->spp, b->spp, n * sizeof(float));
}

/* What the frame must hold, rebuilt from the sink's records: each pixel's samples summed in
 * double per frame slice ([0,4) [4,8) [8,16) [16,32) [32,64), then 64 at a time) in sample
 * order, each slice added to the frame as one float: the colour, emission, direct and
 * indirect parts (SampleRadiance's 12 floats in order) and the albedo of the samples that
 * hit (the guides a render that reads everything sums). */
enum { SUMS = 15 }; /* per pixel: L, emission, direct, indirect, albedo */
typedef struct {
    int width, spp;
    int *count;        /* records seen per pixel */
    double *slice_sum; /* SUMS per pixel: the open slice */
    float *frame;      /* SUMS per pixel */
} SliceCheck;

static int slice_end_after(int begin) { return begin == 0 ? 4 : begin < 64 ? 2 * begin : begin + 64; }

static void slice_close(SliceCheck *c, size_t i)
{
    for (int k = 0; k < SUMS; ++k) c->frame[SUMS * i + k] += (float)c->slice_sum[SUMS * i + k], c->slice_sum[SUMS * i + k] = 0.0;
}

static void slice_check_add(void *ctx, int px, int py, const SampleRecord *r)
{
    SliceCheck *c = ctx;
    size_t i = (size_t)py * (size_t)c->width + (size_t)px;
    int k = c->count[i]++;
    int begin = 0;
    while (slice_end_after(begin) <= k) begin = slice_end_after(begin);
    if (k == begin && k > 0) slice_close(c, i); /* sample k opens a new slice */
    const vec3 part[5] = {r->L, r->emission, r->direct, r->indirect, r->hit ? r->albedo : v3(0.0f, 0.0f, 0.0f)};
    double *sum = &c->slice_sum[SUMS * i];
    for (int p = 0; p < 5; ++p) sum[3 * p] += part[p].x, sum[3 * p + 1] += part[p].y, sum[3 * p + 2] += part[p].z;
}

/* Whether pixel i's sums in f equal the rebuilt ones, bit for bit; the albedo only if with_guides. */
static bool slices_match(const SliceCheck *c, const Frame *f, size_t i, bool with_guides)
{
    const float *arrays[5] = {f->color, f->emission, f->direct, f->indirect, f->albedo};
    for (int p = 0; p < (with_guides ? 5 : 4); ++p)
        if (memcmp(&c->frame[SUMS * i + 3 * p], &arrays[p][3 * i], 3 * sizeof(float))) return false;
    return true;
}

/* Renders the default scene at spp with 1 thread and a SliceCheck sink, with 2 threads
 * without one, and with 2 threads reading the radiance alone (RadianceRecords, the other
 * path of the frame's sums): the counts whose rounds split pixels between waves (83: one
 * round of 83 per pixel, 3 pixels and a part of a fourth per wave of 256; 158: one round;
 * 300: one round longer than a wave, so some pixels span three waves, alone in the middle
 * one, which continues one carried slice and carries another on) give the same frame for
 * the first two, every pixel gets spp records, and the
 * frames' sums are the slices' sums exactly, as if no pixel had been split (renderer.c,
 * WaveQueue's carried slice). */
static void check_split_rounds(const char *text, int spp)
{
    RenderOptions o = {0};
    o.width = 24, o.height = 20, o.spp = spp, o.seed = 77;
    size_t n = (size_t)o.width * (size_t)o.height;
    SliceCheck c = {o.width, spp, calloc(n, sizeof(int)), calloc(SUMS * n, sizeof(double)), calloc(SUMS * n, sizeof(float))};
    SampleSink sink = {slice_check_add, &c};
    TestRender t1, t2, t3;
    o.threads = 1;
    bool ok = c.count && c.slice_sum && c.frame && test_render_sink(text, &o, &sink, &t1);
    o.threads = 2;
    ok = ok && test_render(text, &o, &t2);
    o.reads = RENDER_READS_RADIANCE;
    ok = ok && test_render(text, &o, &t3);
    CHECK(ok);
    if (ok) {
        for (size_t i = 0; i < n; ++i) slice_close(&c, i);
        CHECK(frames_identical(&t1.frame, &t2.frame));
        int bad_count = 0, bad_sums = 0, bad_radiance_only = 0;
        for (size_t i = 0; i < n; ++i) {
            bad_count += c.count[i] != spp || t1.frame.spp[i] != (float)spp || t3.frame.spp[i] != (float)spp;
            bad_sums += !slices_match(&c, &t1.frame, i, true);
            bad_radiance_only += !slices_match(&c, &t3.frame, i, false);
        }
        CHECK(bad_count == 0);
        CHECK(bad_sums == 0);
        CHECK(bad_radiance_only == 0);
        test_render_free(&t1);
        test_render_free(&t2);
        test_render_free(&t3);
    }
    free(c.count), free(c.slice_sum), free(c.frame);
}

/* the default scene is linked into the app library; read it from the source tree instead */
static char *read_default_scene(void)
{
    const char *dir = getenv("WEDGE_SOURCE_DIR");
    char path[4096];
    snprintf(path, sizeof path, "%s/scenes/default.pbrt", dir ? dir : "../..");
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *buf = malloc(1 << 20);
    size_t n = fread(buf, 1, (1 << 20) - 1, f);
    buf[n] = 0;
    fclose(f);
    return buf;
}

int main(void)
{
    char *text = read_default_scene();
    CHECK(text != NULL);
    if (!text) CHECK_DONE();
    RenderOptions o = {0};
    o.width = 40, o.height = 30, o.spp = 4, o.seed = 1234;
    TestRender t1, t2, t3;
    o.threads = 1;
    bool ok = test_render(text, &o, &t1);
    o.threads = 2;
    ok = ok && test_render(text, &o, &t2);
    o.seed = 99;
    ok = ok && test_render(text, &o, &t3);
    CHECK(ok);
    if (ok) {
        EffectMask e = renderer_effects(t1.r);
        CHECK(e == EFFECT_MASK_ALL);
        CHECK(frames_identical(&t1.frame, &t2.frame));
        CHECK(!frames_identical(&t1.frame, &t3.frame));
        CHECK(test_frame_finite(&t1.frame));
        CHECK(t1.stats.rays_primary == 40 * 30 * 4);
        CHECK(t1.stats.rays_primary == t2.stats.rays_primary && t1.stats.rays_shadow == t2.stats.rays_shadow &&
              t1.stats.rays_indirect == t2.stats.rays_indirect);
        /* pass 1 with a per-pixel count array: sums grow by exactly those samples */
        int *spp = calloc((size_t)(40 * 30), sizeof(int));
        for (int i = 0; i < 40 * 30; ++i) spp[i] = i % 3;
        render_pass(t2.r, 1, spp, 0, &t2.frame, NULL);
        int bad = 0;
        for (int i = 0; i < 40 * 30; ++i) bad += t2.frame.spp[i] != 4.0f + (float)(i % 3);
        CHECK(bad == 0);
        /* continuing pass 0 instead (an adaptive second pass): the same sums for 1 and 2
         * threads, and each pixel's count grows by its own number */
        CHECK(render_pass_more(t1.r, 0, 4, spp, &t1.frame, NULL));
        o.threads = 2, o.seed = 1234;
        TestRender t4;
        CHECK(test_render(text, &o, &t4));
        CHECK(render_pass_more(t4.r, 0, 4, spp, &t4.frame, NULL));
        CHECK(frames_identical(&t1.frame, &t4.frame));
        bad = 0;
        for (int i = 0; i < 40 * 30; ++i) bad += t1.frame.spp[i] != 4.0f + (float)(i % 3);
        CHECK(bad == 0);
        CHECK(!frames_identical(&t1.frame, &t2.frame)); /* a continuation is not a new pass */
        test_render_free(&t4);
        free(spp);
        test_render_free(&t1);
        test_render_free(&t2);
        test_render_free(&t3);
    }
    check_split_rounds(text, 13); /* low counts: slices [0,4) [4,8) [8,13), pixels split */
    check_split_rounds(text, 83);
    check_split_rounds(text, 158);
    check_split_rounds(text, 300);
    check_split_rounds(text, 600); /* rounds [0,256) [256,512) [512,600) */
    free(text);
    CHECK_DONE();
}
