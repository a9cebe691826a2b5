/* A planar mesh emitter's boundary for Lambert's formula (see emitter_boundary.h). */
#include "recon/emitter_boundary.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/polygon_irradiance.h"
#include "recon/vertex_weld.h"

/* Planarity: every triangle's unit normal within ~1e-4 rad of the first's, and every vertex
 * within 1e-6 of the surface's size from the first triangle's plane. Looser and the interior
 * terms would no longer cancel to within rounding; a curved mesh keeps its triangles' sum. */
#define NORMAL_COS_MIN (1.0 - 5e-9)
#define PLANE_TOL_REL 1e-6

struct EmitterBoundary {
    int verts, edges, loops;
    double (*pos)[3];  /* the boundary's vertices */
    int (*edge)[2];    /* each boundary edge, from .. to, in its triangle's winding */
    int *loop_vert;    /* the edges chained into closed loops: loop k is the vertices */
    int *loop_start;   /* loop_vert[loop_start[k] .. loop_start[k + 1]), each to the next, the last to the first */
};

typedef struct {
    int lo, hi; /* the edge's vertices, lower index first */
    int forward; /* 1: the triangle runs lo -> hi; 0: hi -> lo */
} EdgeKey;

static int cmp_edge(const void *a, const void *b)
{
    const EdgeKey *x = a, *y = b;
    if (x->lo != y->lo) return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi) return x->hi < y->hi ? -1 : 1;
    return x->forward - y->forward;
}

static void sub3(const double a[3], const double b[3], double out[3])
{
    for (int k = 0; k < 3; ++k) out[k] = a[k] - b[k];
}

/* The triangle's unit normal (its winding's), false when it has no area. */
static bool unit_normal(const double t[3][3], double n[3])
{
    double e1[3], e2[3];
    sub3(t[1], t[0], e1), sub3(t[2], t[0], e2);
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double len = sqrt(polygon_dot3(n, n));
    if (!(len > 0.0) || !isfinite(len)) return false;
    for (int k = 0; k < 3; ++k) n[k] /= len;
    return true;
}

static bool planar(int count, const double (*tri)[3][3])
{
    double n0[3], n[3], lo[3], hi[3];
    if (!unit_normal(tri[0], n0)) return false;
    for (int k = 0; k < 3; ++k) lo[k] = hi[k] = tri[0][0][k];
    for (int t = 0; t < count; ++t) {
        if (!unit_normal(tri[t], n) || !(polygon_dot3(n, n0) >= NORMAL_COS_MIN)) return false;
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k) lo[k] = fmin(lo[k], tri[t][v][k]), hi[k] = fmax(hi[k], tri[t][v][k]);
    }
    double size[3];
    sub3(hi, lo, size);
    double tol = PLANE_TOL_REL * sqrt(polygon_dot3(size, size));
    for (int t = 0; t < count; ++t)
        for (int v = 0; v < 3; ++v) {
            double d[3];
            sub3(tri[t][v], tri[0][0], d);
            if (!(fabs(polygon_dot3(d, n0)) <= tol)) return false;
        }
    return true;
}

/* The boundary edges chained into closed loops (each vertex leaves by one of its outgoing edges
 * not yet walked; where a vertex has two, either choice closes, and the loops' sum of edge terms
 * is the same). False when a vertex's edges in and out do not pair up, or out of memory. */
static bool chain_loops(EmitterBoundary *b)
{
    int *out_first = malloc((size_t)b->verts * sizeof *out_first), *out_next = malloc((size_t)b->edges * sizeof *out_next);
    int *balance = calloc((size_t)b->verts, sizeof *balance);
    b->loop_vert = malloc((size_t)b->edges * sizeof *b->loop_vert);
    b->loop_start = malloc(((size_t)b->edges + 1) * sizeof *b->loop_start);
    bool ok = out_first && out_next && balance && b->loop_vert && b->loop_start;
    for (int v = 0; ok && v < b->verts; ++v) out_first[v] = -1;
    for (int e = 0; ok && e < b->edges; ++e) {
        out_next[e] = out_first[b->edge[e][0]], out_first[b->edge[e][0]] = e;
        ++balance[b->edge[e][0]], --balance[b->edge[e][1]];
    }
    for (int v = 0; ok && v < b->verts; ++v) ok = balance[v] == 0;
    int walked = 0;
    for (int v0 = 0; ok && v0 < b->verts; ++v0)
        while (out_first[v0] >= 0) { /* a loop from v0 */
            b->loop_start[b->loops++] = walked;
            int v = v0;
            do {
                int e = out_first[v];
                if (e < 0 || walked == b->edges) { /* cannot happen with every vertex balanced */
                    ok = false;
                    break;
                }
                out_first[v] = out_next[e];
                b->loop_vert[walked++] = v;
                v = b->edge[e][1];
            } while (v != v0);
            if (!ok) break;
        }
    if (ok) b->loop_start[b->loops] = walked;
    ok = ok && walked == b->edges;
    free(out_first), free(out_next), free(balance);
    return ok;
}

EmitterBoundary *emitter_boundary_create(int count, const double (*tri)[3][3])
{
    if (count < 2 || !planar(count, tri)) return NULL;
    size_t slots = 3 * (size_t)count;
    EdgeKey *ek = malloc(slots * sizeof *ek);
    int *vert = malloc(slots * sizeof *vert), *used = calloc(slots, sizeof *used);
    EmitterBoundary *b = calloc(1, sizeof *b);
    if (b) b->pos = malloc(slots * sizeof *b->pos), b->edge = malloc(slots * sizeof *b->edge);
    bool ok = ek && vert && used && b && b->pos && b->edge;
    int verts = 0, interior = 0;
    double(*pos)[3] = ok ? malloc(slots * sizeof *pos) : NULL;
    ok = ok && pos;
    if (ok) {
        verts = vertex_weld(count, tri, pos, vert);
        ok = verts >= 0;
    }
    if (ok) {
        /* edges: an interior edge twice, once each way; a boundary edge once */
        for (size_t q = 0; q < slots; ++q) {
            int a = vert[q], c = vert[3 * (q / 3) + (q % 3 + 1) % 3];
            ek[q] = (EdgeKey){a < c ? a : c, a < c ? c : a, a < c};
        }
        qsort(ek, slots, sizeof *ek, cmp_edge);
        for (size_t q = 0; ok && q < slots;) {
            size_t r = q;
            while (r < slots && ek[r].lo == ek[q].lo && ek[r].hi == ek[q].hi) ++r;
            /* (no edge has one vertex at both ends: planar() refused triangles without area) */
            if (r - q == 2 && ek[q].forward != ek[q + 1].forward) ++interior;          /* cancels */
            else if (r - q == 1) {                                                      /* the boundary */
                int from = ek[q].forward ? ek[q].lo : ek[q].hi, to = ek[q].forward ? ek[q].hi : ek[q].lo;
                b->edge[b->edges][0] = from, b->edge[b->edges][1] = to, ++b->edges;
                used[from] = used[to] = 1;
            } else ok = false; /* three triangles on an edge, or two wound against each other */
            q = r;
        }
    }
    ok = ok && b->edges > 0 && b->edges < interior;
    if (ok) { /* keep the boundary's vertices only, renumbered */
        for (int v = 0; v < verts; ++v) {
            if (!used[v]) continue;
            memcpy(b->pos[b->verts], pos[v], sizeof pos[v]);
            used[v] = ++b->verts; /* its new index + 1 */
        }
        for (int e = 0; e < b->edges; ++e) b->edge[e][0] = used[b->edge[e][0]] - 1, b->edge[e][1] = used[b->edge[e][1]] - 1;
    }
    ok = ok && chain_loops(b);
    free(ek), free(vert), free(used), free(pos);
    if (!ok) {
        emitter_boundary_destroy(b);
        return NULL;
    }
    return b;
}

void emitter_boundary_destroy(EmitterBoundary *b)
{
    if (!b) return;
    free(b->pos), free(b->edge), free(b->loop_vert), free(b->loop_start);
    free(b);
}

int emitter_boundary_edge_count(const EmitterBoundary *b) { return b ? b->edges : 0; }

/* One clipped loop's running sum: the previous point's unit direction and the first one's. */
typedef struct {
    double first[3], prev[3];
    int points;
    bool at_receiver; /* a point at p itself: the caller sums the triangles */
} LoopWalk;

/* The next point of the clipped loop (relative to p): the edge from the previous one adds its term. */
static void walk_to(LoopWalk *w, const double rel[3], const double n[3], double *sum)
{
    double len = sqrt(polygon_dot3(rel, rel)), u[3];
    if (!(len > 0.0)) {
        w->at_receiver = true;
        return;
    }
    for (int k = 0; k < 3; ++k) u[k] = rel[k] / len;
    if (w->points++ == 0) {
        memcpy(w->first, u, sizeof u);
    } else {
        double c[3], s = polygon_edge_cross(w->prev, u, c);
        if (s > 0.0) *sum += atan2(s, polygon_dot3(w->prev, u)) * polygon_dot3(c, n) / s;
    }
    memcpy(w->prev, u, sizeof u);
}

bool emitter_boundary_phi(const EmitterBoundary *b, const double p[3], const double n[3], double *phi)
{
    double sum = 0.0;
    for (int k = 0; k < b->loops; ++k) {
        /* Sutherland-Hodgman against the receiver's horizon, as polygon_projected_solid_angle clips
         * a triangle, streamed: each kept or crossing point closes an edge of the clipped loop. On a
         * loop that crosses the horizon several times the clipped loop runs back and forth along
         * the horizon between its pieces; those runs enclose no area and their terms cancel. */
        LoopWalk w = {.points = 0};
        int lo = b->loop_start[k], hi = b->loop_start[k + 1];
        for (int i = lo; i < hi; ++i) {
            double a[3], c[3];
            sub3(b->pos[b->loop_vert[i]], p, a), sub3(b->pos[b->loop_vert[i + 1 < hi ? i + 1 : lo]], p, c);
            double ha = polygon_dot3(n, a), hc = polygon_dot3(n, c);
            if (ha >= 0.0) walk_to(&w, a, n, &sum);
            if ((ha >= 0.0) != (hc >= 0.0)) {
                double t = ha / (ha - hc), x[3];
                for (int q = 0; q < 3; ++q) x[q] = a[q] + t * (c[q] - a[q]);
                walk_to(&w, x, n, &sum);
            }
        }
        if (w.at_receiver) return false;
        if (w.points >= 2) { /* close the loop */
            double c[3], s = polygon_edge_cross(w.prev, w.first, c);
            if (s > 0.0) sum += atan2(s, polygon_dot3(w.prev, w.first)) * polygon_dot3(c, n) / s;
        }
    }
    *phi = polygon_phi_of_sum(sum);
    return true;
}
