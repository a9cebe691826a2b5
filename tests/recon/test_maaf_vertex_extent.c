/* maaf_vertex_extent_along against the plain loop over every vertex, bit for bit: the tree of
 * boxes may pass a node over only when none of its vertices can change an extreme, so the four
 * extremes must be exactly the plain loop's floats. Point sets that stress the bounds: a
 * latitude-longitude sphere (every vertex on its hull, a pole ring of equal vertices), a bent
 * grid, a flat grid (no thickness across it), a line, one point repeated, a random cloud, a
 * small mesh far from the origin (float rounding large against its size), sets holding NaN and
 * infinite vertices, and sizes around a leaf; axes turning slowly from call to call (a mesh's
 * triangles in order: each call starts at the last one's extremes) and in random directions (as
 * floats, not exactly unit), centres at the set's middle, near it and far from it. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/maaf/maaf_vertex_extent.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;

static double uniform(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) * 0x1p-53;
}

/* two unit directions across the unit normal n, as floats (their length 1 to float rounding) */
static void axes_across(const double n[3], float t1[3], float t2[3])
{
    double a[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    double u[3] = {n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]};
    double len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int k = 0; k < 3; ++k) u[k] /= len;
    double v[3] = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
    for (int k = 0; k < 3; ++k) t1[k] = (float)u[k], t2[k] = (float)v[k];
}

/* a random direction and a second one across it */
static void random_axes(float t1[3], float t2[3])
{
    double z = 2.0 * uniform() - 1.0, phi = 2.0 * M_PI * uniform(), r = sqrt(fmax(0.0, 1.0 - z * z));
    double n[3] = {r * cos(phi), r * sin(phi), z};
    axes_across(n, t1, t2);
}

/* call c of a slow sweep: axes turning a little from one call to the next, as a mesh's triangles'
 * do in order (the tree starts each call at the leaves of the last one's extremes) */
static void sweeping_axes(int c, float t1[3], float t2[3])
{
    double a = 0.004 * c, b = 0.6 * sin(0.0013 * c);
    double n[3] = {cos(a) * cos(b), sin(a) * cos(b), sin(b)};
    axes_across(n, t1, t2);
}

static int same_float(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* calls random axis pairs and centres against the plain loop; the number that differ */
static int check_set(const char *what, const float (*v)[3], int n, int calls)
{
    MaafVertexExtent *x = maaf_vertex_extent_create(v, n);
    CHECK(x != NULL);
    if (!x) return 1;
    double mid[3] = {0.0, 0.0, 0.0}, span = 0.0;
    int finite = 0;
    for (int i = 0; i < n; ++i)
        if (isfinite(v[i][0] + v[i][1] + v[i][2])) {
            for (int k = 0; k < 3; ++k) mid[k] += v[i][k];
            finite++;
        }
    for (int k = 0; k < 3; ++k) mid[k] = finite ? mid[k] / finite : 0.0;
    for (int i = 0; i < n; ++i)
        if (isfinite(v[i][0] + v[i][1] + v[i][2]))
            for (int k = 0; k < 3; ++k) span = fmax(span, fabs(v[i][k] - mid[k]));
    int differ = 0;
    for (int c = 0; c < calls; ++c) {
        float t1[3], t2[3], centre[3], lo[2], hi[2], plo[2], phi[2];
        /* the first half in a slow sweep, the rest at random */
        if (2 * c < calls)
            sweeping_axes(c, t1, t2);
        else
            random_axes(t1, t2);
        /* a third of the centres at the middle, a third up to twice the set's size away, a third
         * thousands of times its size away (the offsets' rounding then dwarfs the set) */
        double away = c % 3 == 0 ? 0.0 : c % 3 == 1 ? 2.0 : 5000.0;
        for (int k = 0; k < 3; ++k) centre[k] = (float)(mid[k] + (2.0 * uniform() - 1.0) * away * span);
        maaf_vertex_extent_along(x, centre, t1, t2, lo, hi);
        maaf_vertex_extent_plain(v, n, centre, t1, t2, plo, phi);
        int d = !same_float(lo[0], plo[0]) || !same_float(lo[1], plo[1]) || !same_float(hi[0], phi[0]) || !same_float(hi[1], phi[1]);
        if (d) printf("  call %d: tree %.9g %.9g %.9g %.9g, plain %.9g %.9g %.9g %.9g; t1 %.9g %.9g %.9g t2 %.9g %.9g %.9g\n", c, lo[0], hi[0], lo[1], hi[1], plo[0], phi[0], plo[1], phi[1], t1[0], t1[1], t1[2], t2[0], t2[1], t2[2]);
        differ += d;
    }
    printf("%-34s %6d vertices, %d calls: %d differ\n", what, n, calls, differ);
    maaf_vertex_extent_destroy(x);
    return differ;
}

int main(void)
{
    enum { MAX = 40000 };
    float (*v)[3] = malloc(MAX * sizeof *v);
    int n, differ = 0;
    /* a latitude-longitude sphere, its poles rings of equal vertices */
    n = 0;
    for (int i = 0; i <= 60; ++i)
        for (int j = 0; j < 64; ++j) {
            double th = M_PI * i / 60, ph = 2.0 * M_PI * j / 64;
            v[n][0] = (float)(0.3 + 0.5 * sin(th) * cos(ph)), v[n][1] = (float)(2.2 + 0.5 * cos(th));
            v[n][2] = (float)(0.4 + 0.5 * sin(th) * sin(ph)), n++;
        }
    differ += check_set("sphere", (const float(*)[3])v, n, 3000);
    /* a half cylinder and a flat grid */
    n = 0;
    for (int j = 0; j <= 80; ++j)
        for (int i = 0; i <= 80; ++i) {
            double a = M_PI * i / 80;
            v[n][0] = (float)(-0.8 * cos(a)), v[n][1] = (float)(2.6 - 0.5 * sin(a)), v[n][2] = (float)(-0.7 + 1.3 * j / 80), n++;
        }
    differ += check_set("half cylinder", (const float(*)[3])v, n, 2000);
    for (int i = 0; i < n; ++i) v[i][1] = 2.5f;
    differ += check_set("flat grid", (const float(*)[3])v, n, 2000);
    /* a line, and one point repeated */
    n = 3000;
    for (int i = 0; i < n; ++i) v[i][0] = (float)(0.001 * i), v[i][1] = (float)(0.5 - 0.0002 * i), v[i][2] = 1.0f;
    differ += check_set("line", (const float(*)[3])v, n, 1000);
    for (int i = 0; i < n; ++i) v[i][0] = 0.25f, v[i][1] = -1.5f, v[i][2] = 3.0f;
    differ += check_set("one point", (const float(*)[3])v, n, 1000);
    /* a random cloud */
    n = 20000;
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) v[i][k] = (float)(4.0 * uniform() - 2.0);
    differ += check_set("random cloud", (const float(*)[3])v, n, 2000);
    /* a small bumpy patch far from the origin: the floats' rounding is large against its size */
    n = 0;
    for (int j = 0; j < 100; ++j)
        for (int i = 0; i < 100; ++i)
            v[n][0] = (float)(12345.0 + 0.001 * i), v[n][1] = (float)(-9876.5 + 1e-5 * sin(0.7 * i + 0.3 * j)),
            v[n][2] = (float)(5000.0 + 0.001 * j), n++;
    differ += check_set("far from the origin", (const float(*)[3])v, n, 3000);
    /* NaN and infinite vertices among the sphere's */
    n = 0;
    for (int i = 0; i <= 40; ++i)
        for (int j = 0; j < 40; ++j) {
            double th = M_PI * i / 40, ph = 2.0 * M_PI * j / 40;
            v[n][0] = (float)(sin(th) * cos(ph)), v[n][1] = (float)cos(th), v[n][2] = (float)(sin(th) * sin(ph)), n++;
        }
    v[77][1] = NAN, v[500][0] = INFINITY, v[901][2] = -INFINITY;
    differ += check_set("with NaN and infinite vertices", (const float(*)[3])v, n, 2000);
    /* sizes about a leaf */
    for (int size = 1; size <= 40; size += 3) {
        for (int i = 0; i < size; ++i)
            for (int k = 0; k < 3; ++k) v[i][k] = (float)(uniform() - 0.5);
        char what[64];
        snprintf(what, sizeof what, "%d random vertices", size);
        differ += check_set(what, (const float(*)[3])v, size, 300);
    }
    CHECK(differ == 0);
    CHECK(maaf_vertex_extent_create((const float(*)[3])v, 0) == NULL);
    free(v);
    CHECK_DONE();
}
