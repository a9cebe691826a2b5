/* Lambert's polygon formula with horizon clipping (recon/polygon_irradiance.c) against the
 * closed-form form factor of a rectangle and against brute-force quadrature of its defining
 * integral, including polygons cut by the receiver's horizon. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "recon/polygon_irradiance.h"

/* Projected solid angle of an a x b rectangle parallel to the receiver at height c, with the
 * receiver below one corner: pi times the classic point-to-rectangle form factor
 * F = (1/2pi) [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2))],
 * X = a/c, Y = b/c. */
static double corner_rectangle(double a, double b, double c)
{
    double X = a / c, Y = b / c, sx = sqrt(1 + X * X), sy = sqrt(1 + Y * Y);
    return 0.5 * (X / sx * atan(Y / sx) + Y / sy * atan(X / sy));
}

/* The defining integral: integral over the polygon's area of max(0, cos_r) |cos_l| / d^2 by a
 * midpoint rule on an m x m grid of the parallelogram v0 + s (v1 - v0) + t (v3 - v0). */
static double brute_parallelogram(const double p[3], const double n[3], const double v[4][3], int m)
{
    double e1[3], e2[3], nl[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = v[1][k] - v[0][k];
        e2[k] = v[3][k] - v[0][k];
    }
    nl[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nl[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nl[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double area = sqrt(nl[0] * nl[0] + nl[1] * nl[1] + nl[2] * nl[2]);
    for (int k = 0; k < 3; ++k) nl[k] /= area;
    double sum = 0;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            double s = (i + 0.5) / m, t = (j + 0.5) / m, w[3];
            for (int k = 0; k < 3; ++k) w[k] = v[0][k] + s * e1[k] + t * e2[k] - p[k];
            double d2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2], d = sqrt(d2);
            double cr = (n[0] * w[0] + n[1] * w[1] + n[2] * w[2]) / d;
            double cl = fabs(nl[0] * w[0] + nl[1] * w[1] + nl[2] * w[2]) / d;
            if (cr > 0) sum += cr * cl / d2;
        }
    return sum * area / ((double)m * m);
}

static double frand(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / 16777216.0;
}

static void test_closed_forms(void)
{
    const double p[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    double sizes[][3] = {{1, 1, 1}, {2, 0.5, 3}, {0.1, 4, 0.7}, {10, 10, 0.01}};
    for (int k = 0; k < 4; ++k) {
        double a = sizes[k][0], b = sizes[k][1], c = sizes[k][2];
        double quad[4][3] = {{0, 0, c}, {a, 0, c}, {a, b, c}, {0, b, c}};
        double got = polygon_projected_solid_angle(p, up, quad, 4);
        CHECK_NEAR(got, corner_rectangle(a, b, c), 1e-9);
        /* the opposite winding gives the same value */
        double rev[4][3] = {{0, b, c}, {a, b, c}, {a, 0, c}, {0, 0, c}};
        CHECK_NEAR(polygon_projected_solid_angle(p, up, rev, 4), got, 1e-12);
    }
    /* A receiver under the centre of a 2a x 2b rectangle: four corner rectangles. */
    double q[4][3] = {{-1, -0.5, 2}, {1, -0.5, 2}, {1, 0.5, 2}, {-1, 0.5, 2}};
    CHECK_NEAR(polygon_projected_solid_angle(p, up, q, 4), 4 * corner_rectangle(1, 0.5, 2), 1e-9);
    /* An infinite plane above subtends pi: a huge square comes close. */
    double big[4][3] = {{-1e4, -1e4, 1}, {1e4, -1e4, 1}, {1e4, 1e4, 1}, {-1e4, 1e4, 1}};
    CHECK_NEAR(polygon_projected_solid_angle(p, up, big, 4), M_PI, 1e-3);
    /* Wholly below the horizon: nothing; the receiver facing away: nothing. */
    double below[4][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}};
    CHECK_NEAR(polygon_projected_solid_angle(p, up, below, 4), 0.0, 0.0);
    const double down[3] = {0, 0, -1};
    CHECK_NEAR(polygon_projected_solid_angle(p, down, q, 4), 0.0, 0.0);
    /* Degenerate input: too few vertices, a vertex at the receiver. */
    CHECK_NEAR(polygon_projected_solid_angle(p, up, q, 2), 0.0, 0.0);
    double touching[3][3] = {{0, 0, 0}, {1, 0, 1}, {0, 1, 1}};
    CHECK(isfinite(polygon_projected_solid_angle(p, up, touching, 3)));
}

/* Random parallelograms around random receivers, many of them cut by the horizon: the
 * formula equals the integral it stands for. */
static void test_brute_force(void)
{
    unsigned s = 2024u;
    int cut = 0;
    double worst = 0;
    for (int trial = 0; trial < 40; ++trial) {
        double p[3] = {frand(&s) - 0.5, frand(&s) - 0.5, frand(&s) - 0.5}, n[3];
        double nl = 0;
        for (int k = 0; k < 3; ++k) {
            n[k] = 2 * frand(&s) - 1;
            nl += n[k] * n[k];
        }
        for (int k = 0; k < 3; ++k) n[k] /= sqrt(nl);
        double v[4][3], e1[3], e2[3];
        for (int k = 0; k < 3; ++k) {
            v[0][k] = 3 * frand(&s) - 1.5;
            e1[k] = 2 * frand(&s) - 1;
            e2[k] = 2 * frand(&s) - 1;
        }
        for (int k = 0; k < 3; ++k) {
            v[1][k] = v[0][k] + e1[k];
            v[2][k] = v[0][k] + e1[k] + e2[k];
            v[3][k] = v[0][k] + e2[k];
        }
        /* keep the polygon away from the receiver itself (the integrand's singularity) */
        double dmin = 1e9;
        for (int c = 0; c < 4; ++c) {
            double d = 0;
            for (int k = 0; k < 3; ++k) d += (v[c][k] - p[k]) * (v[c][k] - p[k]);
            dmin = fmin(dmin, sqrt(d));
        }
        double en[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        double elen = sqrt(en[0] * en[0] + en[1] * en[1] + en[2] * en[2]);
        double plane_dist = fabs(en[0] * (p[0] - v[0][0]) + en[1] * (p[1] - v[0][1]) + en[2] * (p[2] - v[0][2])) / elen;
        if (dmin < 0.3 || plane_dist < 0.2) continue;
        int above = 0;
        for (int c = 0; c < 4; ++c)
            above += (v[c][0] - p[0]) * n[0] + (v[c][1] - p[1]) * n[1] + (v[c][2] - p[2]) * n[2] > 0;
        if (above > 0 && above < 4) ++cut;
        double got = polygon_projected_solid_angle(p, n, v, 4);
        double want = brute_parallelogram(p, n, v, 600);
        double err = fabs(got - want) / fmax(want, 1e-3);
        worst = fmax(worst, err);
        CHECK(err < 2e-3);
    }
    fprintf(stderr, "polygon vs quadrature: worst relative error %.2e, %d polygons cut by the horizon\n", worst,
            cut);
    CHECK(cut >= 5); /* the clipping was exercised */
}

int main(void)
{
    test_closed_forms();
    test_brute_force();
    CHECK_DONE();
}
