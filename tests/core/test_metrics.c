/* Image metrics of issue 5 on tiny synthetic images whose values are worked out by hand
 * (in the comments) or by an independent direct evaluation written here. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "core/image_metrics.h"

static const double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03; /* (K L)^2 with L = 1 */

/* ---- relMSE, MSE, RMSE, PSNR on a 2x1 image ---------------------------------------
 *   REF  p0 = (0,   0.5, 1  )   p1 = (0.1, 0.2, 2  )
 *   TEST p0 = (0.1, 0.5, 0.5)   p1 = (0.1, 0.4, 3  )
 *   t - r:    (0.1, 0,  -0.5)         (0,   0.2, 1  )
 * relMSE terms (t-r)^2 / (r^2 + 0.01):
 *   0.01/0.01 = 1,  0,  0.25/1.01 = 0.247524752475,  0,  0.04/0.05 = 0.8,  1/4.01 = 0.249376558603
 *   sum 2.296901311079, /6 -> relMSE = 0.382816885180
 * MSE: (0.01 + 0 + 0.25 + 0 + 0.04 + 1) / 6 = 1.3/6 = 0.216666666667; RMSE = 0.465474668125
 * PSNR: clamped to [0,1]: REF (0,.5,1)(.1,.2,1), TEST (.1,.5,.5)(.1,.4,1); differences
 *   0.1, 0, -0.5, 0, 0.2, 0 -> MSE' = (0.01 + 0.25 + 0.04)/6 = 0.05 -> PSNR = 10 log10(20)
 *   = 13.0102999566 dB. */
static void test_pointwise_metrics(void)
{
    const float ref[6] = {0.0f, 0.5f, 1.0f, 0.1f, 0.2f, 2.0f};
    const float test[6] = {0.1f, 0.5f, 0.5f, 0.1f, 0.4f, 3.0f};
    /* Tolerances cover 0.1 and 0.2 not being exact in float32 (error ~1e-8 relative). */
    CHECK_NEAR(metric_relmse(ref, test, 2, 1), 0.382816885180, 1e-7);
    CHECK_NEAR(metric_mse(ref, test, 2, 1), 0.216666666667, 1e-7);
    CHECK_NEAR(metric_psnr(ref, test, 2, 1), 13.0102999566, 1e-6);
    CHECK(metric_nonfinite(test, 2, 1) == 0);
    ImageMetrics m;
    CHECK(image_metrics_compute(ref, test, 2, 1, &m));
    CHECK_NEAR(m.relmse, 0.382816885180, 1e-7);
    CHECK_NEAR(m.mse, 0.216666666667, 1e-7);
    CHECK_NEAR(m.rmse, 0.465474668125, 1e-7);
    CHECK_NEAR(m.psnr, 13.0102999566, 1e-6);
    CHECK(m.nonfinite == 0);
    /* The images differ, so SSIM is below 1; it is finite and at least -1. */
    CHECK(m.ssim < 1.0 && m.ssim >= -1.0);

    /* relMSE weights errors by the reference: the same absolute error of 0.1 costs
     * 0.01/(0+0.01) = 1 on black but 0.01/(100+0.01) = 9.999e-5 on a value of 10. */
    const float dark[3] = {0, 0, 0}, dark_t[3] = {0.1f, 0.1f, 0.1f};
    const float bright[3] = {10, 10, 10}, bright_t[3] = {10.1f, 10.1f, 10.1f};
    CHECK_NEAR(metric_relmse(dark, dark_t, 1, 1), 1.0, 1e-6);
    CHECK_NEAR(metric_relmse(bright, bright_t, 1, 1), 0.01 / 100.01, 1e-8);
}

/* PSNR of identical images: MSE' = 0, capped at 100 dB rather than infinity. PSNR of a
 * uniform difference d: 10 log10(1/d^2) = -20 log10(d); d = 0.5 -> 6.0206 dB. */
static void test_psnr_cases(void)
{
    float a[12], b[12];
    for (int i = 0; i < 12; ++i) a[i] = b[i] = (float)i / 11.0f;
    CHECK(metric_psnr(a, b, 2, 2) == 100.0);
    for (int i = 0; i < 12; ++i) {
        a[i] = 0.25f;
        b[i] = 0.75f;
    }
    CHECK_NEAR(metric_psnr(a, b, 2, 2), -20.0 * log10(0.5), 1e-9);
    /* Values beyond [0,1] clamp first: 3 vs 7 is no error at all for PSNR. */
    for (int i = 0; i < 12; ++i) {
        a[i] = 3.0f;
        b[i] = 7.0f;
    }
    CHECK(metric_psnr(a, b, 2, 2) == 100.0);
    CHECK_NEAR(metric_mse(a, b, 2, 2), 16.0, 0.0);
}

/* Non-finite TEST values: counted per pixel, and 0 in every other metric.
 *   REF all 0.5 (3 pixels). TEST p0 = (NaN, 0.5, 0.5), p1 = (0.5, 0.5, 0.5), p2 = (+Inf, -Inf, 0.5)
 *   nonfinite = 2 pixels. Values become 0: differences -0.5 at three places of nine:
 *   MSE = 3 * 0.25 / 9 = 1/12; relMSE = 3 * 0.25/(0.25 + 0.01) / 9 = 0.320512820513. */
static void test_nonfinite(void)
{
    const float ref[9] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
    const float test[9] = {NAN, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, INFINITY, -INFINITY, 0.5f};
    ImageMetrics m;
    CHECK(image_metrics_compute(ref, test, 3, 1, &m));
    CHECK(m.nonfinite == 2);
    CHECK_NEAR(m.mse, 1.0 / 12.0, 1e-12);
    CHECK_NEAR(m.relmse, 0.75 / 0.26 / 9.0, 1e-9);
    CHECK(isfinite(m.psnr) && isfinite(m.ssim) && isfinite(m.rmse));
}

/* sRGB encoding, IEC 61966-2-1, computed here in double. */
static double srgb(double x)
{
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

static void test_srgb(void)
{
    CHECK_NEAR(srgb_encode(0.18f), 0.461356129500, 1e-6);
    CHECK_NEAR(srgb_encode(1.0f), 1.0, 1e-6);
    CHECK(srgb_encode(0.0f) == 0.0f);
    CHECK_NEAR(srgb_encode(0.001f), 0.01292, 1e-8);
    for (int i = 0; i <= 100; ++i) {
        float x = (float)i / 100.0f;
        CHECK_NEAR(srgb_encode(x), srgb(x), 1e-6);
        CHECK_NEAR(srgb_decode(srgb_encode(x)), x, 1e-6);
    }
}

/* SSIM of two constant images: every window has mean a (resp. b) and no variance, so
 * SSIM = (2ab + C1)/(a^2 + b^2 + C1) * (0 + C2)/(0 + C2), whatever the window. */
static double ssim_constant(double a, double b)
{
    return (2.0 * a * b + C1) / (a * a + b * b + C1);
}

static void fill(float *rgb, int n, float r, float g, float b)
{
    for (int i = 0; i < n; ++i) {
        rgb[3 * i] = r;
        rgb[3 * i + 1] = g;
        rgb[3 * i + 2] = b;
    }
}

static void test_ssim_constant_images(void)
{
    enum { W = 16, H = 13 };
    static float a[W * H * 3], b[W * H * 3];
    /* Grey 0.18 vs grey 0.5 (linear): luma of encoded grey g is srgb(g) (weights sum to 1). */
    fill(a, W * H, 0.18f, 0.18f, 0.18f);
    fill(b, W * H, 0.5f, 0.5f, 0.5f);
    double ya = srgb(0.18), yb = srgb(0.5);
    CHECK_NEAR(metric_ssim(a, b, W, H), ssim_constant(ya, yb), 1e-6);
    /* Smaller than the window (5x3: 5x3 windows, one position): same closed form. */
    CHECK_NEAR(metric_ssim(a, b, 5, 3), ssim_constant(ya, yb), 1e-6);
    /* Pure red vs pure green: encoded (1,0,0) has luma 0.2126, (0,1,0) has 0.7152.
     * (2*0.2126*0.7152 + 1e-4) / (0.2126^2 + 0.7152^2 + 1e-4) = 0.30420... / 0.55676... */
    fill(a, W * H, 1.0f, 0.0f, 0.0f);
    fill(b, W * H, 0.0f, 1.0f, 0.0f);
    CHECK_NEAR(metric_ssim(a, b, W, H), (2 * 0.2126 * 0.7152 + C1) / (0.2126 * 0.2126 + 0.7152 * 0.7152 + C1), 1e-6);
    /* Clamping happens before encoding: 5.0 is white (luma 1), -2 is black (luma 0):
     * (0 + C1)/(1 + 0 + C1) = 1e-4/1.0001. */
    fill(a, W * H, 5.0f, 5.0f, 5.0f);
    fill(b, W * H, -2.0f, -2.0f, -2.0f);
    CHECK_NEAR(metric_ssim(a, b, W, H), C1 / (1.0 + C1), 1e-9);
    /* Identical images: exactly 1 (each window: (2m^2+C1)(2v+C2) / ((2m^2+C1)(2v+C2))). */
    for (int i = 0; i < W * H * 3; ++i) a[i] = b[i] = (float)((i * 7919) % 1000) / 999.0f;
    CHECK_NEAR(metric_ssim(a, b, W, H), 1.0, 1e-12);
}

/* The 1D Gaussian taps of the window, normalised (independent of the implementation). */
static void taps(double g[11])
{
    double s = 0.0;
    for (int i = -5; i <= 5; ++i) s += g[i + 5] = exp(-(double)(i * i) / (2.0 * 1.5 * 1.5));
    for (int i = 0; i < 11; ++i) g[i] /= s;
}

/* One window, one odd pixel. 11x11 luma plane, REF constant 0.5, TEST equal except the
 * centre pixel 0.5 + d. With g0 the centre weight of the 2D window (g[5]^2):
 *   mu_x = 0.5, var_x = 0;  mu_y = 0.5 + g0 d, var_y = g0 d^2 - (g0 d)^2 = g0 (1 - g0) d^2,
 *   cov = E[xy] - mu_x mu_y = 0.5 mu_y - 0.5 mu_y = 0
 *   SSIM = (2 * 0.5 * mu_y + C1) / (0.25 + mu_y^2 + C1) * C2 / (var_y + C2). */
static void test_ssim_single_window(void)
{
    double g[11];
    taps(g);
    double g0 = g[5] * g[5], d = 0.4;
    float ref[121], test[121];
    for (int i = 0; i < 121; ++i) ref[i] = test[i] = 0.5f;
    test[60] = (float)(0.5 + d);
    double mu_y = 0.5 + g0 * d, var_y = g0 * (1 - g0) * d * d;
    double expect = (mu_y + C1) / (0.25 + mu_y * mu_y + C1) * C2 / (var_y + C2);
    CHECK_NEAR(metric_ssim_plane(ref, test, 11, 11), expect, 1e-7);
    /* With g0 = (1/sum)^2 ~ 0.0707 this is far from 1: one pixel off by 0.4 matters. */
    CHECK(expect < 0.5);
}

/* Inverted checkerboard: REF luma 1 where x+y is even, 0 elsewhere; TEST = 1 - REF.
 * Let w be the window weight on REF's white cells. The 2D window is the outer product of
 * the taps; split them into even offsets (sum Ge) and odd offsets (sum Go = 1 - Ge). A
 * window centred on a white cell sees white at offsets (i,j) with i+j even, i.e. both
 * even or both odd: w = Ge^2 + Go^2; centred on black, w' = 2 Ge Go = 1 - w.
 *   mu_x = w, mu_y = 1 - w, var_x = var_y = w (1 - w), cov = 0 - w (1 - w)
 *   SSIM = (2 w (1-w) + C1)/(w^2 + (1-w)^2 + C1) * (C2 - 2 w (1-w))/(C2 + 2 w (1-w)),
 * symmetric in w <-> 1-w, so every window (and the mean) has this value. */
static void test_ssim_checkerboard(void)
{
    double g[11], ge = 0.0;
    taps(g);
    for (int i = -5; i <= 5; ++i)
        if (i % 2 == 0) ge += g[i + 5];
    double go = 1.0 - ge, w = ge * ge + go * go, v = w * (1 - w);
    double expect = (2 * v + C1) / (w * w + (1 - w) * (1 - w) + C1) * (C2 - 2 * v) / (C2 + 2 * v);
    enum { W = 20, H = 18 };
    static float a[W * H * 3], b[W * H * 3];
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            float r = (x + y) % 2 == 0 ? 1.0f : 0.0f;
            fill(a + 3 * (y * W + x), 1, r, r, r);
            fill(b + 3 * (y * W + x), 1, 1 - r, 1 - r, 1 - r);
        }
    CHECK_NEAR(metric_ssim(a, b, W, H), expect, 1e-9);
    CHECK(expect < -0.9); /* anti-correlated structure: close to -1 */
}

/* Brute force: every 'valid' window evaluated directly with the 2D weights, against the
 * separable implementation, on random planes of a size that is not a multiple of anything. */
static void test_ssim_brute_force(void)
{
    enum { W = 23, H = 17 };
    static float a[W * H], b[W * H];
    unsigned s = 12345u;
    for (int i = 0; i < W * H; ++i) {
        s = s * 1664525u + 1013904223u;
        a[i] = (float)(s >> 8) / 16777216.0f;
        s = s * 1664525u + 1013904223u;
        b[i] = 0.7f * a[i] + 0.3f * (float)(s >> 8) / 16777216.0f;
    }
    double g[11];
    taps(g);
    double total = 0.0;
    int windows = 0;
    for (int y0 = 0; y0 + 11 <= H; ++y0)
        for (int x0 = 0; x0 + 11 <= W; ++x0) {
            double ma = 0, mb = 0, saa = 0, sbb = 0, sab = 0;
            for (int j = 0; j < 11; ++j)
                for (int i = 0; i < 11; ++i) {
                    double wt = g[i] * g[j], va = a[(y0 + j) * W + x0 + i], vb = b[(y0 + j) * W + x0 + i];
                    ma += wt * va;
                    mb += wt * vb;
                    saa += wt * va * va;
                    sbb += wt * vb * vb;
                    sab += wt * va * vb;
                }
            double va = saa - ma * ma, vb = sbb - mb * mb, cab = sab - ma * mb;
            total += (2 * ma * mb + C1) * (2 * cab + C2) / ((ma * ma + mb * mb + C1) * (va + vb + C2));
            ++windows;
        }
    CHECK(windows == (W - 10) * (H - 10));
    CHECK_NEAR(metric_ssim_plane(a, b, W, H), total / windows, 1e-10);
}

/* The relative-error map: e^2 averages to relMSE; the colour ramp's ends. Same 2x1 images
 * as test_pointwise_metrics: e0 = sqrt((1 + 0 + 0.247524752)/3) = 0.644987..., e1 =
 * sqrt((0 + 0.8 + 0.249376559)/3) = 0.591516... */
static void test_relerr_map(void)
{
    const float ref[6] = {0.0f, 0.5f, 1.0f, 0.1f, 0.2f, 2.0f};
    const float test[6] = {0.1f, 0.5f, 0.5f, 0.1f, 0.4f, 3.0f};
    float e[2], rgb[6];
    image_relerr_map(ref, test, 2, 1, e, rgb);
    CHECK_NEAR(e[0], sqrt((1.0 + 0.25 / 1.01) / 3.0), 1e-6);
    CHECK_NEAR(e[1], sqrt((0.8 + 1.0 / 4.01) / 3.0), 1e-6);
    CHECK_NEAR((e[0] * e[0] + e[1] * e[1]) / 2.0, metric_relmse(ref, test, 2, 1), 1e-6);
    float c[3];
    relerr_false_colour(0.0, c);
    CHECK(c[0] == 0 && c[1] == 0 && c[2] == 0);
    relerr_false_colour(1e-3, c);
    CHECK(c[0] == 0 && c[1] == 0 && c[2] == 0);
    relerr_false_colour(1.0, c);
    CHECK(c[0] == 1.0f && c[1] == 0.15f && c[2] == 0.05f);
    relerr_false_colour(1e6, c);
    CHECK(c[0] == 1.0f && c[1] == 0.15f && c[2] == 0.05f);
    relerr_false_colour(NAN, c);
    CHECK(isfinite(c[0]) && isfinite(c[1]) && isfinite(c[2]));
    /* A non-finite TEST pixel is magenta, with a finite e (the value counts as 0):
     * REF (0.5, 0.5, 0.5), TEST (NaN, 0.5, 0.5) -> e = sqrt(0.25/0.26/3). */
    const float ref_h[3] = {0.5f, 0.5f, 0.5f}, test_nan[3] = {NAN, 0.5f, 0.5f};
    image_relerr_map(ref_h, test_nan, 1, 1, e, rgb);
    CHECK(rgb[0] == 1.0f && rgb[1] == 0.0f && rgb[2] == 1.0f);
    CHECK_NEAR(e[0], sqrt(0.25 / 0.26 / 3.0), 1e-7);
    /* Every colour stays in [0,1] across the range. */
    int bad = 0;
    for (int k = -40; k <= 10; ++k) {
        relerr_false_colour(pow(10.0, k / 10.0), c);
        for (int i = 0; i < 3; ++i) bad += !(c[i] >= 0.0f && c[i] <= 1.0f);
    }
    CHECK(bad == 0);
}

/* relMSE split by a key: each pixel lands in the bin its key falls in (lower edge
 * inclusive), a non-finite key in the last bin, and the bins add up to relMSE. Pixels of
 * the 2x1 images above (terms e0^2 and e1^2) repeated in a 4x1 image with keys 0.5 (on an
 * edge: the upper bin), -3 (open first bin), NaN and 7 (open last bin). */
static void test_relmse_by_key(void)
{
    const float ref[12] = {0.0f, 0.5f, 1.0f, 0.1f, 0.2f, 2.0f, 0.0f, 0.5f, 1.0f, 0.1f, 0.2f, 2.0f};
    const float test[12] = {0.1f, 0.5f, 0.5f, 0.1f, 0.4f, 3.0f, 0.1f, 0.5f, 0.5f, 0.1f, 0.4f, 3.0f};
    const float key[4] = {0.5f, -3.0f, NAN, 7.0f};
    const double edges[2] = {0.5, 2.0};
    double t0 = (1.0 + 0.25 / 1.01) / 3.0, t1 = (0.8 + 1.0 / 4.01) / 3.0;
    ErrorBin bins[3];
    image_relmse_by_key(ref, test, key, 4, 1, edges, 2, bins);
    CHECK(bins[0].pixels == 1 && bins[1].pixels == 1 && bins[2].pixels == 2);
    CHECK_NEAR(bins[0].relmse_sum, t1, 1e-6);        /* key -3 */
    CHECK_NEAR(bins[1].relmse_sum, t0, 1e-6);        /* key 0.5 */
    CHECK_NEAR(bins[2].relmse_sum, t0 + t1, 1e-6);   /* NaN and 7 */
    CHECK_NEAR(bins[0].key_sum, -3.0, 0.0);
    CHECK_NEAR(bins[2].key_sum, 7.0, 0.0);           /* the NaN adds nothing */
    double total = bins[0].relmse_sum + bins[1].relmse_sum + bins[2].relmse_sum;
    CHECK_NEAR(total / 4.0, metric_relmse(ref, test, 4, 1), 1e-7);
}

int main(void)
{
    test_pointwise_metrics();
    test_psnr_cases();
    test_nonfinite();
    test_srgb();
    test_ssim_constant_images();
    test_ssim_single_window();
    test_ssim_checkerboard();
    test_ssim_brute_force();
    test_relerr_map();
    test_relmse_by_key();
    CHECK_DONE();
}
