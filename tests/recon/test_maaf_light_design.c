/* The light's y-design (maaf_shadow.h, docs/algorithms.md 9.6): its tables of
 *     c_p(y) = int_{lo - y}^{hi - y} exp(j C_p t) g(t; s) dt
 * against a brute-force integral (a fine midpoint rule, independent of the design's Simpson
 * steps), every band of a design with several bands, on a light whose two axes differ (no copy
 * between them) and on a square one (the second axis a copy); their means over the light; and
 * maaf_light_design_copy: a mesh light's second triangle gets the first one's design bit for bit,
 * and a light with another band or extent gets none. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "recon/maaf/maaf_shadow.h"

/* c_p at entry e of axis a by the midpoint rule over the light */
static void brute_entry(const MaafLight *l, int a, int p, int e, double out[2])
{
    enum { STEPS = 20000 };
    double y = l->lo[a] + (l->hi[a] - l->lo[a]) * e / (MAAF_YTABLE - 1.0), C = l->cy[p], s = l->sy[p];
    double lo = l->lo[a] - y, h = (l->hi[a] - l->lo[a]) / STEPS, re = 0.0, im = 0.0;
    for (int k = 0; k < STEPS; ++k) {
        double t = lo + (k + 0.5) * h, g = s * 0.3989422804014327 * exp(-0.5 * s * s * t * t);
        re += g * cos(C * t) * h;
        im += g * sin(C * t) * h;
    }
    out[0] = re, out[1] = im;
}

/* the largest |table - brute force| over every band and a spread of entries of both axes, and
 * the largest |c| */
static void table_vs_brute(const MaafLight *l, int pairs, double *worst, double *biggest)
{
    *worst = 0.0, *biggest = 0.0;
    for (int a = 0; a < 2; ++a)
        for (int p = 0; p < pairs; ++p)
            for (int e = 0; e < MAAF_YTABLE; e += 8) {
                double b[2];
                brute_entry(l, a, p, e, b);
                *worst = fmax(*worst, hypot(l->table[a][p][e][0] - b[0], l->table[a][p][e][1] - b[1]));
                *biggest = fmax(*biggest, hypot(b[0], b[1]));
            }
}

static MaafLight light_box(float lo0, float hi0, float lo1, float hi1)
{
    MaafLight l;
    memset(&l, 0, sizeof l);
    l.t1[0] = l.t2[1] = 1.0f;
    l.lo[0] = lo0, l.hi[0] = hi0, l.lo[1] = lo1, l.hi[1] = hi1;
    return l;
}

int main(void)
{
    enum { PAIRS = 4 };
    /* 1. every band of a wide light (C_p up to 6 wy / 7: several periods over it) */
    MaafLight wide = light_box(-0.7f, 0.7f, -0.35f, 0.85f);
    maaf_light_design(0.3f, PAIRS, &wide);
    double worst, biggest;
    table_vs_brute(&wide, PAIRS, &worst, &biggest);
    printf("light table vs brute force: max |diff| %.2e (largest |c| %.3f)\n", worst, biggest);
    CHECK(biggest > 0.1);
    CHECK(worst < 1e-5 * biggest);
    /* the central band is real (C = 0) and the others are not */
    bool real0 = true, complex_p = false;
    for (int e = 0; e < MAAF_YTABLE; ++e) {
        real0 = real0 && wide.table[0][0][e][1] == 0.0f && wide.table[1][0][e][1] == 0.0f;
        complex_p = complex_p || fabsf(wide.table[0][2][e][1]) > 1e-3f;
    }
    CHECK(real0);
    CHECK(complex_p);
    /* the means: the trapezoid rule over the table, the band's average over the light */
    for (int a = 0; a < 2; ++a)
        for (int p = 0; p < PAIRS; ++p) {
            double s = 0.0;
            for (int e = 0; e < MAAF_YTABLE; ++e) s += (e == 0 || e == MAAF_YTABLE - 1 ? 0.5 : 1.0) * wide.table[a][p][e][0];
            CHECK(fabs(wide.mean[a][p][0] - s / (MAAF_YTABLE - 1)) < 1e-6);
        }

    /* 2. a square light: the second axis' table is the first's, and both match brute force */
    MaafLight square = light_box(-0.5f, 0.5f, -0.5f, 0.5f);
    maaf_light_design(0.25f, PAIRS, &square);
    table_vs_brute(&square, PAIRS, &worst, &biggest);
    CHECK(worst < 1e-5 * biggest);
    CHECK(memcmp(square.table[0], square.table[1], sizeof square.table[0]) == 0);

    /* 3. a mesh light's second triangle (the same extents and band): the same design bit for
     * bit, without its integrals */
    MaafLight second = light_box(-0.7f, 0.7f, -0.35f, 0.85f), fresh = second;
    maaf_light_design(0.3f, PAIRS, &fresh);
    CHECK(maaf_light_design_copy(&wide, 0.3f, &second));
    CHECK(memcmp(&second, &fresh, sizeof second) == 0);
    /* another band, another extent, or a light without one: no copy, the light untouched */
    MaafLight other = light_box(-0.7f, 0.7f, -0.35f, 0.85f), before = other;
    CHECK(!maaf_light_design_copy(&wide, 0.31f, &other));
    other.hi[1] = 0.9f, before = other;
    CHECK(!maaf_light_design_copy(&wide, 0.3f, &other));
    CHECK(!maaf_light_design_copy(&wide, 0.0f, &other));
    CHECK(memcmp(&other, &before, sizeof other) == 0);
    CHECK_DONE();
}
