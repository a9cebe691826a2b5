/* How the soft-shadow sums weight a light's samples (maaf_accumulate, docs/algorithms.md 9.20).
 *
 * 1. On a receiver the light reaches unoccluded, the central component's estimate is the
 *    plain mean of the samples' values over the light, whatever their variation across it:
 *    a grid of samples over a square light with f(y) = 1 + |y|^2 (brighter towards the
 *    corners, as a light's cosines and distances make it vary) must give exactly the grid's
 *    own mean. With the central band's integrated factor c_0(y) (the part of the sample's
 *    y-window on the light: about 1/2 at an edge) as the weight, the estimate is c_0's
 *    weighted mean instead, several percent low here (the old behaviour, printed and checked
 *    to differ, so the test can fail).
 * 2. The other components keep their y-dependent factors (the shear): one sample's sums of
 *    the component (p = 1, q = 0) equal c_1(y1) c_0(y2), both from the light's tables. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "recon/maaf/maaf_filter.h"
#include "recon/maaf/maaf_shadow.h"

enum { PAIRS = 3, GRID = 64 };

static MaafLight square_light(void)
{
    MaafLight l;
    memset(&l, 0, sizeof l);
    l.t1[0] = l.t2[1] = 1.0f;
    l.lo[0] = l.lo[1] = -1.0f;
    l.hi[0] = l.hi[1] = 1.0f;
    /* sigma 0.15: the central band's y-window has std (2N - 1) sigma / 2 = 0.375, so most of
     * the light is within two stds of an edge */
    maaf_light_design(0.15f, PAIRS, &l);
    return l;
}

static double value_at(double y1, double y2) { return 1.0 + y1 * y1 + y2 * y2; }

int main(void)
{
    MaafLight l = square_light();
    int comps = maaf_component_count(PAIRS);
    float ysum[8 * MAAF_COMPS_MAX];
    memset(ysum, 0, sizeof ysum);
    double plain = 0.0, old_num = 0.0, old_den = 0.0;
    for (int i = 0; i < GRID; ++i)
        for (int k = 0; k < GRID; ++k) {
            float y1 = -1.0f + 2.0f * ((float)i + 0.5f) / GRID, y2 = -1.0f + 2.0f * ((float)k + 0.5f) / GRID;
            float v = (float)value_at(y1, y2), f4[4] = {v, v, v, 1.0f};
            maaf_accumulate(PAIRS, &l, y1, y2, f4, ysum);
            plain += v;
            /* the old weight: the central band's integrated factor on both axes */
            float c1[2], c2[2];
            maaf_light_factor(&l, 0, 0, y1, c1);
            maaf_light_factor(&l, 1, 0, y2, c2);
            old_num += v * c1[0] * c2[0];
            old_den += c1[0] * c2[0];
        }
    plain /= (double)GRID * GRID;
    double central = ysum[0] / ysum[3], old = old_num / old_den;
    printf("mean over the light: %.6f; central component: %.6f; with c_0(y) as the weight: %.6f\n", plain, central, old);
    CHECK(fabs(central - plain) < 1e-4 * plain); /* float sums of 4096 samples */
    CHECK(old < 0.97 * plain); /* the old weighting is measurably off on this light */
    for (int ch = 0; ch < 3; ++ch) CHECK(ysum[ch] == ysum[0]);

    /* 2. one sample: component (p = 1, q = 0) is index 5 (p = 0: q = 0, 1, 2; p = 1: q = -2 ..) */
    float one[8 * MAAF_COMPS_MAX], f4[4] = {1.0f, 1.0f, 1.0f, 1.0f}, y1 = 0.7f, y2 = -0.2f;
    memset(one, 0, sizeof one);
    maaf_accumulate(PAIRS, &l, y1, y2, f4, one);
    float c1[2], m2[2];
    maaf_light_factor(&l, 0, 1, y1, c1);
    maaf_light_factor(&l, 1, 0, y2, m2);
    double want_re = c1[0] * m2[0] - c1[1] * m2[1], want_im = c1[0] * m2[1] + c1[1] * m2[0];
    printf("component (1, 0): %.6f %+.6fj, want %.6f %+.6fj\n", one[8 * 5], one[8 * 5 + 4], want_re, want_im);
    CHECK(comps > 5);
    CHECK(fabs(one[8 * 5] - want_re) < 1e-6 && fabs(one[8 * 5 + 4] - want_im) < 1e-6);
    CHECK(fabs(want_im) > 1e-3); /* a complex factor: the sample's place on the light counts */
    CHECK_DONE();
}
