/* A mesh light's vertex extent along axes, by branch and bound (see maaf_vertex_extent.h). */
#include "recon/maaf/maaf_vertex_extent.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "recon/morton_order.h"

enum { LEAF = 16, STACK = 64 }; /* vertices a leaf; the traversal's stack (two entries a level, at most 27 levels) */

/* A node of the tree: a box about the vertices [begin, end), centred on their mean c, along
 * their principal axes (orthonormal), every vertex within half[k] of c along axis k (half[0] < 0:
 * an empty node). A patch of a smooth surface is thin across its plane (and a run along a curve
 * thin across the curve), so near the extreme along a direction, where the surface faces that
 * direction, the box reaches little further than its vertices do; a sphere about the same patch
 * would reach its whole radius further. */
typedef struct {
    double c[3], axis[3][3], half[3];
    int begin, end;
} Node;

struct MaafVertexExtent {
    float (*verts)[3];
    int n, leaves; /* leaves: a power of two; node k (1-based) has children 2k and 2k + 1, leaf j is node leaves + j */
    Node *node;
    int last_leaf[4]; /* the leaf that last moved each extreme (axis a, least / greatest: 2a, 2a + 1), 0: none */
};

/* Widens [lo, hi] to take x (as fminf / fmaxf: a NaN is passed over), inline so loops vectorise. */
static inline void widen(float x, float *lo, float *hi)
{
    *lo = x < *lo ? x : *lo;
    *hi = x > *hi ? x : *hi;
}

static inline float dot3(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void widen_range(const float (*verts)[3], int begin, int end, const float centre[3], const float t1[3],
                        const float t2[3], float lo[2], float hi[2])
{
    for (int v = begin; v < end; ++v) {
        float d[3] = {verts[v][0] - centre[0], verts[v][1] - centre[1], verts[v][2] - centre[2]};
        widen(dot3(d, t1), &lo[0], &hi[0]);
        widen(dot3(d, t2), &lo[1], &hi[1]);
    }
}

/* An extreme that is a zero takes the sign of whichever zero came first (-0 < +0 is false), which
 * depends on the order the vertices are visited in: both paths give +0 instead (x + 0 is +0 for
 * either zero and x for any other x, infinities and NaN included). */
static void zeros_unsigned(float lo[2], float hi[2])
{
    for (int a = 0; a < 2; ++a) lo[a] += 0.0f, hi[a] += 0.0f;
}

void maaf_vertex_extent_plain(const float (*verts)[3], int n, const float centre[3], const float t1[3],
                              const float t2[3], float lo[2], float hi[2])
{
    lo[0] = lo[1] = INFINITY;
    hi[0] = hi[1] = -INFINITY;
    widen_range(verts, 0, n, centre, t1, t2, lo, hi);
    zeros_unsigned(lo, hi);
}

/* The eigenvectors of the symmetric 3 x 3 matrix m, as the rows of axis (Jacobi rotations; any
 * orthonormal axes keep the bounds true, these keep them tight). */
static void principal_axes(double m[3][3], double axis[3][3])
{
    double v[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
    for (int sweep = 0; sweep < 12; ++sweep)
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (!(fabs(m[p][q]) > 1e-300)) continue;
                double theta = 0.5 * (m[q][q] - m[p][p]) / m[p][q];
                double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), sn = t * c;
                for (int k = 0; k < 3; ++k) { /* m <- J^T m J, v <- v J */
                    double a = m[k][p], b = m[k][q];
                    m[k][p] = c * a - sn * b, m[k][q] = sn * a + c * b;
                }
                for (int k = 0; k < 3; ++k) {
                    double a = m[p][k], b = m[q][k];
                    m[p][k] = c * a - sn * b, m[q][k] = sn * a + c * b;
                }
                for (int k = 0; k < 3; ++k) {
                    double a = v[k][p], b = v[k][q];
                    v[k][p] = c * a - sn * b, v[k][q] = sn * a + c * b;
                }
            }
    for (int a = 0; a < 3; ++a) {
        double len = sqrt(v[0][a] * v[0][a] + v[1][a] * v[1][a] + v[2][a] * v[2][a]);
        for (int k = 0; k < 3; ++k) axis[a][k] = len > 0.0 && isfinite(len) ? v[k][a] / len : (a == k);
    }
}

/* The box of the vertices [begin, end): their mean, principal axes and half extents. */
static void box(const float (*verts)[3], Node *nd)
{
    int count = nd->end - nd->begin;
    nd->half[0] = -1.0;
    if (count <= 0) return;
    double m[3] = {0.0, 0.0, 0.0}, cov[3][3] = {{0.0}};
    for (int v = nd->begin; v < nd->end; ++v)
        for (int a = 0; a < 3; ++a) m[a] += verts[v][a];
    for (int a = 0; a < 3; ++a) nd->c[a] = m[a] / count;
    for (int v = nd->begin; v < nd->end; ++v)
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) cov[a][b] += (verts[v][a] - nd->c[a]) * (verts[v][b] - nd->c[b]);
    bool finite = isfinite(nd->c[0] + nd->c[1] + nd->c[2]);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) finite = finite && isfinite(cov[a][b]);
    if (!finite) { /* a NaN or infinite vertex: unbounded, the node is always visited */
        for (int a = 0; a < 3; ++a) {
            nd->c[a] = 0.0, nd->half[a] = INFINITY;
            for (int k = 0; k < 3; ++k) nd->axis[a][k] = a == k;
        }
        return;
    }
    principal_axes(cov, nd->axis);
    double half[3] = {0.0, 0.0, 0.0}, len = 0.0;
    for (int v = nd->begin; v < nd->end; ++v) {
        double d[3] = {verts[v][0] - nd->c[0], verts[v][1] - nd->c[1], verts[v][2] - nd->c[2]};
        for (int a = 0; a < 3; ++a) half[a] = fmax(half[a], fabs(d[0] * nd->axis[a][0] + d[1] * nd->axis[a][1] + d[2] * nd->axis[a][2]));
        len = fmax(len, fabs(d[0]) + fabs(d[1]) + fabs(d[2]));
    }
    /* the axes are orthonormal to about 2^-50: a vertex's offset along them is then off by at
     * most that much of its length, which 2^-40 of the largest length covers */
    for (int a = 0; a < 3; ++a) nd->half[a] = half[a] * (1.0 + 0x1p-40) + 0x1p-40 * len;
}

MaafVertexExtent *maaf_vertex_extent_create(const float (*verts)[3], int n)
{
    if (n < 1) return NULL;
    MaafVertexExtent *x = calloc(1, sizeof *x);
    if (x) {
        x->n = n;
        x->leaves = 1;
        while (x->leaves < (n + LEAF - 1) / LEAF) x->leaves *= 2;
        x->verts = malloc((size_t)n * sizeof *x->verts);
        x->node = malloc(2 * (size_t)x->leaves * sizeof *x->node);
    }
    if (!x || !x->verts || !x->node) {
        maaf_vertex_extent_destroy(x);
        return NULL;
    }
    /* Morton order: runs of LEAF vertices (and the runs of runs above them) are compact */
    double(*pt)[3] = malloc((size_t)n * sizeof *pt);
    for (int v = 0; pt && v < n; ++v)
        for (int a = 0; a < 3; ++a) pt[v][a] = verts[v][a];
    int *order = pt ? morton_order(n, (const double(*)[3])pt) : NULL;
    free(pt);
    if (!order) {
        maaf_vertex_extent_destroy(x);
        return NULL;
    }
    for (int v = 0; v < n; ++v) memcpy(x->verts[v], verts[order[v]], sizeof x->verts[v]);
    free(order);
    /* the leaves: runs of LEAF vertices in Morton order; a node above them: its leaves' runs */
    for (int j = 0; j < x->leaves; ++j) {
        Node *nd = &x->node[x->leaves + j];
        nd->begin = j * LEAF < n ? j * LEAF : n;
        nd->end = nd->begin + LEAF < n ? nd->begin + LEAF : n;
        box((const float(*)[3])x->verts, nd);
    }
    for (int i = x->leaves - 1; i >= 1; --i) {
        Node *nd = &x->node[i];
        nd->begin = x->node[2 * i].begin, nd->end = x->node[2 * i + 1].end;
        box((const float(*)[3])x->verts, nd);
    }
    return x;
}

void maaf_vertex_extent_destroy(MaafVertexExtent *x)
{
    if (!x) return;
    free(x->verts), free(x->node);
    free(x);
}

/* The greatest value of s (v - centre) . t a vertex of node nd can give (s = +-1, t's length tn):
 * its mean's, plus the box's reach along t (the sum over its axes of half extent times |t . axis|),
 * widened by the float evaluation's error: d = v - centre and the dot product round at most a few
 * units of 2^-24 of |v - centre|_1 |t| each; 2^-16 of it is far more than they can reach. */
static inline double node_reach(const Node *nd, const float centre[3], const float t[3], double tn, double s)
{
    double dc[3] = {nd->c[0] - centre[0], nd->c[1] - centre[1], nd->c[2] - centre[2]};
    double mid = dc[0] * t[0] + dc[1] * t[1] + dc[2] * t[2], reach = 0.0, r = 0.0;
    for (int a = 0; a < 3; ++a) {
        reach += nd->half[a] * fabs(nd->axis[a][0] * t[0] + nd->axis[a][1] * t[1] + nd->axis[a][2] * t[2]);
        r += nd->half[a];
    }
    return s * mid + reach + 0x1p-16 * (fabs(dc[0]) + fabs(dc[1]) + fabs(dc[2]) + 2.0 * r) * tn;
}

/* Widens the four extremes by leaf i's vertices, noting the leaf as the last to move each it moves. */
static void visit_leaf(MaafVertexExtent *x, int i, const float centre[3], const float *t[2], float lo[2], float hi[2])
{
    float before[4] = {lo[0], hi[0], lo[1], hi[1]};
    widen_range((const float(*)[3])x->verts, x->node[i].begin, x->node[i].end, centre, t[0], t[1], lo, hi);
    float after[4] = {lo[0], hi[0], lo[1], hi[1]};
    for (int e = 0; e < 4; ++e)
        if (after[e] != before[e]) x->last_leaf[e] = i;
}

/* Branch and bound for one of the four extremes (axis a, sense s: +1 the greatest, -1 the least),
 * the more promising child first; every vertex of a visited leaf widens all four. A node is
 * passed over only when no vertex in it can pass the extreme found so far (a NaN bound never
 * passes one over). */
static void extreme(MaafVertexExtent *x, const float centre[3], const float *t[2], const double tn[2], int a,
                    double s, float lo[2], float hi[2])
{
    int stack[STACK], top = 0;
    stack[top++] = 1;
    while (top > 0) {
        const Node *nd = &x->node[stack[--top]];
        int i = (int)(nd - x->node);
        if (nd->half[0] < 0.0) continue;
        double best = s > 0.0 ? hi[a] : -(double)lo[a];
        if (node_reach(nd, centre, t[a], tn[a], s) <= best) continue;
        if (i >= x->leaves) {
            visit_leaf(x, i, centre, t, lo, hi);
            continue;
        }
        double r0 = node_reach(&x->node[2 * i], centre, t[a], tn[a], s);
        double r1 = node_reach(&x->node[2 * i + 1], centre, t[a], tn[a], s);
        bool first_is_0 = !(r1 > r0); /* pushed last, popped first */
        stack[top++] = first_is_0 ? 2 * i + 1 : 2 * i;
        stack[top++] = first_is_0 ? 2 * i : 2 * i + 1;
    }
}

void maaf_vertex_extent_along(MaafVertexExtent *x, const float centre[3], const float t1[3], const float t2[3],
                              float lo[2], float hi[2])
{
    lo[0] = lo[1] = INFINITY;
    hi[0] = hi[1] = -INFINITY;
    const float *t[2] = {t1, t2};
    /* A mesh's triangles come in order over its surface, so the next one's axes are close to this
     * one's and so are its extremes: the leaves that held the last call's, visited first, give
     * bounds near the final ones from the start (most of the search is then proving them: 1.1-1.4x
     * on large curved meshes, docs/benchmarks.md). Their
     * vertices are candidates like any other; the result is the same minimum and maximum. */
    int seeds[4];
    memcpy(seeds, x->last_leaf, sizeof seeds);
    for (int e = 0; e < 4; ++e) {
        bool again = seeds[e] <= 0;
        for (int f = 0; f < e; ++f) again = again || seeds[f] == seeds[e];
        if (!again) visit_leaf(x, seeds[e], centre, t, lo, hi);
    }
    double tn[2];
    for (int a = 0; a < 2; ++a) tn[a] = sqrt((double)t[a][0] * t[a][0] + (double)t[a][1] * t[a][1] + (double)t[a][2] * t[a][2]);
    for (int a = 0; a < 2; ++a) {
        extreme(x, centre, t, tn, a, 1.0, lo, hi);
        extreme(x, centre, t, tn, a, -1.0, lo, hi);
    }
    zeros_unsigned(lo, hi);
}
