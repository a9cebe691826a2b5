/* Mixed pixels split by surface (gbuffer.h, composite_split_light; docs/algorithms.md "Mixed
 * pixels: the first surface filtered"). A pixel sees two flat surfaces through its samples:
 * surface A (object 1) with probability P_A, surface B (object 2) otherwise, each with its own
 * albedo and a direct light whose samples are uniform around the surface's mean. Checked:
 *
 *   - the split: the first hit's surface is the pixel's first surface, its sample count and
 *     sums are those of its samples (brute force over the samples), and its guides its own;
 *   - the demodulated value composite_prepare gives a split pixel is the first surface's mean
 *     light over its mean albedo;
 *   - a filter that returns the pixel's own value leaves the composite equal to the pixel's
 *     plain mean (the identity: nothing but the filter changes the pixel);
 *   - with a filter that returns the first surface's expected value (an unbiased filter on a
 *     smooth surface), the composite's mean over many pixels is the closed form
 *     P_A (a_A E_A) + (1 - P_A) (a_B E_B): the pixel's expected value, whichever surface came
 *     first;
 *   - a pixel whose first surface's normals disagree, or a frame that tracks nothing, is not
 *     split, and its composite is the plain mean as before. */
#include <stdlib.h>

#include "check.h"
#include "core/rng.h"
#include "recon/composite.h"
#include "recon/gbuffer.h"

enum { SAMPLES = 12 };

#define P_A 0.7
static const float ALBEDO_A[3] = {0.6f, 0.5f, 0.4f}, ALBEDO_B[3] = {0.3f, 0.35f, 0.2f};
static const float LIGHT_A = 2.0f, LIGHT_B = 0.5f; /* mean irradiance; the direct light is albedo x it */
#define LIGHT_SPREAD 0.8f                         /* uniform in mean x (1 +- spread) */

/* One sample on surface A or B; light_scale in [1 - spread, 1 + spread]. turned: B's normal
 * faces another way (for a first surface whose normals disagree, B is object 1 too). */
static SampleRecord sample_on(bool on_a, float light_scale, bool b_same_object_turned)
{
    SampleRecord r = {0};
    r.hit = true;
    const float *a = on_a ? ALBEDO_A : ALBEDO_B;
    float e = (on_a ? LIGHT_A : LIGHT_B) * light_scale;
    r.albedo = v3(a[0], a[1], a[2]);
    r.albedo_diffuse = r.albedo;
    r.direct = v3(a[0] * e, a[1] * e, a[2] * e);
    r.L = r.direct;
    r.object_id = on_a ? 1 : 2;
    r.p_world = on_a ? v3(0.1f, 0.2f, 5.0f) : v3(0.1f, 0.2f, 1.5f);
    r.depth_cam = on_a ? 5.0f : 1.5f;
    r.n_shading = v3(0.0f, 0.0f, -1.0f);
    if (!on_a && b_same_object_turned) {
        r.object_id = 1, r.p_world = v3(0.1f, 0.2f, 5.0f), r.depth_cam = 5.0f;
        r.n_shading = v3(1.0f, 0.0f, 0.0f);
    }
    return r;
}

/* The sample into the G-buffer's sink and the frame's sums (as the renderer adds them). */
static void add(GBuffer *g, int px, const SampleRecord *r)
{
    gbuffer_add(g, px, 0, r);
    Frame *f = &g->frame;
    const float d[3] = {r->direct.x, r->direct.y, r->direct.z}, a[3] = {r->albedo.x, r->albedo.y, r->albedo.z};
    for (int k = 0; k < 3; ++k) {
        f->direct[3 * px + k] += d[k];
        f->color[3 * px + k] += d[k];
        f->albedo[3 * px + k] += a[k];
    }
    f->hits[px] += 1.0f;
    f->spp[px] += 1.0f;
}

/* A row of `count` pixels, SAMPLES each, on A with probability P_A (pcg32 from seed); sums per pixel of
 * each surface's samples and their direct light kept for the brute force. */
typedef struct {
    int n_first;                  /* samples on the first sample's surface */
    float first_light[3];         /* their direct light */
    float mean[3];                /* the pixel's plain mean */
    bool first_is_a;
} PixelTruth;

static bool make_row(GBuffer *g, int count, bool track, bool turned, uint64_t seed, PixelTruth *truth)
{
    Pcg32 rng_state, *rng = &rng_state;
    pcg32_seed(rng, seed, 0);
    ReconCamera cam = {0.0f, 1.0f, 0.001f};
    if (!gbuffer_init(g, count, 1, cam)) return false;
    if (!gbuffer_track_split(g, track, false)) return false;
    for (int px = 0; px < count; ++px) {
        PixelTruth *t = &truth[px];
        memset(t, 0, sizeof *t);
        for (int s = 0; s < SAMPLES; ++s) {
            bool on_a = pcg32_float(rng) < (float)P_A;
            float scale = 1.0f + LIGHT_SPREAD * (2.0f * pcg32_float(rng) - 1.0f);
            SampleRecord r = sample_on(on_a, scale, turned);
            if (s == 0) t->first_is_a = on_a;
            if (on_a == t->first_is_a) {
                t->n_first++;
                t->first_light[0] += r.direct.x, t->first_light[1] += r.direct.y, t->first_light[2] += r.direct.z;
            }
            t->mean[0] += r.direct.x / SAMPLES, t->mean[1] += r.direct.y / SAMPLES, t->mean[2] += r.direct.z / SAMPLES;
            add(g, px, &r);
        }
    }
    gbuffer_resolve_guides(g);
    return true;
}

static void test_split_sums_and_guides(void)
{
    enum { COUNT = 64 };
    PixelTruth truth[COUNT];
    GBuffer g;
    CHECK(make_row(&g, COUNT, true, false, 11, truth));
    int split = 0;
    for (int px = 0; px < COUNT; ++px) {
        const PixelTruth *t = &truth[px];
        bool mixed = t->n_first < SAMPLES;
        CHECK(g.mixed[px] == mixed);
        /* a mixed pixel's first surface (one object, one plane) is split; a plain one is not */
        CHECK((g.split_share[px] > 0.0f) == mixed);
        if (!mixed) {
            CHECK(g.spos4[4 * px + 3] == g.pos4[4 * px + 3]);
            continue;
        }
        ++split;
        CHECK_NEAR(g.split_share[px], (double)t->n_first / SAMPLES, 1e-6);
        float count, light[3], albedo[3];
        gbuffer_first_surface_sums(&g, (size_t)px, true, &count, light, albedo);
        CHECK(count == (float)t->n_first);
        const float *a = t->first_is_a ? ALBEDO_A : ALBEDO_B;
        for (int k = 0; k < 3; ++k) {
            CHECK_NEAR(light[k], t->first_light[k], 1e-4 * (1.0 + fabs(t->first_light[k])));
            CHECK_NEAR(albedo[k], a[k] * count, 1e-4);
        }
        /* the first surface's guides: its own depth and object, not the pixel's mean */
        CHECK_NEAR(g.spos4[4 * px + 3], t->first_is_a ? 5.0 : 1.5, 1e-4);
        CHECK(g.snrm4[4 * px + 3] == (t->first_is_a ? 1.0f : 2.0f));
        CHECK_NEAR(g.spixel_world[px], g.spos4[4 * px + 3] * g.cam.pixel_angle, 1e-9);
        /* composite_prepare: the first surface's mean light over its mean albedo, usable */
        float value4[4 * COUNT];
        composite_prepare(&g, NULL, 0.0f, value4, NULL);
        CHECK(value4[4 * px + 3] == 1.0f);
        for (int k = 0; k < 3; ++k) CHECK_NEAR(value4[4 * px + k], light[k] / albedo[k], 1e-5);
    }
    CHECK(split > COUNT / 2);
    gbuffer_free(&g);
}

static void test_identity_filter_keeps_the_mean(void)
{
    enum { COUNT = 64 };
    PixelTruth truth[COUNT];
    GBuffer g;
    CHECK(make_row(&g, COUNT, true, false, 12, truth));
    float value4[4 * COUNT], rgb[3 * COUNT];
    composite_prepare(&g, NULL, 0.0f, value4, NULL);
    composite_image(&g, NULL, value4, NULL, rgb, NULL);
    for (int px = 0; px < COUNT; ++px)
        for (int k = 0; k < 3; ++k) CHECK_NEAR(rgb[3 * px + k], truth[px].mean[k], 2e-5 * (1.0 + truth[px].mean[k]));
    gbuffer_free(&g);
}

static void test_expected_value_with_an_unbiased_filter(void)
{
    enum { COUNT = 20000 };
    PixelTruth *truth = malloc(COUNT * sizeof *truth);
    float *value4 = malloc(4 * COUNT * sizeof(float)), *rgb = malloc(3 * COUNT * sizeof(float));
    GBuffer g;
    CHECK(truth && value4 && rgb && make_row(&g, COUNT, true, false, 13, truth));
    if (!truth || !value4 || !rgb || !g.sums) return;
    composite_prepare(&g, NULL, 0.0f, value4, NULL);
    /* the filter's output: the first surface's expected demodulated light (its irradiance);
     * a plain pixel (one surface) likewise */
    for (int px = 0; px < COUNT; ++px) {
        CHECK(value4[4 * px + 3] == 1.0f);
        float e = truth[px].first_is_a ? LIGHT_A : LIGHT_B;
        value4[4 * px + 0] = value4[4 * px + 1] = value4[4 * px + 2] = e;
    }
    composite_image(&g, NULL, value4, NULL, rgb, NULL);
    double sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
    for (int px = 0; px < COUNT; ++px)
        for (int k = 0; k < 3; ++k) sum[k] += rgb[3 * px + k], sq[k] += (double)rgb[3 * px + k] * rgb[3 * px + k];
    for (int k = 0; k < 3; ++k) {
        double expected = P_A * ALBEDO_A[k] * LIGHT_A + (1.0 - P_A) * ALBEDO_B[k] * LIGHT_B;
        double mean = sum[k] / COUNT, var = sq[k] / COUNT - mean * mean;
        /* 4 standard errors of the mean over the pixels */
        CHECK_NEAR(mean, expected, 4.0 * sqrt(var / COUNT));
        /* and not trivially: the first surface's share alone, without the others' light,
         * would be far off */
        double share_only = 0.0;
        for (int px = 0; px < COUNT; ++px)
            share_only += g.split_share[px] * (truth[px].first_is_a ? ALBEDO_A[k] * LIGHT_A : ALBEDO_B[k] * LIGHT_B) / COUNT;
        CHECK(fabs(share_only - expected) > 10.0 * sqrt(var / COUNT));
    }
    gbuffer_free(&g);
    free(truth), free(value4), free(rgb);
}

static void test_not_split(void)
{
    enum { COUNT = 32 };
    PixelTruth truth[COUNT];
    for (int turned = 0; turned < 2; ++turned) {
        GBuffer g;
        /* turned: the second "surface" is object 1 facing another way (the first surface's
         * normals disagree); else a frame that tracks nothing */
        CHECK(make_row(&g, COUNT, turned, turned, 14, truth));
        float value4[4 * COUNT], rgb[3 * COUNT];
        composite_prepare(&g, NULL, 0.0f, value4, NULL);
        for (int px = 0; px < COUNT; ++px) {
            CHECK(g.split_share == NULL || g.split_share[px] == 0.0f);
            if (g.mixed[px]) CHECK(value4[4 * px + 3] == 0.0f); /* passed through */
            for (int k = 0; k < 3 && !turned; ++k) CHECK(g.spos4 == g.pos4);
        }
        composite_image(&g, NULL, value4, NULL, rgb, NULL);
        for (int px = 0; px < COUNT; ++px)
            if (g.mixed[px])
                for (int k = 0; k < 3; ++k) CHECK_NEAR(rgb[3 * px + k], truth[px].mean[k], 2e-5 * (1.0 + truth[px].mean[k]));
        gbuffer_free(&g);
    }
}

int main(void)
{
    test_split_sums_and_guides();
    test_identity_filter_keeps_the_mean();
    test_expected_value_with_an_unbiased_filter();
    test_not_split();
    CHECK_DONE();
}
