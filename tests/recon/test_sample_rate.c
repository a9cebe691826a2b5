/* recon/sample_rate.h: the Lagrange allocation of samples (docs/algorithms.md 9.14, MAAF's
 * frames with defocus; section 10, FSF under a budget). Oracles: the effective pixel count of
 * a Gaussian (isotropic and not) against the brute-force sum of its squared weights on the
 * pixel grid; the allocation against random perturbations of it (none may lower
 * sum v / (n A) at the same total, within the bounds when it has them) and against the
 * closed-form optimum; the variance estimate against samples of known variance, and its
 * window and normalisation by hand. */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "recon/sample_rate.h"

/* 1 / sum of the squared weights of a normalised Gaussian of stds sa, sb px along x and y
 * sampled at the pixel centres: the number of pixels it averages. */
static double brute_area2(double sa, double sb)
{
    double sum = 0.0, sum2 = 0.0;
    int r = (int)ceil(8.0 * fmax(sa, sb));
    for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x) {
            double w = exp(-(x * x) / (2.0 * sa * sa) - (y * y) / (2.0 * sb * sb));
            sum += w;
            sum2 += w * w;
        }
    return sum * sum / sum2;
}

static double brute_area(double s)
{
    return brute_area2(s, s);
}

/* isotropic Gaussian of std s px */
static float area_iso(float s)
{
    return sample_rate_area_px(s * s, s * s);
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
    for (double s = 1.0; s <= 4.0; s *= 2.0) CHECK_NEAR(area_iso((float)s) / brute_area(s), 1.0, 0.01);
    /* two axes of different widths (FSF's filter: the light's two axes) */
    CHECK_NEAR(sample_rate_area_px(1.0f, 9.0f) / brute_area2(1.0, 3.0), 1.0, 0.01);
    CHECK_NEAR(sample_rate_area_px(16.0f, 2.25f) / brute_area2(4.0, 1.5), 1.0, 0.01);
    /* a blur after another: variances add, so the area is that of the composed Gaussian */
    CHECK_NEAR(area_iso(sqrtf(0.36f + 2.89f)) / brute_area(sqrt(0.36 + 2.89)), 1.0, 0.01);
    /* a pixel passed through averages itself only */
    CHECK_NEAR(sample_rate_area_px(0.0f, 0.0f), 1.0, 0.0);
    CHECK_NEAR(sample_rate_area_px(0.0f, 25.0f), 1.0, 0.0);
    CHECK_NEAR(area_iso(0.1f), 1.0, 0.0);
}

/* Counts proportional to sample_rate_factor minimise sum v / (n A) for their total: the value
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
        a[i] = area_iso((float)std[i]);
        vbar += v[i] / P;
    }
    const double total = 16.0 * P;
    double fsum = 0.0, closed = 0.0;
    for (int i = 0; i < P; ++i) {
        n[i] = sample_rate_factor((float)(v[i] / vbar), (float)a[i], 50.0f);
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
    sample_rate_add(mom, 1.0f);
    sample_rate_add(mom, 3.0f);
    sample_rate_add(mom, NAN); /* left out */
    for (int i = 1; i < 5; ++i) sample_rate_add(mom + 4 * i, 2.0f), sample_rate_add(mom + 4 * i, 2.0f);
    CHECK_NEAR(mom[0], 2.0, 0.0);
    CHECK(sample_rate_rel_var(mom, 5, 1, rv));
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
                sample_rate_add(m2 + 4 * (y * W + x), (float)(c > 0.0 ? 2.0 * c * uniform01() : 0.3));
            }
    CHECK(sample_rate_rel_var(m2, W, H, r2));
    double va = 0.25 / 3.0 / 0.26, vb = 0.01 / 3.0 / 0.02;
    CHECK_NEAR(r2[2 * W + 2] / r2[2 * W + 8], va / vb, 0.03 * va / vb);
    CHECK_NEAR(r2[2 * W + 5], 0.0, 0.0); /* between the blocks: constant pixels only */
}

/* sample_rate_counts: the bounded optimum. The counts spend the total, stay within
 * [floor, cap], follow lambda sqrt(v / A) between the bounds (the KKT conditions), and no
 * transfer of samples between two pixels that keeps the bounds lowers sum v / (n A). With
 * nothing to follow (all factors 0) the total is spread evenly. */
static void test_counts(void)
{
    enum { P = 200 };
    float f[P], n[P];
    double v[P], a[P], m[P], nd[P];
    for (int i = 0; i < P; ++i) {
        v[i] = uniform01() < 0.3 ? 0.0 : 0.01 + 4.0 * uniform01() * uniform01();
        a[i] = area_iso(uniform01() < 0.2 ? 0.0f : (float)(0.3 + 3.0 * uniform01()));
        f[i] = sample_rate_factor((float)v[i], (float)a[i], 1.0f);
    }
    const float lo = 4.0f, hi = 4.0f * 28.0f;
    sample_rate_counts(f, P, lo, hi, 16.0, n);
    double sum = 0.0, lambda = -1.0;
    int bad = 0, inside = 0;
    for (int i = 0; i < P; ++i) {
        sum += n[i];
        bad += n[i] < lo - 1e-4f || n[i] > hi + 1e-3f;
        if (n[i] > lo + 1e-3f && n[i] < hi - 1e-3f) {
            double l = n[i] / f[i];
            if (lambda < 0.0) lambda = l;
            bad += fabs(l / lambda - 1.0) > 1e-4;
            ++inside;
        } else if (n[i] <= lo + 1e-3f && lambda > 0.0) {
            bad += f[i] * lambda > lo * (1.0 + 1e-4); /* at the floor only if it asks for less */
        }
    }
    CHECK(bad == 0);
    CHECK(inside > P / 4);
    CHECK_NEAR(sum / (16.0 * P), 1.0, 1e-5);
    /* v / (n A) with v 0 has no gradient: use the factor's own objective sum f^2 / n */
    for (int i = 0; i < P; ++i) nd[i] = n[i], v[i] = (double)f[i] * f[i], a[i] = 1.0;
    double best = objective(v, a, nd, P);
    int lower = 0;
    for (int t = 0; t < 4000; ++t) {
        int i = (int)(uniform01() * P), j = (int)(uniform01() * P);
        double d = fmin(nd[i] - lo, hi - nd[j]) * uniform01();
        if (i == j || !(d > 0.0)) continue;
        for (int k = 0; k < P; ++k) m[k] = nd[k];
        m[i] -= d;
        m[j] += d;
        if (objective(v, a, m, P) < best * (1.0 - 1e-6)) ++lower;
    }
    CHECK(lower == 0);
    /* nothing to follow: evenly */
    for (int i = 0; i < P; ++i) f[i] = 0.0f;
    sample_rate_counts(f, P, lo, hi, 16.0, n);
    bad = 0;
    for (int i = 0; i < P; ++i) bad += fabsf(n[i] - 16.0f) > 1e-4f;
    CHECK(bad == 0);
}

int main(void)
{
    test_area();
    test_allocation();
    test_counts();
    test_rel_var();
    CHECK_DONE();
}
