/* A planar mesh emitter's projected solid angle through its boundary (emitter_boundary.h)
 * against the sum over its triangles of polygon_projected_solid_angle (each clipped to the
 * horizon), at random receivers on either side of the emitter's plane, many of them with a
 * horizon that cuts the emitter: a tilted grid of quads from the front and from the back, a ring
 * (a hole: two boundary loops) and a comb (one loop that a horizon crosses many times); and the
 * surfaces that must not take the boundary are refused: a curved mesh, a mesh with one triangle
 * wound the other way, three triangles on one edge, a quad (boundary no shorter than its
 * interior), a grid with a degenerate triangle. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/emitter_boundary.h"
#include "recon/polygon_irradiance.h"

enum { MAX_TRI = 4096 };
static double g_tri[MAX_TRI][3][3];

static unsigned g_rng = 12345u;
static double uniform(void)
{
    g_rng = g_rng * 1664525u + 1013904223u;
    return (g_rng >> 8) * (1.0 / 16777216.0);
}

/* Point (u, v) of the plane through o spanned by e1, e2 (lifted by bump * u^2 when curved). */
static void plane_point(double u, double v, double bump, double q[3])
{
    const double o[3] = {-0.7, 2.0, -0.4}, e1[3] = {1.4, 0.15, 0.1}, e2[3] = {0.05, 0.2, 1.2};
    for (int k = 0; k < 3; ++k) q[k] = o[k] + u * e1[k] + v * e2[k];
    q[1] += bump * u * u;
}

enum { FULL, RING, COMB };

/* An n x n grid of quads over [0,1]^2; RING: the central third left out; COMB: every other
 * column left out above the middle row (teeth). */
static int grid_of(int n, int holes, double bump)
{
    int count = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            if (holes == RING && i >= n / 3 && i < n - n / 3 && j >= n / 3 && j < n - n / 3) continue;
            if (holes == COMB && j >= n / 2 && i % 2 == 1) continue;
            double a[3], b[3], c[3], d[3];
            plane_point((double)i / n, (double)j / n, bump, a), plane_point((double)(i + 1) / n, (double)j / n, bump, b);
            plane_point((double)i / n, (double)(j + 1) / n, bump, c), plane_point((double)(i + 1) / n, (double)(j + 1) / n, bump, d);
            memcpy(g_tri[count][0], a, sizeof a), memcpy(g_tri[count][1], c, sizeof c), memcpy(g_tri[count][2], b, sizeof b);
            ++count;
            memcpy(g_tri[count][0], b, sizeof b), memcpy(g_tri[count][1], c, sizeof c), memcpy(g_tri[count][2], d, sizeof d);
            ++count;
        }
    return count;
}

static int grid(int n, bool ring_hole, double bump) { return grid_of(n, ring_hole ? RING : FULL, bump); }

static double triangles_phi(int count, const double p[3], const double n[3])
{
    double sum = 0.0;
    for (int t = 0; t < count; ++t) sum += polygon_projected_solid_angle(p, n, (const double(*)[3])g_tri[t], 3);
    return sum;
}

/* Random receivers on the side `side` (+1 / -1) of the plane, normals tilted up to ~70 degrees
 * from the plane's: the boundary's value against the triangles'. Returns how many answered;
 * *cut: how many had some vertex below their horizon. */
static int compare_at_receivers(const EmitterBoundary *b, int count, double side, double *worst_rel, int *cut)
{
    int answered = 0;
    *worst_rel = 0.0, *cut = 0;
    for (int r = 0; r < 300; ++r) {
        double centre[3];
        plane_point(uniform() * 1.6 - 0.3, uniform() * 1.6 - 0.3, 0.0, centre);
        double o[3], u1[3], v1[3], e1[3], e2[3], face[3]; /* the plane's unit normal, e2 x e1 */
        plane_point(0, 0, 0.0, o), plane_point(1, 0, 0.0, u1), plane_point(0, 1, 0.0, v1);
        for (int k = 0; k < 3; ++k) e1[k] = u1[k] - o[k], e2[k] = v1[k] - o[k];
        polygon_edge_cross(e2, e1, face);
        double flen = sqrt(polygon_dot3(face, face));
        for (int k = 0; k < 3; ++k) face[k] /= flen;
        double dist = 0.05 + 2.0 * uniform(), p[3], n[3];
        for (int k = 0; k < 3; ++k) p[k] = centre[k] - side * dist * face[k];
        for (int k = 0; k < 3; ++k) n[k] = side * face[k] + 2.5 * (uniform() - 0.5);
        double len = sqrt(polygon_dot3(n, n));
        for (int k = 0; k < 3; ++k) n[k] /= len;
        double want = triangles_phi(count, p, n), got = -1.0;
        bool below = false;
        for (int t = 0; t < count; ++t)
            for (int v = 0; v < 3; ++v) {
                double rel[3] = {g_tri[t][v][0] - p[0], g_tri[t][v][1] - p[1], g_tri[t][v][2] - p[2]};
                below = below || polygon_dot3(rel, n) < 0.0;
            }
        *cut += below;
        if (emitter_boundary_phi(b, p, n, &got)) {
            ++answered;
            /* relative to the emitter's whole projected solid angle from p: a clipped sliver's
             * value is the difference of larger terms */
            double facing[3] = {side * face[0], side * face[1], side * face[2]};
            double scale = fmax(want, triangles_phi(count, p, facing));
            *worst_rel = fmax(*worst_rel, fabs(got - want) / fmax(scale, 1e-300));
        }
    }
    return answered;
}

static void check_surface(const char *what, int count, int boundary_edges, double side)
{
    EmitterBoundary *b = emitter_boundary_create(count, (const double(*)[3][3])g_tri);
    CHECK(b != NULL);
    if (!b) return;
    CHECK(emitter_boundary_edge_count(b) == boundary_edges);
    double worst;
    int cut, answered = compare_at_receivers(b, count, side, &worst, &cut);
    printf("%s: %d of 300 receivers through the boundary (%d with the horizon across the emitter), worst relative "
           "difference %.2e\n", what, answered, cut, worst);
    CHECK(answered == 300);
    CHECK(cut > 60 && cut < 270); /* both kinds of receiver were drawn */
    CHECK(worst < 1e-12); /* sums of a few hundred terms: ~1e-14 of rounding */
    emitter_boundary_destroy(b);
}

int main(void)
{
    /* 1. a tilted 24 x 24 grid, from the front and from the back; 2. a ring: the hole's loop runs
     * the other way and takes its light back out; 3. a comb: one loop of 12 teeth */
    check_surface("grid, front", grid(24, false, 0.0), 4 * 24, 1.0);
    check_surface("grid, back", grid(24, false, 0.0), 4 * 24, -1.0);
    check_surface("ring", grid(24, true, 0.0), 4 * 24 + 4 * 8, 1.0);
    check_surface("comb", grid_of(24, COMB, 0.0), 12 * (1 + 2 * 12) + 24 + 12 + 12 + 12, 1.0); /* teeth, then the base's
                                                                                             bottom, sides, gaps */
    /* a receiver on a boundary vertex: no direction to it, the caller's triangles decide */
    {
        int count = grid(4, false, 0.0);
        EmitterBoundary *b = emitter_boundary_create(count, (const double(*)[3][3])g_tri);
        double n[3] = {0.0, 1.0, 0.0}, got = -7.0;
        CHECK(b != NULL);
        if (b) CHECK(!emitter_boundary_phi(b, g_tri[0][0], n, &got) && got == -7.0);
        emitter_boundary_destroy(b);
    }
    /* 3. what must be refused */
    int count = grid(8, false, 0.3); /* curved */
    CHECK(emitter_boundary_create(count, (const double(*)[3][3])g_tri) == NULL);
    count = grid(8, false, 0.0);
    double keep[3];
    memcpy(keep, g_tri[17][1], sizeof keep); /* one triangle wound the other way */
    memcpy(g_tri[17][1], g_tri[17][2], sizeof keep), memcpy(g_tri[17][2], keep, sizeof keep);
    CHECK(emitter_boundary_create(count, (const double(*)[3][3])g_tri) == NULL);
    count = grid(8, false, 0.0); /* a third triangle on an interior edge, in the plane */
    memcpy(g_tri[count][0], g_tri[10][0], sizeof keep), memcpy(g_tri[count][1], g_tri[10][1], sizeof keep);
    for (int k = 0; k < 3; ++k) g_tri[count][2][k] = 0.5 * (g_tri[10][0][k] + g_tri[10][2][k]) + 0.25 * (g_tri[10][0][k] - g_tri[10][1][k]);
    CHECK(emitter_boundary_create(count + 1, (const double(*)[3][3])g_tri) == NULL);
    count = grid(1, false, 0.0); /* a quad: 4 boundary edges, 1 interior */
    CHECK(count == 2 && emitter_boundary_create(count, (const double(*)[3][3])g_tri) == NULL);
    count = grid(8, false, 0.0); /* a degenerate triangle */
    memcpy(g_tri[5][2], g_tri[5][1], sizeof keep);
    CHECK(emitter_boundary_create(count, (const double(*)[3][3])g_tri) == NULL);
    count = grid(8, false, 2e-5); /* curved by 3e-5 of its size: normals within 1e-4 rad, off the plane */
    CHECK(emitter_boundary_create(count, (const double(*)[3][3])g_tri) == NULL);
    count = grid(8, false, 0.0); /* a triangle over a border triangle's border edge, run the same way */
    double m[3];
    plane_point(0.5 / 8, 0.5 / 8, 0.0, m);
    memcpy(g_tri[count][0], g_tri[0][2], sizeof keep), memcpy(g_tri[count][1], g_tri[0][0], sizeof keep);
    memcpy(g_tri[count][2], m, sizeof m);
    CHECK(emitter_boundary_create(count + 1, (const double(*)[3][3])g_tri) == NULL);
    count = grid(8, false, 0.0); /* a second patch of the plane, apart from the first, wound the other way */
    for (int t = 0; t < 2; ++t)
        for (int v = 0; v < 3; ++v) {
            double q[3];
            plane_point(2.0 + 0.1 * (v == 1) + 0.1 * t, 2.0 + 0.1 * (v == 2), 0.0, q);
            memcpy(g_tri[count + t][t ? 2 - v : v], q, sizeof q);
        }
    CHECK(emitter_boundary_create(count + 2, (const double(*)[3][3])g_tri) == NULL);
    count = grid(8, false, 0.0); /* and the same grid whole is taken */
    EmitterBoundary *b = emitter_boundary_create(count, (const double(*)[3][3])g_tri);
    CHECK(b != NULL);
    emitter_boundary_destroy(b);
    return check_failures ? 1 : 0;
}
