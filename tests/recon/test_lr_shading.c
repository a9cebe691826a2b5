/* The light LR's samples carry beside a shading filter (src/recon/lr/lr_shading.c,
 * docs/algorithms.md 8.17), on random inputs:
 *   - a pixel's samples average to its value, whatever the replacement did;
 *   - where the shading filter ran, samples of one albedo that differ only in their light
 *     sample's noise carry the same light (the noise is gone), and samples of two albedos
 *     differ by the albedo difference times the filtered light (the texture stays);
 *   - where it did not run (pixel passed through, or no shading field), the samples keep
 *     their own deviations;
 *   - the filtered light comes from the pixel seen through the lens centre when it is on
 *     the sample's surface, else from the sample's own pixel;
 *   - a delta light's pick noise is replaced by its pixel mean per unit albedo. */
#include <stdlib.h>

#include "../check.h"
#include "recon/lr/lr_shading.h"

static float uniform(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (float)(*state >> 8) / 16777216.0f;
}

/* 4 pixels of filtered light; pixel 3 passed through (usable 0) for both effects. */
static float direct4[16], indirect4[16], factor[4];

static void make_light(unsigned *st)
{
    for (int i = 0; i < 4; ++i) {
        for (int c = 0; c < 3; ++c) direct4[4 * i + c] = 0.2f + uniform(st), indirect4[4 * i + c] = 0.1f + uniform(st);
        direct4[4 * i + 3] = indirect4[4 * i + 3] = i == 3 ? 0.0f : 1.0f;
        factor[i] = 0.5f + uniform(st);
    }
}

enum { N = 12 };

static void test_mean_kept(void)
{
    unsigned st = 7;
    make_light(&st);
    ReconShadingLight light = {direct4, factor, indirect4};
    int bad = 0;
    for (int trial = 0; trial < 200; ++trial) {
        int n = 1 + (int)(uniform(&st) * N);
        float rad[3 * N], base[LR_SHADING_BASE_FLOATS * N], dir[LR_SHADING_DIRECT_FLOATS * N],
            ind[LR_SHADING_INDIRECT_FLOATS * N], out[3 * N], value[3];
        size_t src[N];
        for (int k = 0; k < n; ++k) {
            for (int f = 0; f < LR_SHADING_BASE_FLOATS; ++f) base[LR_SHADING_BASE_FLOATS * k + f] = uniform(&st);
            for (int f = 0; f < LR_SHADING_DIRECT_FLOATS; ++f) dir[LR_SHADING_DIRECT_FLOATS * k + f] = uniform(&st);
            for (int c = 0; c < 3; ++c) ind[3 * k + c] = uniform(&st);
            for (int c = 0; c < 3; ++c) rad[3 * k + c] = dir[LR_SHADING_DIRECT_FLOATS * k + c] + ind[3 * k + c] + uniform(&st);
            src[k] = (size_t)(uniform(&st) * 4.0f);
        }
        for (int c = 0; c < 3; ++c) value[c] = 2.0f * uniform(&st);
        LrShading sh = {base, dir, ind};
        lr_pixel_light(n, rad, trial % 2 ? &sh : NULL, src, &light, NULL, NULL, value, out);
        for (int c = 0; c < 3; ++c) {
            double mean = 0.0;
            for (int k = 0; k < n; ++k) mean += out[3 * k + c];
            bad += fabs(mean / n - value[c]) > 1e-5;
        }
    }
    CHECK(bad == 0);
}

/* Samples with the non-filterable part `rest`, albedo a[k], filterable light drawn at random
 * (the noise), all taking their light from pixel `from`: their rows in base, dir and ind. */
enum { NB = LR_SHADING_BASE_FLOATS, ND = LR_SHADING_DIRECT_FLOATS, NI = LR_SHADING_INDIRECT_FLOATS };
static LrShading noisy_samples(unsigned *st, int n, const float *albedo_of_k, float rest, float *rad, float *base,
                               float *dir, float *ind)
{
    for (int k = 0; k < n; ++k) {
        float *b = base + NB * k, *d = dir + ND * k, *i = ind + NI * k;
        for (int f = 0; f < NB; ++f) b[f] = 0.0f;
        for (int c = 0; c < 3; ++c) {
            b[c] = d[3 + c] = albedo_of_k[k]; /* Lambert: the diffuse albedo is the albedo */
            d[c] = albedo_of_k[k] * 3.0f * uniform(st) * (uniform(st) < 0.5f); /* occluded half the time */
            i[c] = albedo_of_k[k] * 2.0f * uniform(st);
            rad[3 * k + c] = rest + d[c] + i[c];
        }
    }
    return (LrShading){base, dir, ind};
}

static void test_noise_replaced_texture_kept(void)
{
    unsigned st = 11;
    make_light(&st);
    ReconShadingLight light = {direct4, factor, indirect4};
    float albedo[N], rad[3 * N], base[NB * N], dir[ND * N], ind[NI * N], out[3 * N], value[3] = {0.7f, 0.8f, 0.9f};
    size_t src[N];
    for (int k = 0; k < N; ++k) albedo[k] = k % 3 ? 0.2f : 0.75f, src[k] = 1;
    LrShading sh = noisy_samples(&st, N, albedo, 0.05f, rad, base, dir, ind);
    lr_pixel_light(N, rad, &sh, src, &light, NULL, NULL, value, out);
    int bad = 0;
    for (int k = 1; k < N; ++k)
        for (int c = 0; c < 3; ++c) {
            /* every sample: albedo x (factor x direct + indirect) of pixel 1, plus one constant */
            float e = factor[1] * direct4[4 + c] + indirect4[4 + c];
            float want = (albedo[k] - albedo[0]) * e;
            bad += fabsf((out[3 * k + c] - out[c]) - want) > 1e-5f;
        }
    CHECK(bad == 0);
    /* the raw samples differ by far more than that: the check above can fail */
    float spread = 0.0f;
    for (int k = 1; k < N; ++k) spread = fmaxf(spread, fabsf(rad[3 * k] - rad[0]));
    CHECK(spread > 0.5f);
    /* a light the frame does not filter: its field is not stored, and the result is the one
     * with it stored, to the bit (the pipeline keeps only the filtered lights' fields) */
    for (int part = 0; part < 2; ++part) {
        ReconShadingLight one = {part ? NULL : direct4, part ? NULL : factor, part ? indirect4 : NULL};
        LrShading without = {base, part ? NULL : dir, part ? ind : NULL};
        float with_out[3 * N], without_out[3 * N];
        lr_pixel_light(N, rad, &sh, src, &one, NULL, NULL, value, with_out);
        lr_pixel_light(N, rad, &without, src, &one, NULL, NULL, value, without_out);
        int differ = 0;
        for (int k = 0; k < 3 * N; ++k) differ += with_out[k] != without_out[k];
        CHECK(differ == 0);
    }
}

static void test_deviations_kept_where_not_filtered(void)
{
    unsigned st = 13;
    make_light(&st);
    ReconShadingLight light = {direct4, factor, indirect4};
    float albedo[N], rad[3 * N], base[NB * N], dir[ND * N], ind[NI * N], out[3 * N], value[3] = {0.3f, 0.2f, 0.1f};
    size_t src[N];
    for (int k = 0; k < N; ++k) albedo[k] = 0.5f, src[k] = 3; /* pixel 3: passed through */
    LrShading sh = noisy_samples(&st, N, albedo, 0.0f, rad, base, dir, ind);
    for (int pass = 0; pass < 2; ++pass) { /* a passed-through pixel, then no shading field */
        lr_pixel_light(N, rad, pass ? NULL : &sh, src, &light, NULL, NULL, value, out);
        int bad = 0;
        for (int k = 1; k < N; ++k)
            for (int c = 0; c < 3; ++c) bad += fabsf((out[3 * k + c] - out[c]) - (rad[3 * k + c] - rad[c])) > 1e-5f;
        CHECK(bad == 0);
    }
}

static void test_light_pixel(void)
{
    GBuffer g = {0};
    float pos4[4 * 6] = {0}, nrm4[4 * 6] = {0};
    g.width = 3, g.height = 2, g.pos4 = pos4, g.nrm4 = nrm4;
    for (int i = 0; i < 6; ++i) {
        pos4[4 * i + 3] = i == 5 ? 20.0f : 10.0f; /* pixel (2, 1) is farther */
        nrm4[4 * i + 3] = i == 2 ? 8.0f : 3.0f;   /* pixel (2, 0) shows object 8, the rest object 3 */
    }
    CHECK(lr_light_pixel(&g, 1.5f, 0.5f, 10.3f, 3.0f, 4) == 1);    /* same surface: its pixel */
    CHECK(lr_light_pixel(&g, 2.5f, 0.5f, 10.0f, 3.0f, 4) == 4);    /* another object at that depth: own */
    CHECK(lr_light_pixel(&g, 2.5f, 0.5f, 10.0f, 8.0f, 4) == 2);
    CHECK(lr_light_pixel(&g, 2.9f, 1.2f, 10.0f, 3.0f, 4) == 4);    /* another depth: own */
    CHECK(lr_light_pixel(&g, 2.9f, 1.2f, 19.5f, 3.0f, 0) == 5);
    CHECK(lr_light_pixel(&g, -0.1f, 0.5f, 10.0f, 3.0f, 2) == 2);   /* outside: own */
    CHECK(lr_light_pixel(&g, 1.0f, 2.0f, 10.0f, 3.0f, 2) == 2);
    CHECK(lr_light_pixel(&g, 1.0f, 1.0f, INFINITY, -1.0f, 2) == 2); /* a miss: own */
}

/* A delta light picked by half the samples: each carries 0 or twice its light. With the
 * pixel means of lr_delta_light, samples of one albedo carry the same light; the means are
 * the albedo-divided average, and mixed or black pixels are not usable. */
static void test_delta_light(void)
{
    enum { W = 3, CAP = 8 };
    SampleStore *store = NULL;
    Diag d = {0};
    CHECK(sample_store_create(SAMPLE_FIELD_SHADING | SAMPLE_FIELD_RADIANCE, W, 1, CAP, (size_t)1 << 30, &store, &d));
    if (!store) return;
    const float albedo[W] = {0.5f, 0.5f, 0.0f}, delta_light = 0.8f; /* pixel 2 is black */
    for (int x = 0; x < W; ++x)
        for (int k = 0; k < CAP; ++k) {
            SampleRecord r = {0};
            r.hit = true;
            r.object_id = 1;
            r.albedo = r.albedo_diffuse = (vec3){albedo[x], albedo[x], albedo[x]}; /* Lambert */
            float u = k % 2 ? 2.0f * albedo[x] * delta_light : 0.0f; /* picked or not */
            r.unfiltered_direct = r.direct = r.L = (vec3){u, u, u};
            sample_store_add(store, x, 0, &r);
        }
    unsigned char hit[W] = {1, 1, 1}, mixed[W] = {0, 1, 0};
    GBuffer g = {0};
    g.width = W, g.height = 1, g.hit = hit, g.mixed = mixed;
    float delta4[4 * W];
    LrShading sh = lr_shading_of(store);
    CHECK(sh.base && !sh.direct && !sh.indirect);
    lr_delta_light(&g, store, sh.base, delta4);
    CHECK_NEAR(delta4[0], delta_light, 1e-6);
    CHECK(delta4[3] == 1.0f);
    CHECK(delta4[4 + 3] == 0.0f); /* mixed */
    CHECK(delta4[8 + 3] == 0.0f); /* black */
    float out[3 * CAP], value[3] = {0.4f, 0.4f, 0.4f};
    size_t src[CAP];
    for (int k = 0; k < CAP; ++k) src[k] = 0;
    ReconShadingLight none = {NULL, NULL, NULL};
    lr_pixel_light(CAP, sample_store_field(store, SAMPLE_FIELD_RADIANCE), &sh, src, &none, delta4, NULL, value, out);
    float spread = 0.0f;
    for (int k = 1; k < CAP; ++k) spread = fmaxf(spread, fabsf(out[3 * k] - out[0]));
    CHECK(spread < 1e-6f);
    lr_pixel_light(CAP, sample_store_field(store, SAMPLE_FIELD_RADIANCE), &sh, src, &none, NULL, NULL, value, out);
    CHECK(fabsf(out[3] - out[0]) > 0.5f); /* without the means the pick's noise stays */
    sample_store_destroy(store);
}

/* The centre light (lr_centre_light_build, docs/algorithms.md 8.19): samples stored at their own pixels but put by
 * their lens-centre, mid-shutter positions into the bins around pixel (5, 1), as a moving
 * object's samples are. Object 1's direct light is its albedo times 0.6 with a +-90% light
 * sample noise in pairs, object 2 (a floor meeting it there) has 0.2 and lands in the same
 * bins: each gets its own mean light per unit albedo exactly, a third object in those bins
 * and a sample outside the image get none; then lr_pixel_light gives a sample of an
 * unfiltered pixel that light times its albedo instead of its own noise. */
static void test_centre_light(void)
{
    enum { W = 8, H = 3, CAP = 8 };
    SampleStore *store = NULL;
    Diag d = {0};
    unsigned fields = SAMPLE_FIELD_SHADING | SAMPLE_FIELD_SHADING_DIRECT | SAMPLE_FIELD_SHADING_INDIRECT | SAMPLE_FIELD_RADIANCE;
    CHECK(sample_store_create(fields, W, H, CAP, (size_t)1 << 30, &store, &d));
    if (!store) return;
    float centre_xy[2 * W * H * CAP];
    int object_of[W * H * CAP];
    const float e1 = 0.6f, e2 = 0.2f;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int k = 0; k < CAP; ++k) {
                size_t j = ((size_t)y * W + (size_t)x) * CAP + (size_t)k;
                int object = x < 4 ? 1 : x < 7 ? 2 : 3; /* pixel order: 1 and 2 claim the slots first */
                float albedo = object == 1 ? 0.3f + 0.1f * (float)(x % 3) : 0.5f;
                float e = object == 1 ? e1 * (k % 2 ? 1.9f : 0.1f) : object == 2 ? e2 : 0.9f;
                SampleRecord r = {0};
                r.hit = true;
                r.object_id = object;
                r.albedo = r.albedo_diffuse = (vec3){albedo, albedo, albedo}; /* Lambert */
                r.direct = r.L = (vec3){albedo * e, albedo * e, albedo * e};
                sample_store_add(store, x, y, &r);
                object_of[j] = object;
                centre_xy[2 * j] = 4.1f + 0.25f * (float)(k % 8); /* bins x = 4..5, y = 1 */
                centre_xy[2 * j + 1] = 1.5f;
            }
    /* samples 0 and 1 of pixel (0, 0), object 1 (a pair of the noise: the rest stays exact),
     * land outside the image */
    const size_t outside = 0;
    centre_xy[0] = -3.0f, centre_xy[2] = 9.5f;
    GBuffer g = {0};
    g.width = W, g.height = H;
    LrShading sh = lr_shading_of(store);
    static float light9[9 * W * H * CAP];
    LrCentreLight cl = {0};
    CHECK(lr_centre_light_build(&cl, &g, store, &sh, centre_xy));
    for (size_t j = 0; j < (size_t)W * H * CAP; ++j) {
        const float *v = lr_centre_light_at(&cl, centre_xy[2 * j], centre_xy[2 * j + 1], (float)object_of[j]);
        for (int c = 0; c < 9; ++c) light9[9 * j + c] = v ? v[c] : NAN;
    }
    lr_centre_light_free(&cl);
    int wrong = 0;
    for (size_t j = 0; j < (size_t)W * H * CAP; ++j) {
        float want = object_of[j] == 1 ? e1 : e2;
        if (object_of[j] == 3 || j < 2) wrong += !isnan(light9[9 * j]); /* a third object: no slot; outside */
        else wrong += !(fabsf(light9[9 * j] - want) < 1e-5f) || !(fabsf(light9[9 * j + 3]) < 1e-6f);
    }
    CHECK(wrong == 0);
    CHECK(isnan(light9[9 * outside + 3]) && isnan(light9[9 * outside + 6]));
    /* pixel (1, 1) of object 1, passed through by the shading filter (weight 0) */
    size_t p = 1 * W + 1;
    float direct4[4 * W * H] = {0}, value[3] = {0.3f, 0.3f, 0.3f}, out[3 * CAP];
    ReconShadingLight light = {direct4, NULL, NULL};
    size_t src[CAP];
    for (int k = 0; k < CAP; ++k) src[k] = p;
    const float *rad = sample_store_field(store, SAMPLE_FIELD_RADIANCE) + p * CAP * 3;
    LrShading rows = lr_shading_from(&sh, p * CAP);
    lr_pixel_light(CAP, rad, &rows, src, &light, NULL, light9 + p * CAP * 9, value, out);
    float spread = 0.0f, mean = 0.0f;
    for (int k = 0; k < CAP; ++k) spread = fmaxf(spread, fabsf(out[3 * k] - out[0])), mean += out[3 * k] / CAP;
    CHECK(spread < 1e-6f);              /* one albedo in the pixel: one light */
    CHECK(fabsf(mean - value[0]) < 1e-6f); /* the pixel's value kept */
    lr_pixel_light(CAP, rad, &rows, src, &light, NULL, NULL, value, out);
    CHECK(fabsf(out[3] - out[0]) > 0.2f); /* without it the sample's own noise stays */
    sample_store_destroy(store);
}

int main(void)
{
    test_mean_kept();
    test_noise_replaced_texture_kept();
    test_deviations_kept_where_not_filtered();
    test_light_pixel();
    test_delta_light();
    test_centre_light();
    CHECK_DONE();
}
