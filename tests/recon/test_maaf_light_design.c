/* The light's y-design (maaf_shadow.h, docs/algorithms.md 9.6):
 * 1. the universal table Phi_p (maaf_band_cdf.h) against its closed forms: Phi_0 the normal
 *    CDF, Phi_p(+inf) = exp(-2 p^2), and its symmetries;
 * 2. c_p(y) = int_{lo - y}^{hi - y} exp(j C_p t) g(t; s) dt from that table against a direct
 *    integral (Simpson in double, C_p and s from eq. 6, not from the table's units), every band
 *    p = 0..4, both axes, on a narrow, a wide, an off-centre and a square light, within the bound
 *    of the table's linear interpolation (twice h^2/8 max|Phi_p''| plus float rounding);
 * 3. the means over the light (the trapezoid rule over c_p);
 * 4. maaf_light_design_copy: a mesh light's second triangle gets the first one's design bit for
 *    bit, and a light with another band, extent or poses gets none; a moving light's poses
 *    weight its means. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "recon/maaf/maaf_band_cdf.h"
#include "recon/maaf/maaf_shadow.h"

enum { PAIRS = MAAF_PAIRS_MAX };

static const double PHI0 = 0.3989422804014327; /* 1 / sqrt(2 pi) */

/* c_p(y) along axis a by Simpson's rule over the window, from the light's band Omega_y_max and
 * eq. 6 (C_p = Omega 2p / (2N - 1), s = Omega / (2N - 1)) */
static void direct_factor(const MaafLight *l, int a, int p, double y, double out[2])
{
    enum { STEPS = 8000 };
    double bands = 2.0 * PAIRS - 1.0, C = l->omega_y_max * 2.0 * p / bands, s = l->omega_y_max / bands;
    double lo = l->lo[a] - y, h = (l->hi[a] - l->lo[a]) / STEPS, re = 0.0, im = 0.0;
    for (int k = 0; k <= STEPS; ++k) {
        double t = lo + k * h, w = (k == 0 || k == STEPS ? 1.0 : k % 2 ? 4.0 : 2.0) * h / 3.0;
        double g = w * s * PHI0 * exp(-0.5 * s * s * t * t);
        re += g * cos(C * t);
        im += g * sin(C * t);
    }
    out[0] = re, out[1] = im;
}

/* The bound on |c_p - exact|: each of the window's two ends interpolated linearly on a step h
 * errs by at most h^2/8 max|Phi_p''|, |Phi_p''(v)| = sqrt(4p^2 + v^2) phi(v), whose maximum is
 * 2p phi(0) for p >= 1 and phi(1) (at |v| = 1) for p = 0; plus the rounding of a few float
 * operations on values of magnitude <= 1 (entries, the interpolation, the difference): 1e-6. */
static double factor_tolerance(int p)
{
    double h = 1.0 / MAAF_BAND_CDF_PER_UNIT, top = p > 0 ? 2.0 * p * PHI0 : PHI0 * exp(-0.5);
    return 2.0 * h * h / 8.0 * top + 1e-6;
}

static MaafLight light_box(float lo0, float hi0, float lo1, float hi1, float sigma)
{
    MaafLight l;
    memset(&l, 0, sizeof l);
    l.t1[0] = l.t2[1] = 1.0f;
    l.lo[0] = lo0, l.hi[0] = hi0, l.lo[1] = lo1, l.hi[1] = hi1;
    maaf_light_design(sigma, PAIRS, &l);
    return l;
}

/* the worst |c_p - direct| / tolerance over both axes, every band and Y places on the light
 * (ends included); *biggest the largest |Im c_p| for p >= 1 seen, *imag0 whether c_0 was ever
 * not real */
static double factor_vs_direct(const MaafLight *l, double *biggest_im, bool *imag0)
{
    enum { Y = 61 };
    double worst = 0.0;
    for (int a = 0; a < 2; ++a)
        for (int i = 0; i < Y; ++i) {
            float y = l->lo[a] + (l->hi[a] - l->lo[a]) * (float)i / (Y - 1);
            for (int p = 0; p < PAIRS; ++p) {
                float c[2];
                double d[2];
                maaf_light_factor(l, a, p, y, c);
                direct_factor(l, a, p, y, d);
                worst = fmax(worst, hypot(c[0] - d[0], c[1] - d[1]) / factor_tolerance(p));
                if (p > 0) *biggest_im = fmax(*biggest_im, fabs(d[1]));
                if (p == 0 && c[1] != 0.0f) *imag0 = true;
            }
        }
    return worst;
}

static void check_table(void)
{
    const MaafBandCdf *t = maaf_band_cdf();
    double worst_cdf = 0.0, worst_sym = 0.0, worst_end = 0.0;
    for (int e = 0; e < MAAF_BAND_CDF_ENTRIES; ++e) {
        double v = -MAAF_BAND_CDF_V_MAX + (double)e / MAAF_BAND_CDF_PER_UNIT;
        worst_cdf = fmax(worst_cdf, fabs((*t)[0][e][0] - 0.5 * erfc(-v / sqrt(2.0))));
        for (int p = 0; p < PAIRS; ++p) {
            const float *a = (*t)[p][e], *b = (*t)[p][MAAF_BAND_CDF_ENTRIES - 1 - e];
            worst_sym = fmax(worst_sym, fabs(a[0] + b[0] - exp(-2.0 * p * p)));
            worst_sym = fmax(worst_sym, fabs(a[1] - b[1]));
        }
    }
    for (int p = 0; p < PAIRS; ++p) {
        const float *top = (*t)[p][MAAF_BAND_CDF_ENTRIES - 1];
        worst_end = fmax(worst_end, hypot(top[0] - exp(-2.0 * p * p), top[1]));
    }
    printf("table: Phi_0 vs the normal CDF %.2e, symmetry %.2e, Phi_p(V_MAX) vs exp(-2p^2) %.2e\n", worst_cdf, worst_sym,
           worst_end);
    CHECK(worst_cdf < 1e-7);  /* a float's rounding (6e-8 at 1) and Simpson's ~1e-11 */
    CHECK(worst_sym < 2e-7);
    CHECK(worst_end < 1e-7);
    CHECK(maaf_band_cdf() == t); /* one table a process */
}

int main(void)
{
    check_table();

    /* 2. lights of every kind (sigma sets Omega_y_max = 2 / sigma, so s = Omega / 9 at 5 pairs):
     * narrow (s w about 0.9: the window much narrower than the Gaussian), wide (s w about 50:
     * both ends saturate; the old 129-entry table was coarse here), off-centre, and square */
    struct {
        const char *name;
        MaafLight l;
    } lights[] = {
        {"narrow", light_box(-0.05f, 0.05f, -0.02f, 0.03f, 0.025f)},
        {"wide", light_box(-0.7f, 0.7f, -0.35f, 0.85f, 0.006f)},
        {"off-centre", light_box(-0.1f, 1.3f, -0.9f, -0.2f, 0.3f)},
        {"square", light_box(-0.5f, 0.5f, -0.5f, 0.5f, 0.25f)},
    };
    double biggest_im = 0.0;
    bool imag0 = false;
    for (size_t i = 0; i < sizeof lights / sizeof lights[0]; ++i) {
        double worst = factor_vs_direct(&lights[i].l, &biggest_im, &imag0);
        printf("%-10s s w = %6.2f, %6.2f: worst |c_p - direct| / bound %.3f\n", lights[i].name,
               lights[i].l.sy * (lights[i].l.hi[0] - lights[i].l.lo[0]), lights[i].l.sy * (lights[i].l.hi[1] - lights[i].l.lo[1]),
               worst);
        CHECK(worst <= 1.0);
    }
    CHECK(biggest_im > 0.05); /* the offset bands are complex (the phase is tested, not only |c|) */
    CHECK(!imag0);            /* the central band is real */

    /* outside the extent (a disk's samples outside its box): the nearest end, bit for bit */
    const MaafLight *off = &lights[2].l;
    for (int p = 0; p < PAIRS; ++p) {
        float in[2], out[2];
        maaf_light_factor(off, 0, p, off->hi[0], in);
        maaf_light_factor(off, 0, p, off->hi[0] + 0.4f, out);
        CHECK(memcmp(in, out, sizeof in) == 0);
        maaf_light_factor(off, 1, p, off->lo[1], in);
        maaf_light_factor(off, 1, p, NAN, out);
        CHECK(memcmp(in, out, sizeof in) == 0);
    }
    /* the square's axes give the same factors */
    const MaafLight *sq = &lights[3].l;
    bool same = true;
    for (int p = 0; p < PAIRS; ++p)
        for (int i = 0; i <= 20; ++i) {
            float y = -0.5f + 0.05f * (float)i, c0[2], c1[2];
            maaf_light_factor(sq, 0, p, y, c0);
            maaf_light_factor(sq, 1, p, y, c1);
            same = same && memcmp(c0, c1, sizeof c0) == 0;
        }
    CHECK(same);

    /* 3. the means: the trapezoid rule over c_p on MAAF_MEAN_NODES nodes, the band's average
     * over the light (a static light: real, as c_p(y) averaged over y in the window is) */
    for (size_t i = 0; i < sizeof lights / sizeof lights[0]; ++i) {
        const MaafLight *l = &lights[i].l;
        for (int a = 0; a < 2; ++a)
            for (int p = 0; p < PAIRS; ++p) {
                double s[2] = {0.0, 0.0};
                for (int e = 0; e < MAAF_MEAN_NODES; ++e) {
                    float c[2];
                    maaf_light_factor(l, a, p, (float)(l->lo[a] + (l->hi[a] - l->lo[a]) * e / (MAAF_MEAN_NODES - 1.0)), c);
                    for (int k = 0; k < 2; ++k) s[k] += (e == 0 || e == MAAF_MEAN_NODES - 1 ? 0.5 : 1.0) * c[k];
                }
                for (int k = 0; k < 2; ++k) CHECK(fabs(l->mean[a][p][k] - s[k] / (MAAF_MEAN_NODES - 1)) < 1e-6);
                CHECK(fabs(l->mean[a][p][1]) < 1e-5);
            }
    }

    /* 4. a mesh light's second triangle (the same extents and band): the same design bit for
     * bit, without its integrals */
    const MaafLight *wide = &lights[1].l;
    MaafLight second = *wide, fresh = light_box(-0.7f, 0.7f, -0.35f, 0.85f, 0.006f);
    memset(second.mean, 0, sizeof second.mean);
    second.sy = 0.0f, second.omega_y_max = 0.0f;
    CHECK(maaf_light_design_copy(wide, 0.006f, &second));
    CHECK(memcmp(&second, &fresh, sizeof second) == 0);
    /* another band, another extent, or a light without one: no copy, the light untouched */
    MaafLight other = light_box(-0.7f, 0.7f, -0.35f, 0.85f, 0.3f), before = other;
    CHECK(!maaf_light_design_copy(wide, 0.0061f, &other));
    other.hi[1] = 0.9f, before = other;
    CHECK(!maaf_light_design_copy(wide, 0.006f, &other));
    CHECK(!maaf_light_design_copy(wide, 0.0f, &other));
    CHECK(memcmp(&other, &before, sizeof other) == 0);

    /* a moving light: its poses weight the means (a light sliding along t1 covers the middle
     * longer), a copy needs the same poses, whichever storage holds them, and poses at hand */
    MaafSweep poses, twin, shifted;
    for (int k = 0; k < MAAF_SWEEP_NODES; ++k) {
        float d = 0.6f * (float)k / (MAAF_SWEEP_NODES - 1) - 0.3f;
        poses.lo[0][k] = d - 0.4f, poses.hi[0][k] = d + 0.4f, poses.lo[1][k] = -0.2f, poses.hi[1][k] = 0.2f;
    }
    twin = shifted = poses;
    shifted.hi[0][7] += 0.01f;
    MaafLight moving = light_box(-0.7f, 0.7f, -0.2f, 0.2f, 0.0f), copy = moving, unlike = moving, bare = moving;
    moving.sweep_nodes = copy.sweep_nodes = unlike.sweep_nodes = bare.sweep_nodes = MAAF_SWEEP_NODES;
    moving.sweep = &poses, copy.sweep = &twin, unlike.sweep = &shifted;
    MaafLight still = moving;
    still.sweep_nodes = 0, still.sweep = NULL;
    maaf_light_design(0.05f, PAIRS, &moving);
    maaf_light_design(0.05f, PAIRS, &still);
    printf("moving light: mean c_0 along the motion %.4f, the static light's %.4f\n", moving.mean[0][0][0], still.mean[0][0][0]);
    CHECK(moving.mean[0][0][0] > still.mean[0][0][0] + 0.01f); /* the density: more samples mid-light */
    CHECK(moving.mean[1][0][0] == still.mean[1][0][0]);        /* no motion along t2 */
    CHECK(maaf_light_design_copy(&moving, 0.05f, &copy));
    CHECK(memcmp(copy.mean, moving.mean, sizeof copy.mean) == 0);
    CHECK(!maaf_light_design_copy(&moving, 0.05f, &unlike));
    CHECK(!maaf_light_design_copy(&moving, 0.05f, &bare));
    CHECK(!maaf_light_design_copy(&moving, 0.05f, &still));
    CHECK_DONE();
}
