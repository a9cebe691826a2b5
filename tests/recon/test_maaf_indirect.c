/* MAAF for indirect light (maaf_indirect.c, docs/algorithms.md 9.12). Oracles:
 *   - the direction-factor table equals a brute-force integral of the component against the
 *     cosine transfer, divided by the transfer at the sample (c_pq of maaf_indirect.h);
 *   - the factor's average over cosine-distributed directions is the closed-form mean that
 *     samples without a direction get (maaf_direction_mean);
 *   - a synthetic receiver plane under a parallel emitting plane at height h whose radiance is a
 *     step edge (the cosine-weighted fraction of the hemisphere that sees the lit half has a
 *     closed form): at 4 spp MAAF is well below the pixel mean's error, and the design of the
 *     mirrored wedge (C_x negated: the slope -h) is clearly worse;
 *   - the OpenCL pass on the receiver guides of that plane, with rejected neighbours, equals the
 *     C reference;
 *   - at a contact line (reflector height -> 0) the central filter's std is 1/alpha(n) pixels,
 *     alpha(n) = 0.3 (n / 16)^(1/4) (maaf_indirect_heights, docs/algorithms.md 9.26), whatever
 *     the footprint and the knob, and a reflector above that floor keeps its own design. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/maaf/maaf_indirect.h"
#include "recon/maaf/maaf_shadow.h" /* maaf_pixel_param */
#include "maaf_test_plane.h"

enum { W = 48, H = 40, SPP = 4 };
#define PIXEL_WORLD 0.01f
#define HEIGHT 0.1f   /* the emitting plane's height over the receiver (world units) */
#define EDGE_C 0.44f  /* it emits 1 where X + Y > EDGE_C */

static unsigned rng_state = 4711u;
static float frand(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (float)(rng_state >> 8) / 16777216.0f;
}

/* brute force: int K(v - v_k) T(v) dv / T(v_k) on a midpoint grid 7 stds around v_k */
static void brute_factor(const MaafLens *t, int p, int q, double v1, double v2, double out[2])
{
    enum { N = 700 };
    double C1 = maaf_lens_band_centre(t, p), C2 = maaf_lens_band_centre(t, q), s = maaf_lens_band_std(t);
    double half = 7.0 / s, dv = 2.0 * half / N, re = 0.0, im = 0.0;
    for (int a = 0; a < N; ++a)
        for (int b = 0; b < N; ++b) {
            double d1 = -half + (a + 0.5) * dv, d2 = -half + (b + 0.5) * dv;
            double g = s * s / (2.0 * 3.14159265358979) * exp(-0.5 * s * s * (d1 * d1 + d2 * d2));
            double r = 1.0 + (v1 + d1) * (v1 + d1) + (v2 + d2) * (v2 + d2), tr = 1.0 / (r * r);
            re += g * tr * cos(C1 * d1 + C2 * d2);
            im += g * tr * sin(C1 * d1 + C2 * d2);
        }
    double r0 = 1.0 + v1 * v1 + v2 * v2;
    out[0] = re * dv * dv * r0 * r0;
    out[1] = im * dv * dv * r0 * r0;
}

/* A cosine-distributed direction above the plane z = 0 (uniform on the projected disk). */
static void cosine_dir(float d[3])
{
    float a, b;
    do {
        a = 2.0f * frand() - 1.0f;
        b = 2.0f * frand() - 1.0f;
    } while (a * a + b * b >= 1.0f);
    d[0] = a, d[1] = b, d[2] = sqrtf(1.0f - a * a - b * b);
}

/* Exact value at receiver point (x, y): the cosine-weighted fraction of directions whose hit
 * (x + h v1, y + h v2) lies where X + Y > EDGE_C. Along a unit direction e the cosine lobe's
 * marginal density of v_e is 1 / (2 (1 + v_e^2)^(3/2)), so P(v_e > a) = 1/2 - a / (2 sqrt(1 + a^2)),
 * here with e = (1, 1)/sqrt 2 and a = (EDGE_C - x - y) / (sqrt 2 h). Averaged over the pixel. */
static double exact_pixel(float x0, float y0)
{
    enum { SUB = 6 };
    double acc = 0.0;
    for (int i = 0; i < SUB; ++i)
        for (int j = 0; j < SUB; ++j) {
            double x = x0 + (i + 0.5) / SUB * PIXEL_WORLD, y = y0 + (j + 0.5) / SUB * PIXEL_WORLD;
            double a = (EDGE_C - x - y) / (sqrt(2.0) * HEIGHT);
            acc += 0.5 - a / (2.0 * sqrt(1.0 + a * a));
        }
    return acc / (SUB * SUB);
}

typedef MaafTestPlane Plane;

/* mirror: the design for the slope -h (every C_x negated), the wedge's mirror image */
static void plane_build(Plane *s, const MaafLens *dirs, bool mirror)
{
    maaf_test_plane_alloc(s, W, H, dirs->pairs);
    const float nrm[3] = {0.0f, 0.0f, 1.0f};
    float t1[3], t2[3];
    maaf_basis(nrm, t1, t2); /* the method's pixel frame for this normal */
    rng_state = 4711u;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + x;
            float x0 = x * PIXEL_WORLD, y0 = y * PIXEL_WORLD;
            float *p4 = s->pos4 + 4 * i, *n4 = s->nrm4 + 4 * i;
            p4[0] = x0 + 0.5f * PIXEL_WORLD, p4[1] = y0 + 0.5f * PIXEL_WORLD, p4[2] = 0.0f, p4[3] = 2.0f;
            n4[2] = 1.0f;
            memcpy(s->frame4 + 4 * i, t1, 3 * sizeof(float));
            s->frame4[4 * i + 3] = 1.0f;
            memcpy(s->axis2 + 4 * i, t2, 3 * sizeof(float));
            float *pr = s->param + i * MAAF_PARAM_STRIDE;
            maaf_pixel_param(0.9f * HEIGHT, 1.1f * HEIGHT, dirs->omega_u_max, dirs->pairs, 1.0f, PIXEL_WORLD, pr);
            if (mirror)
                for (int p = 0; p < MAAF_PAIRS_MAX; ++p) pr[2 + 3 * p] = -pr[2 + 3 * p];
            s->exact[i] = (float)exact_pixel(x0, y0);
            float sum = 0.0f;
            for (int k = 0; k < SPP; ++k) {
                float d[3], px = x0 + frand() * PIXEL_WORLD, py = y0 + frand() * PIXEL_WORLD;
                cosine_dir(d);
                float hx = px + HEIGHT * d[0] / d[2], hy = py + HEIGHT * d[1] / d[2];
                float val = hx + hy > EDGE_C ? 1.0f : 0.0f, f[4] = {val, val, val, 1.0f};
                maaf_direction_accumulate(dirs, t1, t2, nrm, d, f, s->ysum + i * (size_t)dirs->comps * 8);
                sum += val;
            }
            s->mean[i] = sum / SPP;
        }
}

/* maaf_direction_factor with the point as two coordinates (maaf_test_table_vs_brute's form) */
static void direction_factor_at(const MaafLens *t, int c, float v1, float v2, float out[2])
{
    const float v[2] = {v1, v2};
    maaf_direction_factor(t, c, v, out);
}

/* The width at a contact line: reflectors 1e-5 above receivers of footprint d give the
 * central band Omega_x = alpha(n) / d exactly, a std of 1/alpha(n) px: 3.33 px at AAF-GI's 16
 * rays, 1.67 px at 256 (16 times the count, half the width), 6.67 px at 1; scene size and knob
 * do not enter. A reflector higher than the floor keeps the design of its own heights. */
static void test_contact_width(void)
{
    const float spps[] = {1.0f, 9.0f, 16.0f, 256.0f}, footprints[] = {0.001f, 0.011f, 0.3f}, kappas[] = {1.0f, 3.0f, 8.5f};
    float param[MAAF_PARAM_STRIDE];
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 3; ++b)
            for (int k = 0; k < 3; ++k) {
                float omega = kappas[k] * MAAF_INDIRECT_OMEGA_V, h_min, h_max, d = footprints[b];
                maaf_indirect_heights(1e-5f, 1e-5f, omega, 3, d, spps[a], &h_min, &h_max);
                CHECK(h_max == h_min);
                float std_px = maaf_pixel_param(h_min, h_max, omega, 3, 1.0f, d, param);
                double want = 1.0 / (0.3 * pow(spps[a] / 16.0, 0.25));
                CHECK_NEAR(std_px, want, 1e-4 * want);
            }
    float h_min, h_max, std16, std256;
    maaf_indirect_heights(0.0f, 2.0f, 8.4f, 3, 0.01f, 16.0f, &h_min, &h_max);
    std16 = maaf_pixel_param(h_min, h_max, 8.4f, 3, 1.0f, 0.01f, param);
    maaf_indirect_heights(0.0f, 2.0f, 8.4f, 3, 0.01f, 256.0f, &h_min, &h_max);
    std256 = maaf_pixel_param(h_min, h_max, 8.4f, 3, 1.0f, 0.01f, param);
    CHECK(h_max == 2.0f);
    CHECK_NEAR(std16 / std256, 2.0, 1e-5);
    /* a reflector 1.0 above, footprint 0.01: the floor at 16 spp is 8.4 0.01 / (5 0.3) = 0.056 */
    maaf_indirect_heights(1.0f, 2.0f, 8.4f, 3, 0.01f, 16.0f, &h_min, &h_max);
    CHECK(h_min == 1.0f && h_max == 2.0f);
    /* no count (0 or NaN) counts as one sample: the widest floor, finite */
    maaf_indirect_heights(0.0f, 0.0f, 8.4f, 3, 0.01f, NAN, &h_min, &h_max);
    CHECK_NEAR(h_min, 8.4 * 0.01 / (5.0 * 0.3 * pow(1.0 / 16.0, 0.25)), 1e-6);
    printf("contact width: %.3f px at 16 spp, %.3f px at 256\n", std16, std256);
}

int main(void)
{
    test_contact_width();
    /* 1. the table against brute force, on and off the grid, near the centre and far out */
    MaafLens dirs;
    CHECK(maaf_direction_design(MAAF_INDIRECT_KAPPA_DEFAULT, 3, &dirs));
    CHECK(dirs.comps == 13);
    const float probes[][2] = {{0.0f, 0.0f}, {0.3f, -0.2f}, {-1.3f, 0.71f}, {2.5f, 1.1f}, {-4.03f, -3.1f}, {6.5f, 0.2f}};
    double worst, biggest;
    maaf_test_table_vs_brute(&dirs, probes, sizeof probes / sizeof probes[0], brute_factor, direction_factor_at, &worst,
                             &biggest);
    printf("direction table vs brute force: max |diff| %.2e (largest |c| %.3f)\n", worst, biggest);
    CHECK(worst < 5e-3 * biggest);
    CHECK(biggest > 0.5);

    /* 2. the mean over cosine-distributed directions is the closed form */
    {
        enum { SAMPLES = 40000 };
        double mean[13][2] = {{0}};
        rng_state = 99u;
        for (int k = 0; k < SAMPLES; ++k) {
            float d[3], v[2], f[2];
            cosine_dir(d);
            v[0] = d[0] / d[2], v[1] = d[1] / d[2];
            for (int cc = 0; cc < 13; ++cc) {
                maaf_direction_factor(&dirs, cc, v, f);
                mean[cc][0] += f[0] / SAMPLES, mean[cc][1] += f[1] / SAMPLES;
            }
        }
        double off = 0.0;
        for (int cc = 0; cc < 13; ++cc) off = fmax(off, hypot(mean[cc][0] - maaf_direction_mean(3, cc), mean[cc][1]));
        printf("cosine mean of the factors vs closed form: max |diff| %.3f (central %.3f, want 1)\n", off, mean[0][0]);
        CHECK(off < 0.03);
        CHECK(maaf_direction_mean(3, 0) == 1.0f);
    }

    /* 3. the plane under a step edge: right design against the pixel mean and the mirror */
    float *out = malloc(4 * W * H * sizeof(float));
    MaafLens paper;
    CHECK(maaf_direction_design(1.0f, 3, &paper));
    const MaafLens *designs[2] = {&dirs, &paper};
    Plane right, wrong;
    for (int k = 0; k < 2; ++k) {
        plane_build(&right, designs[k], false);
        plane_build(&wrong, designs[k], true);
        double e_mean, e_maaf, e_wrong;
        int filtered = maaf_test_plane_right_wrong(&right, &wrong, out, &e_mean, &e_maaf, &e_wrong);
        printf("plane under an edge (h %.2f, %d spp, kappa %s): rmse pixel mean %.4f, MAAF %.4f, mirrored wedge %.4f\n",
               (double)HEIGHT, SPP, k == 0 ? "default" : "1", e_mean, e_maaf, e_wrong);
        CHECK(filtered == W * H);
        /* kappa 1's filters are twice as wide (16 px std here): more of the edge's curvature blurs */
        CHECK(e_maaf < (k == 0 ? 0.4 : 0.6) * e_mean);
        CHECK(e_wrong > (k == 0 ? 1.5 : 2.0) * e_maaf);
        maaf_test_plane_free(&right);
        maaf_test_plane_free(&wrong);
    }
    maaf_lens_free(&paper);

    /* 4. the kernel against the C reference on the receiver guides, with rejected neighbours */
    plane_build(&right, &dirs, false);
    for (int i = 0; i < W * H; ++i) {
        if (i % 13 == 4) right.nrm4[4 * i + 3] = 1.0f;              /* another object */
        if (i % 17 == 3) right.pos4[4 * i + 2] = 0.5f;              /* off the tangent plane */
        if (i % 19 == 2) right.frame4[4 * i + 3] = 0.0f;            /* unusable */
        if (i % 23 == 9) right.param[i * MAAF_PARAM_STRIDE] = 0.0f; /* not filtered */
    }
    maaf_test_plane_kernel_check(&right, 0.93969262f, "receiver guides");
    maaf_test_plane_free(&right);
    free(out);
    maaf_lens_free(&dirs);
    CHECK_DONE();
}
