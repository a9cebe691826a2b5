/* maaf_rate.h: the Lagrange allocation of samples in frames with defocus (docs/algorithms.md
 * 9.14). Oracles: the effective pixel count of a Gaussian against the brute-force sum of its
 * squared weights on the pixel grid; the allocation against random perturbations of it (none
 * may lower sum v / (n A) at the same total) and against the closed-form optimum; the variance
 * estimate against samples of known variance, and its window and normalisation by hand. */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "recon/maaf/maaf_rate.h"

/* 1 / sum of the squared weights of a normalised Gaussian of std s px sampled at the pixel
 * centres: the number of pixels it averages. */
static double brute_area(double s)
{
    double sum = 0.0, sum2 = 0.0;
    int r = (int)ceil(8.0 * s);
    for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x) {
            double w = exp(-(x * x + y * y) / (2.0 * s * s));
            sum += w;
            sum2 += w * w;
        }
    return sum * sum / sum2;
}

static unsigned rng_state = 12345u;
static double uniform01(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (rng_state >> 8) / 16777216.0;
}

/* sum_i v_i / (n_i A_i): the frame's variance (times the pixel count) for counts n */
static double objective(const double *v, const double *a, const double *n, int count)
{
    double e = 0.0;
    for (int i = 0; i < count; ++i) e += v[i] / (n[i] * a[i]);
    return e;
}

static void test_area(void)
{
    for (double s = 1.0; s <= 4.0; s *= 2.0)
        CHECK_NEAR(maaf_rate_area_px((float)s, 0.0f) / brute_area(s), 1.0, 0.01);
    /* the lens blurs the shading filter's output: stds in quadrature */
    CHECK_NEAR(maaf_rate_area_px(0.6f, 1.7f), maaf_rate_area_px(sqrtf(0.36f + 2.89f), 0.0f), 1e-3);
    /* a pixel passed through averages itself only */
    CHECK_NEAR(maaf_rate_area_px(0.0f, 0.0f), 1.0, 0.0);
    CHECK_NEAR(maaf_rate_area_px(0.1f, 0.0f), 1.0, 0.0);
}

/* Counts proportional to maaf_rate_factor minimise sum v / (n A) for their total: the value
 * is the closed form (sum sqrt(v / A))^2 / N, and every perturbation that keeps the total
 * raises it; uniform counts and the earlier rule (n ~ 1 / std^2) are worse. */
static void test_allocation(void)
{
    enum { P = 64 };
    double v[P], a[P], std[P], n[P], m[P];
    double vbar = 0.0;
    for (int i = 0; i < P; ++i) {
        v[i] = 0.01 + 4.0 * uniform01() * uniform01();    /* relative variance of one sample */
        std[i] = uniform01() < 0.2 ? 0.0 : 0.3 + 3.0 * uniform01();
        a[i] = maaf_rate_area_px((float)std[i], 0.0f);
        vbar += v[i] / P;
    }
    const double total = 16.0 * P;
    double fsum = 0.0, closed = 0.0;
    for (int i = 0; i < P; ++i) {
        n[i] = maaf_rate_factor((float)(v[i] / vbar), (float)a[i], 50.0f);
        fsum += n[i];
        closed += sqrt(v[i] / a[i]);
    }
    for (int i = 0; i < P; ++i) n[i] *= total / fsum;
    double best = objective(v, a, n, P);
    CHECK_NEAR(best / (closed * closed / total), 1.0, 1e-5);
    int lower = 0;
    for (int t = 0; t < 2000; ++t) {
        /* move a random share of one pixel's samples to another */
        int i = (int)(uniform01() * P), j = (int)(uniform01() * P);
        double d = n[i] * 0.5 * uniform01();
        for (int k = 0; k < P; ++k) m[k] = n[k];
        m[i] -= d;
        m[j] += d;
        if (objective(v, a, m, P) < best * (1.0 - 1e-12)) ++lower;
    }
    CHECK(lower == 0);
    double uniform = 0.0, old = 0.0, osum = 0.0;
    for (int i = 0; i < P; ++i) {
        m[i] = total / P;
        double f = 2.0 / fmax(std[i], 0.5);
        osum += f * f;
    }
    uniform = objective(v, a, m, P);
    for (int i = 0; i < P; ++i) {
        double f = 2.0 / fmax(std[i], 0.5);
        m[i] = f * f * total / osum;
    }
    old = objective(v, a, m, P);
    CHECK(best < 0.9 * uniform);
    CHECK(best < 0.9 * old);
    printf("allocation: sum v/(nA) %.4g, uniform %.4g, n ~ 1/std^2 %.4g\n", best, uniform, old);
}

/* The variance: by hand on a 5 x 1 frame (window and normalisation), then against samples of
 * known variance. */
static void test_rel_var(void)
{
    float mom[5 * 4] = {0}, rv[5];
    maaf_rate_add(mom, 1.0f);
    maaf_rate_add(mom, 3.0f);
    maaf_rate_add(mom, NAN); /* left out */
    for (int i = 1; i < 5; ++i) maaf_rate_add(mom + 4 * i, 2.0f), maaf_rate_add(mom + 4 * i, 2.0f);
    CHECK_NEAR(mom[0], 2.0, 0.0);
    CHECK(maaf_rate_rel_var(mom, 5, 1, rv));
    /* pixel 0: unbiased variance 2, relative 2 / (4 + 0.01); its window has 2 pixels, pixel
     * 1's 3, the others see only constant pixels */
    double v0 = 2.0 / 4.01, w0 = v0 / 2.0, w1 = v0 / 3.0, mean = (w0 + w1) / 5.0;
    CHECK_NEAR(rv[0], w0 / mean, 1e-5);
    CHECK_NEAR(rv[1], w1 / mean, 1e-5);
    CHECK_NEAR(rv[2], 0.0, 0.0);
    CHECK_NEAR(rv[4], 0.0, 0.0);
    /* two 3 x 3 blocks of uniform samples on [0, 2c] (variance c^2 / 3, mean c), c = 0.5 and
     * 0.1, apart in a frame of constant pixels: the window at each block's centre holds that
     * block alone, and the ratio of the two is that of the relative variances
     * c^2 / 3 / (c^2 + 0.01) (the normalisation cancels), 1.92 (plain variances: 25) */
    enum { W = 11, H = 5, N = 4000 };
    float m2[W * H * 4] = {0}, r2[W * H];
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int k = 0; k < N; ++k) {
                bool in_y = y >= 1 && y <= 3;
                double c = in_y && x >= 1 && x <= 3 ? 0.5 : in_y && x >= 7 && x <= 9 ? 0.1 : -1.0;
                maaf_rate_add(m2 + 4 * (y * W + x), (float)(c > 0.0 ? 2.0 * c * uniform01() : 0.3));
            }
    CHECK(maaf_rate_rel_var(m2, W, H, r2));
    double va = 0.25 / 3.0 / 0.26, vb = 0.01 / 3.0 / 0.02;
    CHECK_NEAR(r2[2 * W + 2] / r2[2 * W + 8], va / vb, 0.03 * va / vb);
    CHECK_NEAR(r2[2 * W + 5], 0.0, 0.0); /* between the blocks: constant pixels only */
}

int main(void)
{
    test_area();
    test_allocation();
    test_rel_var();
    CHECK_DONE();
}
