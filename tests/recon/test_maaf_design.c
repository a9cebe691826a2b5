/* MAAF filter design (maaf_design.c) against hand values of eqs. 6-10, its primal forms
 * against each other and against the Fourier design, and the box coverage closed form against
 * the design's own boxes (docs/algorithms.md, "MAAF"). */
#include <math.h>

#include "check.h"
#include "recon/maaf/maaf_design.h"

static void test_hand_values(void)
{
    /* s in [1, 2], Omega_y_max 5, N = 3: five bands of height 2 (half height 1).
     * p = 0: |Omega_y| <= 1 reaches |Omega_x| <= 1/s_min = 1.
     * p = 1: Omega_y in [1, 3]: Omega_x from 1/2 (bottom, s_max) to 3/1 (top, s_min).
     * p = 2: Omega_y in [3, 5]: Omega_x from 3/2 to 5. */
    MaafDesign2D d;
    CHECK(maaf_design_2d(1.0f, 2.0f, 5.0f, 3, &d));
    CHECK(d.pairs == 3);
    CHECK_NEAR(d.c[0].cx, 0.0, 0.0);
    CHECK_NEAR(d.c[0].cy, 0.0, 0.0);
    CHECK_NEAR(d.c[0].sx, 1.0, 1e-6);
    CHECK_NEAR(d.c[0].sy, 1.0, 1e-6);
    CHECK_NEAR(d.c[0].weight, 1.0, 0.0);
    CHECK_NEAR(d.c[1].cx, 1.75, 1e-6);
    CHECK_NEAR(d.c[1].sx, 1.25, 1e-6);
    CHECK_NEAR(d.c[1].cy, 2.0, 1e-6);
    CHECK_NEAR(d.c[1].sy, 1.0, 1e-6);
    CHECK_NEAR(d.c[2].cx, 3.25, 1e-6);
    CHECK_NEAR(d.c[2].sx, 1.75, 1e-6);
    CHECK_NEAR(d.c[2].cy, 4.0, 1e-6);
    /* eq. 10: G(C_x; 5/1) G(C_y; 5) = exp(-(0.35^2 + 0.4^2)/2) for p = 1 */
    CHECK_NEAR(d.c[1].weight, exp(-0.5 * (0.35 * 0.35 + 0.4 * 0.4)), 1e-6);
    CHECK_NEAR(d.c[2].weight, exp(-0.5 * (0.65 * 0.65 + 0.8 * 0.8)), 1e-6);
    /* N = 1 is AAF's eq. 2: one Gaussian of widths (Omega_y_max / s_min, Omega_y_max) */
    CHECK(maaf_design_2d(1.0f, 2.0f, 5.0f, 1, &d));
    CHECK(d.pairs == 1);
    CHECK_NEAR(d.c[0].sx, 5.0, 1e-6);
    CHECK_NEAR(d.c[0].sy, 5.0, 1e-6);
    /* degenerate inputs: swapped and clamped, never NaN; no bandwidth: no design */
    CHECK(maaf_design_2d(2.0f, 1.0f, 5.0f, 9, &d));
    CHECK(d.pairs == MAAF_PAIRS_MAX && d.s_min == 1.0f && d.s_max == 2.0f);
    CHECK(maaf_design_2d(0.0f, NAN, 5.0f, 3, &d));
    for (int p = 0; p < d.pairs; ++p) CHECK(isfinite(d.c[p].cx) && isfinite(d.c[p].sx) && d.c[p].sx > 0.0f);
    CHECK(!maaf_design_2d(1.0f, 2.0f, 0.0f, 3, &d));
    CHECK(!maaf_design_2d(1.0f, 2.0f, INFINITY, 3, &d));
}

/* Eq. 13 is an identity: the separable cos*cos - sin*sin terms sum to eq. 12 everywhere. */
static void test_separable_equals_direct(void)
{
    const float slopes[][2] = {{0.5f, 0.8f}, {1.5f, 2.0f}, {0.7f, 2.2f}, {0.1f, 9.0f}};
    double worst = 0.0;
    for (int s = 0; s < 4; ++s)
        for (int n = 1; n <= MAAF_PAIRS_MAX; ++n) {
            MaafDesign2D d;
            CHECK(maaf_design_2d(slopes[s][0], slopes[s][1], 3.0f, n, &d));
            double peak = fabs(maaf_primal_2d_direct(&d, 0.0, 0.0));
            for (int i = -12; i <= 12; ++i)
                for (int k = -12; k <= 12; ++k) {
                    double x = 0.37 * i, y = 0.29 * k;
                    double e = fabs(maaf_primal_2d_separable(&d, x, y) - maaf_primal_2d_direct(&d, x, y));
                    if (e / peak > worst) worst = e / peak;
                }
        }
    CHECK(worst < 1e-12);
}

/* The primal kernel's Fourier transform, by a Riemann sum on a grid fine enough for its
 * highest frequency and wide enough for its widest Gaussian, is the Fourier design (eq. 9). */
static void test_dft_matches_design(void)
{
    MaafDesign2D d;
    CHECK(maaf_design_2d(1.0f, 2.0f, 5.0f, 3, &d));
    /* widest primal Gaussian: std 1/min(sigma) = 1; highest frequency about 5 + 4 * 1.75 = 12 */
    const double h = 0.08, extent = 9.0;
    int m = (int)(extent / h);
    static double w[2 * 113 + 1][2 * 113 + 1];
    for (int i = -m; i <= m; ++i)
        for (int k = -m; k <= m; ++k) w[i + m][k + m] = maaf_primal_2d_direct(&d, i * h, k * h);
    const double probes[][2] = {{0, 0},     {1.75, 2},  {-1.75, -2}, {3.25, 4},  {1, 1},    {2, 4},
                                {-3, 1},    {0.5, 3},   {4, 2},      {2.5, 5},   {-1, 0.5}, {6, 6}};
    double worst = 0.0;
    for (int q = 0; q < 12; ++q) {
        double ox = probes[q][0], oy = probes[q][1], re = 0.0;
        for (int i = -m; i <= m; ++i)
            for (int k = -m; k <= m; ++k) re += w[i + m][k + m] * cos(ox * i * h + oy * k * h);
        re *= h * h; /* w is even: the transform is real */
        double e = fabs(re - maaf_fourier_2d(&d, ox, oy));
        if (e > worst) worst = e;
    }
    CHECK(worst < 1e-6);
    /* the design covers the wedge's centre line and not the mirror quadrant: on Omega_y = 1.5
     * Omega_x the filter passes more than half, on Omega_y = -1.5 Omega_x (outside) it stops */
    CHECK(maaf_fourier_2d(&d, 2.0, 3.0) > 0.5);
    CHECK(maaf_fourier_2d(&d, 2.0, -3.0) < 0.05);
}

static void test_box_coverage(void)
{
    const double slopes[][2] = {{0.5, 0.8}, {1.5, 2.0}, {0.7, 2.2}, {0.2, 9.0}};
    for (int s = 0; s < 4; ++s) {
        double lo = slopes[s][0], hi = slopes[s][1];
        /* N = 1 is AAF: (1 - s_min/s_max)/4 (eq. 16) */
        CHECK_NEAR(maaf_box_coverage(lo, hi, 1), (1.0 - lo / hi) / 4.0, 1e-12);
        double prev = 0.0;
        for (int n = 1; n <= MAAF_PAIRS_MAX; ++n) {
            MaafDesign2D d;
            CHECK(maaf_design_2d((float)lo, (float)hi, 4.0f, n, &d));
            double from_boxes = maaf_wedge_area(d.s_min, d.s_max, 4.0) / maaf_box_area(&d);
            CHECK_NEAR(maaf_box_coverage(d.s_min, d.s_max, n), from_boxes, 1e-5);
            double c = maaf_box_coverage(lo, hi, n);
            CHECK(c > prev && c < 1.0);
            prev = c;
        }
        CHECK(maaf_box_coverage(lo, hi, 1000) > 0.99);
    }
}

/* Gaussian coverage (eq. 15: the filter's mass inside the wedge over its total mass) and
 * accuracy (eq. 14: one minus the RMS of W - 1 over the wedge), integrated on a grid. */
static void gaussian_metrics(double s_min, double s_max, int n, double *coverage, double *accuracy)
{
    MaafDesign2D d;
    maaf_design_2d((float)s_min, (float)s_max, 1.0f, n, &d);
    double xr = 4.0 / s_min, yr = 3.0, h = 0.01 * (1.0 / s_min < 1.0 ? 1.0 / s_min : 1.0);
    double in = 0.0, all = 0.0, err2 = 0.0, area = 0.0;
    for (double oy = -yr; oy <= yr; oy += h)
        for (double ox = -xr; ox <= xr; ox += h) {
            double w = fabs(maaf_fourier_2d(&d, ox, oy));
            bool inside = fabs(oy) <= 1.0 && ox * oy > 0.0 && fabs(oy) >= s_min * fabs(ox) &&
                          fabs(oy) <= s_max * fabs(ox);
            all += w;
            if (inside) {
                in += w;
                err2 += (w - 1.0) * (w - 1.0);
                area += 1.0;
            }
        }
    *coverage = in / all;
    *accuracy = 1.0 - sqrt(err2 / area);
}

/* The trend of the paper's Table 2 for its three representative wedges: Gaussian MAAF with 3,
 * 5 and 7 filters covers the wedge better than AAF (N = 1), and more filters do better. */
static void test_gaussian_trend(void)
{
    const double slopes[][2] = {{0.5, 0.8}, {1.5, 2.0}, {0.7, 2.2}};
    for (int s = 0; s < 3; ++s) {
        double cov[5], acc[5];
        for (int n = 1; n <= 4; ++n) gaussian_metrics(slopes[s][0], slopes[s][1], n, &cov[n], &acc[n]);
        printf("wedge [%.1f, %.1f]: coverage", slopes[s][0], slopes[s][1]);
        for (int n = 1; n <= 4; ++n) printf(" %d:%.3f", 2 * n - 1, cov[n]);
        printf("  accuracy");
        for (int n = 1; n <= 4; ++n) printf(" %d:%.3f", 2 * n - 1, acc[n]);
        printf("\n");
        for (int n = 2; n <= 4; ++n) CHECK(cov[n] > cov[n - 1]);
    }
}

int main(void)
{
    test_hand_values();
    test_separable_equals_direct();
    test_dft_matches_design();
    test_box_coverage();
    test_gaussian_trend();
    CHECK_DONE();
}
