/* AAF parameter math (aaf_params.c, aaf_pixel_params.c) against values derived by hand from
 * the papers' equations, consistency in mu, and finiteness on degenerate inputs. */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "recon/aaf/aaf_params.h"
#include "recon/aaf/aaf_pixel_params.h"

static void test_shadow_hand_values(void)
{
    AafShadowConfig c = aaf_shadow_config_default();
    CHECK_NEAR(c.k, 3.0, 0.0);
    CHECK_NEAR(c.alpha, 1.0, 0.0);
    CHECK_NEAR(c.mu, 2.0, 0.0);

    /* Light at distance d1 = 2 from the receiver, occluders between 0.5 and 1 from the light.
     * Eq. 4: s1 = 2/0.5 - 1 = 3 (steepest), s2 = 2/1 - 1 = 1. */
    float s1, s2;
    aaf_shadow_slopes(2.0f, 0.5f, 1.0f, &s1, &s2);
    CHECK_NEAR(s1, 3.0, 1e-6);
    CHECK_NEAR(s2, 1.0, 1e-6);

    /* sigma = 0.1, pixel d = 0.01.
     * Eq. 6: Omega_x^max = alpha/((1 + s2) d) = 1/(2 * 0.01) = 50.
     * Eq. 8: Omega_x^f = min(Omega_L/s2, 50) = min(10/1, 50) = 10.
     * Eq. 13: beta = 1/(k mu Omega_x^f) = 1/(3*2*10) = 1/60 = (1/6) max(0.1*1, 1/50). */
    CHECK_NEAR(aaf_shadow_omega_x_max(1.0f, s2, 0.01f), 50.0, 1e-4);
    CHECK_NEAR(aaf_shadow_omega_x_f(0.1f, s2, 50.0f), 10.0, 1e-5);
    CHECK_NEAR(aaf_shadow_beta_world(s2, 0.1f, 0.01f, &c), 1.0 / 60.0, 1e-7);

    /* Eq. 21 closed form, valid here (no min() clause active):
     *   n = 4 (1 + mu s1/s2)^2 (mu (2/s2) sqrt(A_p/A_l) + alpha/(1 + s2))^2
     * with sqrt(A_p/A_l) = d/(2 sigma) = 0.05: 4 * 7^2 * (0.2 + 0.5)^2 = 4 * 49 * 0.49 = 96.04.
     * (Checks the general form: Omega_y^max = (1 - 0.5/2)/0.01 = 75 > s1 mu Omega_x^f = 60.) */
    CHECK_NEAR(aaf_shadow_spp(s1, s2, 0.1f, 0.01f, &c), 96.04, 1e-3);

    /* Contact shadow, occluder almost on the receiver: d2max = 1.99, s2 = 2/1.99 - 1.
     * Omega_L/s2 = 1990 > Omega_x^max = 1/(0.01 (1 + s2)), so the pixel band wins:
     * beta = d (1 + s2)/(k mu alpha) = 0.01 * (2/1.99)/6. */
    aaf_shadow_slopes(2.0f, 1.99f, 1.99f, &s1, &s2);
    CHECK_NEAR(aaf_shadow_beta_world(s2, 0.1f, 0.01f, &c), 0.01 * (2.0 / 1.99) / 6.0, 1e-8);
    /* ... and the count stays finite where the closed form eq. 21 would blow up (s2 -> 0):
     * Omega_x^* d = (mu + 1) alpha/(1 + s2); Omega_y^* 2 sigma = 2 + 2 sigma s1 mu Omega_x^max. */
    {
        double s = 2.0 / 1.99 - 1.0, ox = 1.0 / (0.01 * (1.0 + s));
        double nx = 3.0 / (1.0 + s), ny = 2.0 + 0.2 * fmin(s * 2.0 * ox, (s / (1.0 + s)) / 0.01);
        CHECK_NEAR(aaf_shadow_spp((float)s, (float)s, 0.1f, 0.01f, &c), nx * nx * ny * ny, 1e-3);
    }
}

static void test_shadow_degenerate(void)
{
    AafShadowConfig c = aaf_shadow_config_default();
    float s1, s2;
    /* occluder at the light: steepest slope, clamped */
    aaf_shadow_slopes(2.0f, 0.0f, 1.0f, &s1, &s2);
    CHECK_NEAR(s1, AAF_SLOPE_MAX, 0.0);
    /* occluder behind the receiver (rounding): slope 0 */
    aaf_shadow_slopes(2.0f, 2.5f, 3.0f, &s1, &s2);
    CHECK_NEAR(s1, 0.0, 0.0);
    CHECK_NEAR(s2, 0.0, 0.0);
    /* NaN / inf distances */
    aaf_shadow_slopes(NAN, NAN, INFINITY, &s1, &s2);
    CHECK(isfinite(s1) && isfinite(s2));
    float bad[] = {0.0f, -1.0f, NAN, INFINITY, 1e-30f, 1e30f};
    for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 6; ++b)
            for (int e = 0; e < 6; ++e) {
                aaf_shadow_slopes(1.0f, bad[a], bad[b], &s1, &s2);
                float beta = aaf_shadow_beta_world(s2, bad[e], bad[b], &c);
                float n = aaf_shadow_spp(s1, s2, bad[e], bad[a], &c);
                CHECK(isfinite(beta) && beta >= 0.0f);
                CHECK(!isnan(n));
                int spp = aaf_clamp_spp(n, 9, 200.0f);
                CHECK(spp >= 9 && spp <= 200);
            }
}

static void test_consistency_in_mu(void)
{
    /* Width ~ 1/mu exactly (eq. 13, eq. 16, defocus analogue), so it falls to 0 as mu grows,
     * while the sample count never decreases (eq. 21). */
    AafShadowConfig sc = aaf_shadow_config_default();
    AafIndirectConfig ic = aaf_indirect_config_default();
    AafDefocusConfig dc = aaf_defocus_config_default();
    sc.mu = ic.mu = dc.mu = 1.0f;
    float b_s1 = aaf_shadow_beta_world(1.0f, 0.1f, 0.01f, &sc);
    float b_i1 = aaf_indirect_beta_world(1.0f, 2.8f, 0.01f, &ic);
    float b_d1 = aaf_defocus_beta_px(6.0f, 12.0f, &dc);
    float prev_n_s = 0, prev_n_i = 0, prev_n_d = 0, prev_b = FLT_MAX;
    for (float mu = 1.0f; mu <= 1.0e6f; mu *= 4.0f) {
        sc.mu = ic.mu = dc.mu = mu;
        float bs = aaf_shadow_beta_world(1.0f, 0.1f, 0.01f, &sc);
        CHECK_NEAR(bs, b_s1 / mu, 1e-6 * b_s1);
        CHECK_NEAR(aaf_indirect_beta_world(1.0f, 2.8f, 0.01f, &ic), b_i1 / mu, 1e-6 * b_i1);
        CHECK_NEAR(aaf_defocus_beta_px(6.0f, 12.0f, &dc), b_d1 / mu, 1e-6 * b_d1);
        CHECK(bs < prev_b);
        prev_b = bs;
        float ns = aaf_shadow_spp(3.0f, 1.0f, 0.1f, 0.01f, &sc);
        float ni = aaf_indirect_spp(1.0f, 3.0f, 2.8f, 0.4f, 0.01f, &ic);
        float nd = aaf_defocus_spp(6.0f, 12.0f, &dc);
        CHECK(ns >= prev_n_s && ni >= prev_n_i && nd >= prev_n_d);
        prev_n_s = ns;
        prev_n_i = ni;
        prev_n_d = nd;
    }
    CHECK(prev_b <= b_s1 / 262144.0f * 1.0001f); /* last mu = 4^9 */
    /* mu = inf: zero width (no filter), the sample count at its cap, nothing NaN. */
    sc.mu = ic.mu = dc.mu = INFINITY;
    CHECK_NEAR(aaf_shadow_beta_world(1.0f, 0.1f, 0.01f, &sc), 0.0, 0.0);
    CHECK_NEAR(aaf_indirect_beta_world(1.0f, 2.8f, 0.01f, &ic), 0.0, 0.0);
    CHECK_NEAR(aaf_defocus_beta_px(6.0f, 12.0f, &dc), 0.0, 0.0);
    CHECK(aaf_clamp_spp(aaf_shadow_spp(3.0f, 1.0f, 0.1f, 0.01f, &sc), 9, 1e9f) == AAF_SPP_HARD_MAX);
}

static void test_indirect_hand_values(void)
{
    AafIndirectConfig c = aaf_indirect_config_default();
    CHECK_NEAR(c.alpha, 0.3, 1e-7);
    CHECK_NEAR(c.spp_cap_per_mu, 16.0, 0.0); /* our measured cap (paper: 100) */
    c.mu = 1.0f;                             /* the hand values below are at mu = 1 */
    CHECK_NEAR(aaf_indirect_omega_h_diffuse(), 2.8, 1e-6);
    /* eq. 18: 3.6 + 0.084 * 20 = 5.28 */
    CHECK_NEAR(aaf_indirect_omega_h_glossy(20.0f), 5.28, 1e-5);
    /* Sec. 4.3: gamma = acos(cos(pi/4)^(1/20))/(pi/2): 0.70711^0.05 = 0.982821, acos = 0.185631,
     * / 1.570796 = 0.118176 (the paper rounds this to 0.11). */
    CHECK_NEAR(aaf_indirect_gamma_glossy(20.0f), 0.118176, 2e-5);
    CHECK_NEAR(aaf_indirect_gamma_diffuse(), 0.4, 1e-7);
    /* zmin = 1, zmax = 3, d = 0.01, mu = 1, diffuse.
     * Eq. 15: Omega_x^r = min(2.8/1, 0.3/0.01 = 30) = 2.8. Eq. 16: beta = 2/2.8 = 0.714286. */
    CHECK_NEAR(aaf_indirect_omega_x_r(1.0f, 2.8f, 0.01f, 0.3f, 1.0f), 2.8, 1e-6);
    CHECK_NEAR(aaf_indirect_beta_world(1.0f, 2.8f, 0.01f, &c), 2.0 / 2.8, 1e-6);
    /* Eq. 21: n = gamma (mu Omega_h sqrt(A_p)/zmin + alpha)^2 Omega_h^2 (1 + mu zmax/zmin)^2
     *           = 0.4 * (0.028 + 0.3)^2 * 2.8^2 * 4^2 = 0.4 * 0.107584 * 7.84 * 16 = 5.398115 */
    CHECK_NEAR(aaf_indirect_spp(1.0f, 3.0f, 2.8f, 0.4f, 0.01f, &c), 5.398115, 1e-4);
    /* Very close reflector: the pixel band caps the filter band: Omega_x^r = 30, beta = 2/30. */
    CHECK_NEAR(aaf_indirect_beta_world(0.05f, 2.8f, 0.01f, &c), 2.0 / 30.0, 1e-6);
    /* Sec. 5: zmin clamped to 2% of the scene size (10 -> 0.2). */
    CHECK_NEAR(aaf_indirect_clamp_zmin(0.001f, 10.0f, 0.02f), 0.2, 1e-7);
    CHECK_NEAR(aaf_indirect_clamp_zmin(0.5f, 10.0f, 0.02f), 0.5, 0.0);
    /* degenerate */
    float bad[] = {0.0f, -1.0f, NAN, INFINITY};
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            float beta = aaf_indirect_beta_world(bad[a], 2.8f, bad[b], &c);
            CHECK(!isnan(beta) && beta >= 0.0f);
            CHECK(!isnan(aaf_indirect_spp(bad[a], bad[b], 2.8f, 0.4f, bad[b], &c)));
            CHECK(isfinite(aaf_indirect_clamp_zmin(bad[a], bad[b], 0.02f)));
        }
}

/* The indirect cap (aaf_indirect_spp_cap): 16 mu up to the default mu 2, as measured before;
 * beyond it the samples under a capped pixel's filter, cap * beta^2 with beta from eq. 16, must
 * grow with mu, or a larger budget (which raises mu) leaves each filtered pixel fewer samples
 * and more variance. With the paper's linear cap, cap * beta^2 falls like 1/mu. */
static void test_indirect_cap_grows_under_the_filter(void)
{
    AafIndirectConfig c = aaf_indirect_config_default();
    for (float mu = 0.5f; mu <= 2.0f; mu += 0.5f) {
        c.mu = mu;
        CHECK_NEAR(aaf_indirect_spp_cap(&c), 16.0 * mu, 1e-4);
    }
    double prev = 0.0;
    const float mus[] = {2.0f, 2.5f, 3.0f, 4.0f, 8.0f, 16.0f, 64.0f};
    for (size_t k = 0; k < sizeof mus / sizeof mus[0]; ++k) {
        c.mu = mus[k];
        double beta = aaf_indirect_beta_world(1.0f, 2.8f, 0.01f, &c); /* zmin 1: the reflector sets the band */
        double under = aaf_indirect_spp_cap(&c) * beta * beta;
        CHECK(under > prev * 1.1);
        if (!(under > prev * 1.1)) fprintf(stderr, "mu %g: cap * beta^2 %g after %g\n", (double)mus[k], under, prev);
        prev = under;
    }
    c.mu = INFINITY;
    CHECK(aaf_indirect_spp_cap(&c) == FLT_MAX);
}

/* Pixels with no occluder nearby (aaf_far_spp): pass 1's count up to mu 2, then enough that
 * the samples under their filter (width ~ 1/mu, aaf_method.c) grow with mu; with the old
 * pass1 * mu/2 they fell like 1/mu and the test fails. */
static void test_far_samples_grow_under_the_filter(void)
{
    for (float mu = 0.5f; mu <= 2.0f; mu += 0.5f) CHECK(aaf_far_spp(9, mu) == 9);
    double prev = 0.0;
    const float mus[] = {2.0f, 2.5f, 3.0f, 4.0f, 8.0f, 16.0f};
    for (size_t k = 0; k < sizeof mus / sizeof mus[0]; ++k) {
        double width = 1.0 / mus[k];
        double under = aaf_far_spp(9, mus[k]) * width * width;
        CHECK(under > prev * 1.1);
        if (!(under > prev * 1.1)) fprintf(stderr, "mu %g: far spp * width^2 %g after %g\n", (double)mus[k], under, prev);
        prev = under;
    }
    CHECK(aaf_far_spp(9, NAN) == 9);
}

static void test_defocus_hand_values(void)
{
    AafDefocusConfig c = aaf_defocus_config_default();
    CHECK_NEAR(c.mu, 1.0, 0.0); /* measured default (docs/algorithms.md) */
    c.mu = 2.0f;                /* the hand values below are at mu = 2 */
    float amin, amax;
    aaf_defocus_abs_slopes(-3.0f, 5.0f, &amin, &amax);
    CHECK_NEAR(amin, 0.0, 0.0); /* straddles the focal plane */
    CHECK_NEAR(amax, 5.0, 0.0);
    aaf_defocus_abs_slopes(-10.0f, -4.0f, &amin, &amax);
    CHECK_NEAR(amin, 4.0, 0.0);
    CHECK_NEAR(amax, 10.0, 0.0);
    /* Straddling: Omega_x^f0 = alpha = 1 -> beta = 1/(k mu alpha) = 1/6 px (a pixel-sized
     * filter, i.e. none), n = (mu alpha + alpha)^2 (Omega_u + min(5 mu, 5 alpha))^2 (2 sigma_u)^2
     *   = 3^2 * (2 + 5)^2 * 1 = 441. */
    CHECK_NEAR(aaf_defocus_beta_px(-3.0f, 5.0f, &c), 1.0 / 6.0, 1e-7);
    CHECK_NEAR(aaf_defocus_spp(-3.0f, 5.0f, &c), 441.0, 1e-3);
    /* Behind the focal plane, slopes 4..10 px: Omega_x^f0 = min(Omega_u/4, 1) = 0.5,
     * beta = (1/(k mu)) max(sigma_u 4, 1) = 2/6 = 1/3 px;
     * n = (mu 0.5 + 1)^2 (2 + min(10 * 1, 10 * 1))^2 = 4 * 144 = 576. Sign does not matter. */
    CHECK_NEAR(aaf_defocus_beta_px(4.0f, 10.0f, &c), 1.0 / 3.0, 1e-7);
    CHECK_NEAR(aaf_defocus_beta_px(-10.0f, -4.0f, &c), 1.0 / 3.0, 1e-7);
    CHECK_NEAR(aaf_defocus_spp(4.0f, 10.0f, &c), 576.0, 1e-3);
    /* A large, uniform blur: slopes 30..30 px: beta = (1/6) * 15 = 2.5 px. */
    CHECK_NEAR(aaf_defocus_beta_px(30.0f, 30.0f, &c), 2.5, 1e-6);
    CHECK(aaf_clamp_spp(aaf_defocus_spp(NAN, INFINITY, &c), 16, 200.0f) <= 200);
    CHECK(isfinite(aaf_defocus_beta_px(NAN, INFINITY, &c)));
}

static void test_clamp_spp(void)
{
    CHECK(aaf_clamp_spp(3.2f, 9, 200.0f) == 9);
    CHECK(aaf_clamp_spp(96.04f, 9, 200.0f) == 97);
    CHECK(aaf_clamp_spp(1e9f, 9, 200.0f) == 200);
    CHECK(aaf_clamp_spp(NAN, 9, 200.0f) == 200);
    CHECK(aaf_clamp_spp(50.0f, 9, NAN) == 50);
    CHECK(aaf_clamp_spp(5.0f, 16, 4.0f) == 16); /* cap below the pass-1 count: pass 1 wins */
}

/* Image maps: a 9x9 image, one occluded pixel in the centre with d1 = 2, d2 = [0.5, 1];
 * pixels within the borrow radius (2) take its statistics, the others get the "far" width
 * (0.5 px here, i.e. 0.005 world) or none when it is 0. */
static void test_shadow_image_borrowing(void)
{
    enum { W = 9, H = 9, N = W * H };
    float d1[N], d2min[N], d2max[N], sigma[N], pw[N], beta[N];
    int spp[N];
    for (int i = 0; i < N; ++i) {
        d1[i] = 2.0f;
        d2min[i] = d2max[i] = 0.0f;
        sigma[i] = 0.1f;
        pw[i] = 0.01f;
    }
    d2min[4 * W + 4] = 0.5f;
    d2max[4 * W + 4] = 1.0f;
    AafPixelStats st = {0};
    st.width = W;
    st.height = H;
    st.pixel_world = pw;
    st.d1_world = d1;
    st.d2min_world = d2min;
    st.d2max_world = d2max;
    st.sigma_light_world = sigma;
    AafShadowConfig c = aaf_shadow_config_default();
    AafImageConfig ic = {2, 9, 200.0f, 0.0f, 0};
    int filtered = aaf_shadow_params_image(&st, &c, &ic, beta, spp);
    CHECK(filtered == 25);
    CHECK_NEAR(beta[4 * W + 4], 1.0 / 60.0, 1e-7);
    CHECK(spp[4 * W + 4] == 97);
    CHECK_NEAR(beta[2 * W + 6], 1.0 / 60.0, 1e-7); /* borrowed (corner of the 5x5 window) */
    CHECK_NEAR(beta[1 * W + 4], 0.0, 0.0);         /* too far: unoccluded, unfiltered */
    CHECK(spp[0] == 9);
    ic.far_beta_px = 0.5f;
    filtered = aaf_shadow_params_image(&st, &c, &ic, beta, spp);
    CHECK(filtered == N);
    CHECK_NEAR(beta[1 * W + 4], 0.5 * 0.01, 1e-9); /* far width, converted to world units */
    CHECK_NEAR(beta[4 * W + 4], 1.0 / 60.0, 1e-7);
    CHECK(spp[1 * W + 4] == 9);
}

/* Indirect image maps at a contact line (far_light_bounce.pbrt: the floor at a wall's foot):
 * every pixel's reflector is 0.001 away, in a scene 100 across. Sec. 5's clamp (2%: zmin 2)
 * bounds the sample count (eq. 21), but the width keeps the measured zmin: eq. 15's pixel term
 * alpha / d then sets it, beta = 2 / (mu alpha / d) = 2 * 0.01 / (2 * 0.3) = 1/30. With the
 * clamped zmin the width was 2 / (mu omega_h / 2) = 0.714 (71 pixels): a filter far wider than
 * the gradient of the light bounced off the wall, which darkened the floor along the contact
 * (docs/benchmarks.md, "Held-out bench scenes"). */
static void test_indirect_image_contact(void)
{
    enum { W = 7, H = 1, N = W * H };
    float zmin[N], zmax[N], pw[N], beta[N];
    int spp[N];
    for (int i = 0; i < N; ++i) zmin[i] = 0.001f, zmax[i] = 5.0f, pw[i] = 0.01f;
    AafPixelStats st = {.width = W, .height = H, .pixel_world = pw, .zmin_world = zmin, .zmax_world = zmax};
    AafIndirectConfig c = aaf_indirect_config_default();
    AafImageConfig ic = {2, 9, 200.0f, 0.0f, 0};
    CHECK(aaf_indirect_params_image(&st, &c, &ic, 100.0f, beta, spp) == N);
    int want_spp = aaf_clamp_spp(aaf_indirect_spp(2.0f, 5.0f, 2.8f, 0.4f, 0.01f, &c), 9, aaf_indirect_spp_cap(&c));
    for (int i = 0; i < N; ++i) {
        CHECK_NEAR(beta[i], 1.0 / 30.0, 1e-6);
        CHECK(spp[i] == want_spp);
    }
    /* a reflector farther than the clamp: the clamp changes nothing */
    for (int i = 0; i < N; ++i) zmin[i] = 3.0f;
    CHECK(aaf_indirect_params_image(&st, &c, &ic, 100.0f, beta, spp) == N);
    CHECK_NEAR(beta[3], aaf_indirect_beta_world(3.0f, 2.8f, 0.01f, &c), 1e-6);
}

/* Defocus image maps: pixel 0 saw a surface behind the focal plane (slopes 4..10 px), pixel 1
 * only escaped rays (the background's slope, 20 px, for both ends). Over a lit background
 * the escaped pixel is sized like any other: beta = (1/(k mu)) sigma_u 20 = 10/6 px and
 * n = (mu Omega_u/20 + alpha)^2 (Omega_u + 20 mu Omega_u/20)^2 = 1.2^2 6^2 = 51.84 -> 52 at mu = 2.
 * Over a black background it keeps its pass-1 samples and its own value: width 0, no gather
 * (a width pulled a bright out-of-focus emitter's light over the black around it). */
static void test_defocus_image_black_background(void)
{
    float smin[2] = {4.0f, 20.0f}, smax[2] = {10.0f, 20.0f}, beta[2];
    unsigned char hit[2] = {1, 0};
    int spp[2];
    AafPixelStats st = {0};
    st.width = 2;
    st.height = 1;
    st.hit = hit;
    st.coc_min_px = smin;
    st.coc_max_px = smax;
    AafDefocusConfig c = aaf_defocus_config_default();
    CHECK(!c.black_background); /* unknown background: assume it is lit */
    c.mu = 2.0f;
    AafImageConfig ic = {2, 16, 200.0f, 0.0f, 0};
    CHECK(aaf_defocus_params_image(&st, &c, &ic, beta, spp) == 2);
    CHECK(spp[0] == 200); /* 576, capped */
    CHECK(spp[1] == 52);
    CHECK_NEAR(beta[1], 10.0 / 6.0, 1e-6);
    c.black_background = true;
    CHECK(aaf_defocus_params_image(&st, &c, &ic, beta, spp) == 1);
    CHECK(spp[0] == 200);
    CHECK(spp[1] == 16);
    CHECK(beta[1] == 0.0f);
    CHECK(beta[0] > 0.0f); /* the surface pixel is filtered as before */
}

int main(void)
{
    test_indirect_cap_grows_under_the_filter();
    test_far_samples_grow_under_the_filter();
    test_shadow_hand_values();
    test_shadow_degenerate();
    test_consistency_in_mu();
    test_indirect_hand_values();
    test_defocus_hand_values();
    test_clamp_spp();
    test_shadow_image_borrowing();
    test_indirect_image_contact();
    test_defocus_image_black_background();
    CHECK_DONE();
}
