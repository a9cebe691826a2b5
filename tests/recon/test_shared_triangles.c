/* shared_triangles_phi against polygon_projected_solid_angle, triangle by triangle, bit for
 * bit: a quad (two triangles, one shared edge), a fan of six triangles round a centre vertex
 * (each edge from the centre shared, traversed both ways round), a lone triangle, and a vertex
 * at 0 whose copy in another triangle is -0 (kept apart: not the same bits). Receivers above,
 * below and straddling the lights' planes with tilted normals (the horizon clips some
 * triangles), one at a vertex and one on a shared edge's line; each receiver's triangles in a
 * shuffled order, so that an edge's angle is found by either of its triangles first. */
#include "check.h"
#include "recon/polygon_irradiance.h"
#include "recon/shared_triangles.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

enum { TRIS = 2 + 6 + 1 + 2, RECEIVERS = 4000 };

static uint32_t rng(uint32_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 17, *s ^= *s << 5;
    return *s;
}

static double uniform(uint32_t *s, double lo, double hi) { return lo + (hi - lo) * (double)(rng(s) >> 8) / 16777216.0; }

static void set(double t[3][3], double ax, double ay, double az, double bx, double by, double bz, double cx, double cy,
                double cz)
{
    const double v[9] = {ax, ay, az, bx, by, bz, cx, cy, cz};
    for (int k = 0; k < 9; ++k) t[k / 3][k % 3] = v[k];
}

int main(void)
{
    double tri[TRIS][3][3];
    /* a quad at y = 3 */
    set(tri[0], -1, 3, -1, 1, 3, -1, 1, 3, 1);
    set(tri[1], -1, 3, -1, 1, 3, 1, -1, 3, 1);
    /* a fan of six round (2, 2.5, 0), tilted */
    for (int k = 0; k < 6; ++k) {
        double a0 = k * M_PI / 3.0, a1 = (k + 1) * M_PI / 3.0;
        set(tri[2 + k], 2, 2.5, 0, 2 + cos(a0), 2.5 + 0.3 * sin(a0), sin(a0), 2 + cos(a1), 2.5 + 0.3 * sin(a1), sin(a1));
    }
    set(tri[8], -3, 1, 2, -2, 1.5, 2, -3, 2, 3);
    /* two triangles sharing (0, 4, 0) but with a -0 in one copy */
    set(tri[9], 0, 4, 0, 1, 4, 0.5, 0.5, 4, 1);
    set(tri[10], -0.0, 4, 0, 0.5, 4, 1, -0.5, 4, 1);
    SharedTriangles *s = shared_triangles_create(TRIS, (const double(*)[3][3])tri);
    SharedTrianglesAt *at = s ? shared_triangles_at_create(s) : NULL;
    CHECK(s && at);
    if (!s || !at) CHECK_DONE();
    uint32_t st = 99;
    long compared = 0, differ = 0, clipped = 0, lit = 0;
    for (int r = 0; r < RECEIVERS; ++r) {
        double p[3] = {uniform(&st, -4, 4), uniform(&st, -1, 5), uniform(&st, -3, 3)};
        double n[3] = {uniform(&st, -1, 1), uniform(&st, -0.2, 1), uniform(&st, -1, 1)};
        if (r == 0) memcpy(p, tri[2][0], sizeof p);                       /* at the fan's centre */
        if (r == 1) p[0] = 2 + 2 * cos(0.0), p[1] = 2.5, p[2] = 0;        /* on a fan edge's line */
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) n[k] /= len;
        shared_triangles_receiver(at, p, n);
        int order[TRIS];
        for (int t = 0; t < TRIS; ++t) order[t] = t;
        for (int t = TRIS - 1; t > 0; --t) {
            int u = (int)(rng(&st) % (uint32_t)(t + 1)), x = order[t];
            order[t] = order[u], order[u] = x;
        }
        for (int q = 0; q < TRIS; ++q) {
            int t = order[q];
            double want = polygon_projected_solid_angle(p, n, (const double(*)[3])tri[t], 3);
            double got = shared_triangles_phi(s, at, t);
            ++compared;
            differ += memcmp(&want, &got, sizeof want) != 0;
            lit += want > 0.0;
            int below = 0;
            for (int k = 0; k < 3; ++k)
                below += n[0] * (tri[t][k][0] - p[0]) + n[1] * (tri[t][k][1] - p[1]) + n[2] * (tri[t][k][2] - p[2]) < 0.0;
            clipped += below > 0 && below < 3;
        }
    }
    printf("%ld triangle evaluations (%ld lit, %ld straddling the horizon): %ld differ\n", compared, lit, clipped, differ);
    CHECK(differ == 0);
    CHECK(lit > compared / 4 && clipped > 100);
    shared_triangles_at_destroy(at);
    shared_triangles_destroy(s);
    CHECK_DONE();
}
