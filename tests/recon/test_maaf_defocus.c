/* MAAF for defocus (maaf_defocus.c, docs/algorithms.md 9.8). Oracles:
 *   - the lens-factor table equals a brute-force integral of the component over the unit disk;
 *   - the mirrored (negative-slope) design: its separable primal form equals the direct
 *     component sum, and its Fourier design covers the negative-slope wedge, not its mirror;
 *   - a synthetic defocused plane (constant depth, known circle of confusion, a diagonal step
 *     edge whose blur has a closed form) at 8 spp: MAAF is well below the pixel mean's error,
 *     and the design of the opposite slope sign (the mirrored wedge) is clearly worse;
 *   - the OpenCL pass on screen guides (negative C_x, pixels of the other side of the focal
 *     plane rejected) equals the C reference;
 *   - putting a shading light back into a pixel's lens sums (maaf_defocus_add_light) gives the
 *     sums of the samples with that light substituted, in each of its three cases. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/maaf/maaf_defocus.h"
#include "maaf_test_plane.h"

enum { W = 36, H = 28, SPP = 8 };
#define COC_PX 6.0f   /* circle-of-confusion radius: px per unit lens coordinate */
#define EDGE_C 30.0f  /* the texture is 1 where X + Y > EDGE_C (raster pixels) */

static unsigned rng_state = 12345u;
static float frand(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (float)(rng_state >> 8) / 16777216.0f;
}

/* brute force: c_pq(u, v) on a polar grid of the disk (midpoints) */
static void brute_factor(const MaafLens *l, int p, int q, double u, double v, double out[2])
{
    enum { NR = 400, NA = 800 };
    double C1 = maaf_lens_band_centre(l, p), C2 = maaf_lens_band_centre(l, q), s = maaf_lens_band_std(l);
    double re = 0.0, im = 0.0;
    for (int a = 0; a < NR; ++a)
        for (int b = 0; b < NA; ++b) {
            double r = (a + 0.5) / NR, t = 2.0 * 3.14159265358979 * (b + 0.5) / NA;
            double du = r * cos(t) - u, dv = r * sin(t) - v;
            double g = s * s / (2.0 * 3.14159265358979) * exp(-0.5 * s * s * (du * du + dv * dv));
            double ph = C1 * du + C2 * dv, da = r / NR * 2.0 * 3.14159265358979 / NA;
            re += g * cos(ph) * da;
            im += g * sin(ph) * da;
        }
    out[0] = re, out[1] = im;
}

/* fraction of the unit disk with u < a */
static double disk_fraction_below(double a)
{
    if (a <= -1.0) return 0.0;
    if (a >= 1.0) return 1.0;
    return (a * sqrt(1.0 - a * a) + asin(a) + 0.5 * 3.14159265358979) / 3.14159265358979;
}

/* The renderer's convention (maaf_defocus.h): sample (x, y, u, v) sees the texture at
 * (x - coc u, y + coc v). The edge X + Y > c is then seen where u - v < (x + y - c)/coc, i.e.
 * (u - v)/sqrt 2 < (x + y - c)/(coc sqrt 2); the pixel value is averaged over the pixel. */
static double exact_pixel(int x, int y)
{
    enum { SUB = 8 };
    double acc = 0.0;
    for (int a = 0; a < SUB; ++a)
        for (int b = 0; b < SUB; ++b) {
            double px = x + (a + 0.5) / SUB, py = y + (b + 0.5) / SUB;
            acc += 1.0 - disk_fraction_below((EDGE_C - px - py) / (COC_PX * sqrt(2.0)));
        }
    return acc / (SUB * SUB);
}

typedef MaafTestPlane Plane;

/* slope_sign -1: the design for s = -coc (right); +1: the mirrored wedge */
static void plane_build(Plane *s, const MaafLens *lens, float slope_sign)
{
    maaf_test_plane_alloc(s, W, H, lens->pairs);
    rng_state = 12345u;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + x;
            maaf_screen_guides(x, y, slope_sign, true, s->pos4 + 4 * i, s->nrm4 + 4 * i, s->frame4 + 4 * i, s->axis2 + 4 * i);
            maaf_pixel_param_signed(slope_sign * 0.9f * COC_PX, slope_sign * 1.1f * COC_PX, lens->omega_u_max, lens->pairs,
                                    s->param + i * MAAF_PARAM_STRIDE);
            s->exact[i] = (float)exact_pixel(x, y);
            float sum = 0.0f;
            for (int k = 0; k < SPP; ++k) {
                float u, v;
                do {
                    u = 2.0f * frand() - 1.0f;
                    v = 2.0f * frand() - 1.0f;
                } while (u * u + v * v > 1.0f);
                float px = x + frand(), py = y + frand();
                float val = (px - COC_PX * u) + (py + COC_PX * v) > EDGE_C ? 1.0f : 0.0f;
                float f[4] = {val, val, val, 1.0f};
                maaf_lens_accumulate(lens, u, -v, f, s->ysum + i * (size_t)lens->comps * 8);
                sum += val;
            }
            s->mean[i] = sum / SPP;
        }
}

int main(void)
{
    /* 1. the lens-factor table against brute force, at grid and off-grid points */
    MaafLens lens;
    CHECK(maaf_lens_design(MAAF_DEFOCUS_KAPPA_DEFAULT, 3, &lens));
    CHECK(lens.comps == 13);
    /* u > 0 reads the stored half (u <= 0) through the conjugate symmetry; u = 0 and the rims
     * test its ends */
    const float probes[][2] = {{0.0f, 0.0f},      {0.3f, -0.2f}, {-0.71f, 0.55f}, {0.93f, 0.1f},
                               {0.013f, -0.987f}, {1.0f, -0.6f}, {-1.0f, 0.45f},  {0.0f, 0.77f}};
    double worst, biggest;
    maaf_test_table_vs_brute(&lens, probes, sizeof probes / sizeof probes[0], brute_factor, maaf_lens_factor, &worst,
                             &biggest);
    /* every component's factors at once (the sums' lookup) equal the one-component lookup */
    bool same = true;
    for (size_t k = 0; k < sizeof probes / sizeof probes[0]; ++k) {
        float all[2 * MAAF_COMPS_MAX], one[2];
        maaf_lens_factors(&lens, probes[k][0], probes[k][1], all);
        for (int cc = 0; cc < lens.comps; ++cc) {
            maaf_lens_factor(&lens, cc, probes[k][0], probes[k][1], one);
            same = same && fabsf(one[0] - all[2 * cc]) <= 1e-6f && fabsf(one[1] - all[2 * cc + 1]) <= 1e-6f;
        }
    }
    CHECK(same);
    printf("lens table vs brute force: max |diff| %.2e (largest |c| %.3f)\n", worst, biggest);
    CHECK(worst < 5e-3 * biggest);
    CHECK(biggest > 0.1);

    /* 2. the mirrored design: separable == direct, and it covers the negative-slope wedge */
    MaafDesign2D d;
    CHECK(!maaf_design_2d_signed(-2.0f, 3.0f, 8.0f, 3, &d)); /* straddles the focal plane */
    CHECK(maaf_design_2d_signed(-5.0f, -3.0f, 8.0f, 3, &d));
    CHECK(d.s_min == -5.0f && d.s_max == -3.0f);
    double sep = 0.0;
    for (int k = 0; k < 50; ++k) {
        double x = 6.0 * frand() - 3.0, y = 2.0 * frand() - 1.0;
        sep = fmax(sep, fabs(maaf_primal_2d_separable(&d, x, y) - maaf_primal_2d_direct(&d, x, y)));
    }
    printf("mirrored design: separable vs direct max |diff| %.2e\n", sep);
    CHECK(sep < 1e-9);
    double on = 0.0, mirror = 0.0;
    for (int k = 1; k <= 20; ++k) { /* the wedge's middle line and its mirror image, above the
                                       * central band (|Omega_y| > 8/5, which holds both) */
        double wy = 8.0 * (0.3 + 0.7 * k / 21.0), s = -4.0;
        on += maaf_fourier_2d(&d, wy / s, wy);
        mirror += maaf_fourier_2d(&d, -wy / s, wy);
    }
    printf("mirrored design on its wedge %.3f, on the mirror image %.3f\n", on / 20, mirror / 20);
    CHECK(on > 10.0 * mirror);

    /* 3. the defocused plane, at the default knob and at the paper's design (kappa 1: the
     * widest filters, whose offset components carry the most: the sign matters most there) */
    Plane right, wrong;
    float *out = malloc(4 * W * H * sizeof(float));
    MaafLens paper;
    CHECK(maaf_lens_design(1.0f, 3, &paper));
    const MaafLens *designs[2] = {&lens, &paper};
    for (int k = 0; k < 2; ++k) {
        plane_build(&right, designs[k], -1.0f);
        plane_build(&wrong, designs[k], 1.0f);
        double e_mean, e_maaf, e_wrong;
        int filtered = maaf_test_plane_right_wrong(&right, &wrong, out, &e_mean, &e_maaf, &e_wrong);
        printf("defocused plane (coc %.0f px, %d spp, kappa %s): rmse pixel mean %.4f, MAAF %.4f, mirrored slope %.4f\n",
               (double)COC_PX, SPP, k == 0 ? "default" : "1", e_mean, e_maaf, e_wrong);
        CHECK(filtered == W * H);
        CHECK(e_maaf < 0.5 * e_mean);
        CHECK(e_wrong > (k == 0 ? 1.2 : 2.0) * e_maaf);
        maaf_test_plane_free(&right);
        maaf_test_plane_free(&wrong);
    }
    maaf_lens_free(&paper);

    /* 5. the shading substitution is linear: sums of (L - D) and of the albedo, then the light
     * put back, equal the sums of each sample's L - D + substitute accumulated directly */
    {
        enum { SAMPLES = 7 };
        size_t per = (size_t)lens.comps * 8;
        float *rest = calloc(per, sizeof(float)), *alb = calloc(per, sizeof(float)), *got = malloc(per * sizeof(float)),
              *want = malloc(per * sizeof(float));
        const float filtered4[4] = {0.3f, 0.5f, 0.9f, 1.0f}, raw4[4] = {0.7f, 0.2f, 0.4f, 0.0f}, mean3[3] = {0.25f, 0.6f, 0.1f};
        const float factor = 1.7f;
        float su[SAMPLES], sv[SAMPLES], sl[SAMPLES][3], sa[SAMPLES][3];
        rng_state = 4242u;
        for (int k = 0; k < SAMPLES; ++k) {
            su[k] = 1.4f * frand() - 0.7f, sv[k] = 1.4f * frand() - 0.7f;
            for (int ch = 0; ch < 3; ++ch) sl[k][ch] = frand(), sa[k][ch] = frand();
            float f[4] = {sl[k][0], sl[k][1], sl[k][2], 1.0f}, a[4] = {sa[k][0], sa[k][1], sa[k][2], 0.0f};
            maaf_lens_accumulate(&lens, su[k], sv[k], f, rest);
            maaf_lens_accumulate(&lens, su[k], sv[k], a, alb);
        }
        for (int mode = 0; mode < 3; ++mode) { /* filtered, passed through, not filtered */
            const float *v4 = mode == 0 ? filtered4 : mode == 1 ? raw4 : NULL;
            memcpy(got, rest, per * sizeof(float));
            maaf_defocus_add_light(v4, factor, mean3, rest, alb, per, got);
            memset(want, 0, per * sizeof(float));
            for (int k = 0; k < SAMPLES; ++k) {
                float f[4] = {0, 0, 0, 1.0f};
                for (int ch = 0; ch < 3; ++ch)
                    f[ch] = sl[k][ch] + (mode == 0 ? factor * filtered4[ch] * sa[k][ch] : mode == 1 ? raw4[ch] : mean3[ch]);
                maaf_lens_accumulate(&lens, su[k], sv[k], f, want);
            }
            double diff = 0.0, size = 0.0;
            for (size_t c = 0; c < per; ++c) diff = fmax(diff, fabs(got[c] - want[c])), size = fmax(size, fabs(want[c]));
            printf("substitution case %d: max |diff| %.2e of %.3f\n", mode, diff, size);
            CHECK(diff < 1e-5 * size);
            CHECK(size > 0.1);
        }
        free(rest), free(alb), free(got), free(want);
    }

    /* 4. the kernel against the C reference on screen guides, with rejected neighbours */
    plane_build(&right, &lens, -1.0f);
    for (int i = 0; i < W * H; ++i) {
        if (i % 13 == 4) right.nrm4[4 * i + 3] = 1.0f;              /* the other side of the focal plane */
        if (i % 19 == 2) right.frame4[4 * i + 3] = 0.0f;            /* unusable */
        if (i % 23 == 9) right.param[i * MAAF_PARAM_STRIDE] = 0.0f; /* not filtered */
    }
    maaf_test_plane_kernel_check(&right, 0.93969262f, "screen guides");
    /* the lens filter's own sharpness rule: neighbours a little sharper (std 0.88 of the
     * others': kept by both rules) and much sharper (0.71: kept by the light filter's 0.5,
     * left out by the lens filter's 0.8); the kernel must decide as the reference does */
    int sharper = 0, rejected = 0;
    for (int i = 0; i < W * H; ++i) {
        float *pr = right.param + i * MAAF_PARAM_STRIDE;
        if (i % 17 == 5) pr[3] *= 1.3f;
        if (i % 11 == 3) pr[3] *= 2.0f, ++sharper;
    }
    for (int i = 0; i < W * H; ++i) rejected += right.param[i * MAAF_PARAM_STRIDE + 3] > MAAF_LENS_SHARP_FACTOR * right.param[3];
    CHECK(sharper > 0 && rejected > 0);
    maaf_test_plane_kernel_check(&right, 0.93969262f, "screen guides, sharper neighbours, light filter's rule");
    maaf_test_plane_kernel_check_sharp(&right, 0.93969262f, MAAF_LENS_SHARP_FACTOR,
                                       "screen guides, sharper neighbours, lens filter's rule");
    maaf_test_plane_free(&right);
    free(out);
    maaf_lens_free(&lens);
    CHECK_DONE();
}
