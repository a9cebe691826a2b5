/* LR's per-partition filter (src/recon/lr/lr_filter.c) against closed forms derived
 * independently in docs/algorithms.md 8.3-8.4: the reductions (no motion: VMCS13's sheared
 * defocus filter; pinhole: a sheared motion filter; neither: the pixel filter), the x-only
 * rewrite of eqs. 10-11 against the warp of eq. 8, and the blur the filter gives a layer. */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "recon/lr/lr_filter.h"

/* The filter's parameters are floats computed in double: relative 1e-5 is float rounding of
 * a few operations (2^-24 ~ 6e-8 each) with margin. */
#define REL 1e-5

static double rel(double a, double b) { return fabs(a - b) / fmax(1e-30, fmax(fabs(a), fabs(b))); }

/* 2D sheared filter of a wedge of slopes [a, b] (same sign) clipped at the band 1/sigma of the
 * integrated dimension, written from the Gaussian's covariance (docs 8.3): sigma_x is sigma
 * times the RMS-harmonic slope, the shear is minus the ratio of the mean of 1/s to the mean of
 * 1/s^2. */
static void sheared_2d(double a, double b, double sigma, double *sigma_x, double *shear, double *sigma_e)
{
    double m1 = 0.5 * (1 / a + 1 / b), m2 = 0.5 * (1 / (a * a) + 1 / (b * b));
    *sigma_x = sigma / sqrt(m2);
    *shear = -m1 / m2;
    *sigma_e = sigma * 2 * sqrt(m2) / fabs(1 / a - 1 / b);
}

static void test_no_motion_is_defocus(const LrFilterConfig *cfg, double c0, double c1)
{
    c0 = (float)c0, c1 = (float)c1; /* the oracle sees the slopes the filter sees */
    LrSlopes s = {(float)c0, (float)c1, 0.0f, 0.0f};
    LrFilter f = lr_filter_make(&s, cfg);
    double sx, sh, su;
    sheared_2d(c0, c1, cfg->sigma_lens, &sx, &sh, &su);
    CHECK(f.clip_x == LR_CLIP_U && f.clip_y == LR_CLIP_U && !f.clamped);
    CHECK(rel(1 / f.inv_sigma_x_px, sx) < REL);
    CHECK(rel(f.eta_px, sh) < REL);
    CHECK(rel(1 / f.inv_sigma_u, su) < REL);
    /* exactly no time dependence: no shear by t, flat weight over t */
    CHECK(f.xi_px == 0.0f && f.inv_sigma_t == 0.0f);
    /* and the yv filter is the same 2D filter (VMCS13) */
    CHECK(f.inv_sigma_y_px == f.inv_sigma_x_px && f.rho_px == f.eta_px && f.inv_sigma_v == f.inv_sigma_u);
}

static void test_pinhole_is_motion(const LrFilterConfig *cfg, double d0, double d1)
{
    d0 = (float)d0, d1 = (float)d1;
    LrSlopes s = {0.0f, 0.0f, (float)d0, (float)d1};
    LrFilter f = lr_filter_make(&s, cfg);
    double sx, sh, st;
    sheared_2d(d0, d1, cfg->sigma_shutter, &sx, &sh, &st);
    CHECK(f.clip_x == LR_CLIP_T && !f.clamped);
    CHECK(rel(1 / f.inv_sigma_x_px, sx) < REL);
    CHECK(rel(f.xi_px, sh) < REL);
    CHECK(rel(1 / f.inv_sigma_t, st) < REL);
    CHECK(f.eta_px == 0.0f && f.inv_sigma_u == 0.0f);
    /* across the motion: only the pixel filter */
    CHECK(f.clip_y == LR_CLIP_X && rel(1 / f.inv_sigma_y_px, cfg->sigma_pixel_px) < REL);
    CHECK(f.rho_px == 0.0f && f.inv_sigma_v == 0.0f);
}

static void test_neither_is_pixel_filter(const LrFilterConfig *cfg)
{
    LrSlopes s = {0.0f, 0.0f, 0.0f, 0.0f};
    LrFilter f = lr_filter_make(&s, cfg);
    CHECK(f.clip_x == LR_CLIP_X && f.clip_y == LR_CLIP_X);
    CHECK(rel(1 / f.inv_sigma_x_px, cfg->sigma_pixel_px) < REL && rel(1 / f.inv_sigma_y_px, cfg->sigma_pixel_px) < REL);
    CHECK(f.eta_px == 0.0f && f.xi_px == 0.0f && f.rho_px == 0.0f);
    CHECK(f.inv_sigma_u == 0.0f && f.inv_sigma_t == 0.0f && f.inv_sigma_v == 0.0f);
}

/* Eqs. 10-11 and 13: the x-only primal product of Gaussians equals exp(-|S^T x|^2 / 2) of the
 * eq. 8 warp S (primal precision = Fourier covariance S S^T, angular frequencies). */
static int check_x_only(const LrFilterConfig *cfg, LrSlopes s, unsigned *seed)
{
    LrFilter f = lr_filter_make_paper(&s, cfg);
    double S[3][3];
    lr_filter_warp(&s, cfg, S);
    for (int k = 0; k < 20; ++k) {
        double x[3];
        for (int i = 0; i < 3; ++i) x[i] = (double)rand_r(seed) / RAND_MAX * 2 - 1;
        x[0] *= 6.0; /* px */
        double q = 0;
        for (int j = 0; j < 3; ++j) {
            double c = S[0][j] * x[0] + S[1][j] * x[1] + S[2][j] * x[2]; /* (S^T x)_j */
            q += c * c;
        }
        double w = lr_filter_weight_xut(&f, x[0], x[1], x[2]);
        /* compare exponents: relative float rounding of the parameters, absolute 1e-6 when
         * the exponent is near 0 */
        CHECK(fabs(-2 * log(w) - q) <= 1e-4 * q + 1e-6);
    }
    return f.clip_x;
}

static void test_x_only_rewrite(const LrFilterConfig *cfg)
{
    unsigned seed = 7;
    int seen[3] = {0, 0, 0};
    for (int n = 0; n < 300; ++n) {
        double r[4];
        for (int i = 0; i < 4; ++i) r[i] = (double)rand_r(&seed) / RAND_MAX;
        double c0 = (r[0] * 2 - 1) * 12, d0 = (r[1] * 2 - 1) * 25;
        LrSlopes s = {(float)c0, (float)(c0 + r[2] * 4), (float)d0, (float)(d0 + r[3] * 6)};
        seen[check_x_only(cfg, s, &seed)]++;
    }
    /* the random slopes exercise all three clipping cases */
    CHECK(seen[LR_CLIP_X] > 0 && seen[LR_CLIP_U] > 0 && seen[LR_CLIP_T] > 0);
}

/* The blur the filter leaves on a layer of slope c (dense samples over u, evaluated at u = 0):
 * variance sigma_x^2 + (c + eta)^2 sigma_u^2 (docs 8.3). At the central (harmonic) slope it
 * must be the Gaussian aperture's c^2 sigma_a^2, clamped or not (Appendix C keeps the shear);
 * at the wedge's edge the Gaussian's 1-sigma contour passes the corner: twice that. */
static double layer_blur_var(const LrFilter *f, double c)
{
    double sx = 1 / f->inv_sigma_x_px, su = 1 / f->inv_sigma_u;
    return sx * sx + (c + f->eta_px) * (c + f->eta_px) * su * su;
}

static void test_layer_blur(const LrFilterConfig *cfg)
{
    double sa2 = (double)cfg->sigma_lens * cfg->sigma_lens;
    double pairs[3][2] = {{4, 6}, {-9, -5}, {40, 44}}; /* the last is clamped */
    for (int i = 0; i < 3; ++i) {
        double a = pairs[i][0], b = pairs[i][1];
        LrSlopes s = {(float)a, (float)b, 0, 0};
        LrFilter f = lr_filter_make(&s, cfg);
        CHECK(f.clamped == (i == 2));
        if (f.clamped) CHECK(rel(1 / f.inv_sigma_x_px, cfg->sigma_clamp_px) < REL);
        double ch = 2 / (1 / a + 1 / b);
        CHECK(rel(layer_blur_var(&f, ch), ch * ch * sa2) < 1e-4);
        if (!f.clamped) CHECK(rel(layer_blur_var(&f, a), 2 * a * a * sa2) < 1e-4);
    }
}

/* The blur at slopes (c, d): v^T Sigma v with v = (1, c, d) and Sigma the primal filter's
 * covariance in x-only form; a flat dimension counts only if its coefficient is 0. */
static double blur_var(const LrFilter *f, double c, double d)
{
    double sx = 1 / f->inv_sigma_x_px, a = c + f->eta_px, b = d + f->xi_px, v = sx * sx;
    if (f->inv_sigma_u > 0) v += a * a / ((double)f->inv_sigma_u * f->inv_sigma_u);
    else if (fabs(a) > 1e-5) return INFINITY;
    if (f->inv_sigma_t > 0) v += b * b / ((double)f->inv_sigma_t * f->inv_sigma_t);
    else if (fabs(b) > 1e-5) return INFINITY;
    return v;
}

/* complete_bands (docs 8.3): at the layer's central slopes the filter gives both blurs, the
 * Gaussian aperture's c^2 sigma_a^2 and the Gaussian shutter's d^2 sigma_shutter^2, in every
 * case (the paper's case U alone gives only the first, case T only the second). Slopes kept
 * small enough that no clamp applies. */
static void test_both_blurs(const LrFilterConfig *cfg)
{
    double sa2 = (double)cfg->sigma_lens * cfg->sigma_lens, st2 = (double)cfg->sigma_shutter * cfg->sigma_shutter;
    struct { float c0, c1, d0, d1; LrClip clip; } cases[] = {
        {3, 3, 2, 2, LR_CLIP_U}, {3, 4, 1.5f, 2.5f, LR_CLIP_U}, {-5, -4, 0.5f, 0.7f, LR_CLIP_U},
        {0.5f, 0.5f, 6, 6, LR_CLIP_T}, {0.4f, 0.6f, 5, 7, LR_CLIP_T}, {0.05f, 0.1f, 0.2f, 0.3f, LR_CLIP_X},
    };
    for (unsigned i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        LrSlopes s = {cases[i].c0, cases[i].c1, cases[i].d0, cases[i].d1};
        LrFilter f = lr_filter_make(&s, cfg);
        CHECK(f.clip_x == cases[i].clip && !f.clamped);
        double c = s.c_min_px, d = s.d_min_px, c1 = s.c_max_px, d1 = s.d_max_px;
        /* central slopes: the harmonic mean in the clipping dimension, the mean in the other */
        double cc = f.clip_x == LR_CLIP_U ? 2 / (1 / c + 1 / c1) : 0.5 * (c + c1);
        double dc = f.clip_x == LR_CLIP_T ? 2 / (1 / d + 1 / d1) : 0.5 * (d + d1);
        double want = cc * cc * sa2 + dc * dc * st2;
        if (f.clip_x == LR_CLIP_X) want += (double)cfg->sigma_pixel_px * cfg->sigma_pixel_px;
        CHECK(rel(blur_var(&f, cc, dc), want) < 1e-4);
        if (!(rel(blur_var(&f, cc, dc), want) < 1e-4)) fprintf(stderr, "case %u: blur %g want %g\n", i, blur_var(&f, cc, dc), want);
    }
}

/* Finite output for degenerate and extreme input (no NaN reaches the kernels). */
static void test_finite(const LrFilterConfig *cfg)
{
    LrSlopes cases[] = {{0, 0, 0, 0}, {1e-30f, 1e-30f, 0, 0}, {-3, 3, -40, 40}, {1e6f, 1e6f, 1e6f, 1e6f}, {5, 5, 7, 7}};
    for (unsigned i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        LrFilter f = lr_filter_make(&cases[i], cfg);
        float v[] = {f.inv_sigma_x_px, f.eta_px, f.xi_px, f.inv_sigma_u, f.inv_sigma_t, f.inv_sigma_y_px, f.rho_px, f.inv_sigma_v};
        for (unsigned k = 0; k < sizeof v / sizeof v[0]; ++k) CHECK(isfinite(v[k]));
        CHECK(f.inv_sigma_x_px > 0 && f.inv_sigma_y_px > 0);
    }
}

/* The blur variance a flat-weight filter gives a layer at slopes (c, d): every sample keeps
 * its residual offset (c + eta) u + (d + xi) t over the renderer's uniform disk (per-axis
 * variance 1/4) and box shutter (1/12), then the screen Gaussian. */
static double flat_blur(double sigma, double shear_u, double shear_t, double c, double d)
{
    double a = c + shear_u, b = d + shear_t;
    return sigma * sigma + a * a / 4 + b * b / 12;
}

/* Flat lens and time weights (the default, docs 8.15 and 8.18): u, v, t weigh 1 everywhere,
 * the clipping case and clamp are the Gaussian design's, and at the layer's central slopes
 * (c0, d0) the blur is the renderer's own, c0^2/4 + d0^2/12 along the motion and c0^2/4
 * across, wherever the Gaussian design's screen parameters would give less (they counted
 * their own sample weights); a design that blurs more (a wide slope range) keeps its blur.
 * The screen sigma never exceeds the larger of the design's and the clamp, and the shears
 * only shrink (samples reproject less, never more). */
static void test_flat_weights(void)
{
    LrFilterConfig flat = lr_filter_config_default(), gauss = flat;
    CHECK(flat.flat_lens_time);
    gauss.flat_lens_time = false;
    LrSlopes cases[] = {{4, 6, 0, 0}, {0, 0, 5, 8}, {3, 4, 1.5f, 2.5f}, {40, 44, -20, -12}, {20, 21, 0, 0}, {2, 3, 0, 0},
                        {18, 19, 40, 50}, {-8, -6, 60, 90}, {-3, 3, 0, 0}};
    int raised = 0;
    for (unsigned i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        LrFilter a = lr_filter_make(&cases[i], &flat), b = lr_filter_make(&cases[i], &gauss);
        CHECK(a.inv_sigma_u == 0.0f && a.inv_sigma_v == 0.0f && a.inv_sigma_t == 0.0f);
        CHECK(b.inv_sigma_u > 0.0f || b.inv_sigma_t > 0.0f);
        CHECK(a.clip_x == b.clip_x && a.clip_y == b.clip_y && a.clamped == b.clamped);
        double c0 = 0.5 * (cases[i].c_min_px + cases[i].c_max_px), d0 = 0.5 * (cases[i].d_min_px + cases[i].d_max_px);
        double want_x = c0 * c0 / 4 + d0 * d0 / 12, want_y = c0 * c0 / 4;
        double design_x = flat_blur(1 / b.inv_sigma_x_px, b.eta_px, b.xi_px, c0, d0);
        double design_y = flat_blur(1 / b.inv_sigma_y_px, b.rho_px, 0, c0, 0);
        double got_x = flat_blur(1 / a.inv_sigma_x_px, a.eta_px, a.xi_px, c0, d0);
        double got_y = flat_blur(1 / a.inv_sigma_y_px, a.rho_px, 0, c0, 0);
        CHECK(rel(got_x, fmax(design_x, want_x)) < 1e-4);
        CHECK(rel(got_y, fmax(design_y, want_y)) < 1e-4);
        raised += design_x < want_x * 0.99;
        double clamp = flat.sigma_clamp_px * (1 + 1e-6);
        CHECK(1 / a.inv_sigma_x_px <= fmax(1 / b.inv_sigma_x_px, clamp) && 1 / a.inv_sigma_y_px <= fmax(1 / b.inv_sigma_y_px, clamp));
        CHECK(fabsf(a.eta_px) <= fabsf(b.eta_px) && fabsf(a.xi_px) <= fabsf(b.xi_px) && fabsf(a.rho_px) <= fabsf(b.rho_px));
        CHECK(a.eta_px * b.eta_px >= 0 && a.xi_px * b.xi_px >= 0 && a.rho_px * b.rho_px >= 0);
    }
    /* the clamped defocus layers (the hard bench's back wall, c = 20.5 px: the design gives a
     * std of 9.6 px with flat weights, the lens 10.25) and the moving ones need the raise */
    CHECK(raised >= 3);
}

int main(void)
{
    test_flat_weights();
    /* the closed forms below describe the Gaussian design itself (sample weights included) */
    LrFilterConfig cfg = lr_filter_config_default();
    cfg.flat_lens_time = false;
    test_no_motion_is_defocus(&cfg, 4, 6);
    test_no_motion_is_defocus(&cfg, -9, -5);
    test_no_motion_is_defocus(&cfg, 3, 3.001);
    test_pinhole_is_motion(&cfg, 5, 8);
    test_pinhole_is_motion(&cfg, -10, -6);
    test_neither_is_pixel_filter(&cfg);
    test_x_only_rewrite(&cfg);
    test_layer_blur(&cfg);
    test_both_blurs(&cfg);
    test_finite(&cfg);
    CHECK_DONE();
}
