/* A curved mesh emitter's projected solid angle through its facing parts' boundaries (see
 * emitter_facing.h). */
#include "recon/emitter_facing.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/morton_order.h"
#include "recon/polygon_irradiance.h"
#include "recon/shared_triangles.h"

enum { LEAF = 4, STACK = 64 }; /* triangles a leaf; the traversal's stack (two entries a level) */

/* Margins: a node is taken whole only when its sphere clears the horizon by this share of its
 * distance and size, and its facing by this angle (radians), far above the rounding of the tests. */
#define HORIZON_MARGIN_REL 1e-9
#define FACING_MARGIN_RAD 1e-7

typedef struct {
    double c[3], r;      /* bounding sphere of its triangles' vertices (r infinite: unknown) */
    double axis[3];      /* the cone of its triangles' unit normals: within alpha of axis */
    double alpha;        /* radians; >= pi / 2: no cone (or a degenerate triangle inside) */
    double sin_a, cos_a; /* of alpha plus FACING_MARGIN_RAD */
    int begin, end;      /* its triangles (sorted order) */
    int ebegin, eend;    /* its boundary edges: bedge[ebegin .. eend) */
} Node;

struct EmitterFacing {
    int tris, leaves;
    bool two_sided;
    double (*tri)[3][3]; /* per sorted triangle: its corners */
    SharedTriangles *shared; /* the same triangles' vertices, edges and Lambert terms */
    double (*nrm)[3];    /* its unit normal (0: no area) */
    double *size;        /* its longest edge */
    int *orig;           /* its index in the triangles create was given */
    Node *node;          /* node k (1-based) has children 2k, 2k + 1; leaf j is node leaves + j */
    int *bedge;          /* 3 t + k: sorted triangle t's edge from corner k to k + 1 */
    int (*twin)[3];      /* the sorted triangle across each edge, wound the other way (-1: none) */
};

/* A receiver's parts: each triangle's label (which sum it joins), and the nodes and single
 * triangles labelled into the two sums, whose edges are read once every label is set. */
enum { ALONE = 0, FRONT = 1, BACK = 2 };

struct EmitterFacingAt {
    SharedTrianglesAt *shared; /* the receiver's vertex heights, directions, edge angles */
    unsigned char *label;      /* per sorted triangle */
    int *part, parts;     /* node i (> 0) or single triangle -1 - t, labelled FRONT or BACK */
};

static void sub3(const double a[3], const double b[3], double out[3])
{
    for (int k = 0; k < 3; ++k) out[k] = a[k] - b[k];
}

/* The bounding sphere and normal cone of the sorted triangles [begin, end). */
static void node_bounds(const EmitterFacing *f, Node *nd)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, sum[3] = {0.0, 0.0, 0.0};
    bool degenerate = false;
    for (int t = nd->begin; t < nd->end; ++t) {
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) lo[a] = fmin(lo[a], f->tri[t][k][a]), hi[a] = fmax(hi[a], f->tri[t][k][a]);
        degenerate = degenerate || polygon_dot3(f->nrm[t], f->nrm[t]) == 0.0;
        for (int a = 0; a < 3; ++a) sum[a] += f->nrm[t][a];
    }
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) nd->c[a] = 0.5 * (lo[a] + hi[a]), d2 += (hi[a] - lo[a]) * (hi[a] - lo[a]);
    nd->r = 0.5 * sqrt(d2) * (1.0 + 1e-12);
    if (!isfinite(nd->r) || !isfinite(nd->c[0] + nd->c[1] + nd->c[2])) nd->r = INFINITY, nd->c[0] = nd->c[1] = nd->c[2] = 0.0;
    double len = sqrt(polygon_dot3(sum, sum));
    nd->alpha = M_PI; /* no cone */
    if (degenerate || !(len > 0.0) || !isfinite(len)) return;
    for (int a = 0; a < 3; ++a) nd->axis[a] = sum[a] / len;
    double cos_min = 1.0;
    for (int t = nd->begin; t < nd->end; ++t) cos_min = fmin(cos_min, polygon_dot3(nd->axis, f->nrm[t]));
    if (cos_min > 0.0) nd->alpha = acos(fmin(cos_min, 1.0));
    nd->sin_a = sin(nd->alpha + FACING_MARGIN_RAD), nd->cos_a = cos(nd->alpha + FACING_MARGIN_RAD);
}

EmitterFacing *emitter_facing_create(int count, const double (*tri)[3][3], bool two_sided)
{
    if (count < 1) return NULL;
    EmitterFacing *f = calloc(1, sizeof *f);
    size_t n = (size_t)count;
    double(*centroid)[3] = malloc(n * sizeof *centroid);
    int *twin = malloc(3 * n * sizeof *twin), *first_use = NULL;
    if (f) {
        f->tris = count, f->two_sided = two_sided;
        f->tri = malloc(n * sizeof *f->tri);
        f->nrm = malloc(n * sizeof *f->nrm), f->twin = malloc(n * sizeof *f->twin);
        f->size = malloc(n * sizeof *f->size), f->orig = malloc(n * sizeof *f->orig);
        f->leaves = 1;
        while (f->leaves < (count + LEAF - 1) / LEAF) f->leaves *= 2;
        f->node = calloc(2 * (size_t)f->leaves, sizeof *f->node);
    }
    if (!f || !centroid || !twin || !f->tri || !f->nrm || !f->twin || !f->size || !f->orig || !f->node) {
        free(centroid), free(twin);
        emitter_facing_destroy(f);
        return NULL;
    }
    /* the triangles in Morton order of their centroids */
    for (size_t t = 0; t < n; ++t)
        for (int a = 0; a < 3; ++a) centroid[t][a] = (tri[t][0][a] + tri[t][1][a] + tri[t][2][a]) / 3.0;
    int *order = morton_order(count, (const double(*)[3])centroid);
    free(centroid);
    if (!order) {
        free(twin);
        emitter_facing_destroy(f);
        return NULL;
    }
    for (size_t s = 0; s < n; ++s) {
        int t = order[s];
        f->orig[s] = t;
        memcpy(f->tri[s], tri[t], sizeof f->tri[s]);
        double e1[3], e2[3], *m = f->nrm[s];
        sub3(tri[t][1], tri[t][0], e1), sub3(tri[t][2], tri[t][0], e2);
        m[0] = e1[1] * e2[2] - e1[2] * e2[1], m[1] = e1[2] * e2[0] - e1[0] * e2[2], m[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double len = sqrt(polygon_dot3(m, m));
        for (int a = 0; a < 3; ++a) m[a] = len > 0.0 && isfinite(len) ? m[a] / len : 0.0;
        f->size[s] = 0.0;
        for (int k = 0; k < 3; ++k) {
            double e[3];
            sub3(tri[t][(k + 1) % 3], tri[t][k], e);
            f->size[s] = fmax(f->size[s], sqrt(polygon_dot3(e, e)));
        }
    }
    free(order);
    /* the sorted triangles' shared vertices and edges, and each directed edge's twin: the one
     * other triangle that runs the same edge the other way (-1 when there is none, or the edge is
     * not shared so) */
    f->shared = shared_triangles_create(count, (const double(*)[3][3])f->tri);
    int edges = f->shared ? shared_triangles_edge_count(f->shared) : 0;
    int *uses = f->shared ? calloc(edges > 0 ? (size_t)edges : 1, sizeof *uses) : NULL;
    first_use = uses ? malloc((edges > 0 ? (size_t)edges : 1) * sizeof *first_use) : NULL;
    if (!first_use) {
        free(uses), free(twin);
        emitter_facing_destroy(f);
        return NULL;
    }
    for (size_t q = 0; q < 3 * n; ++q) twin[q] = -1;
    for (int t = 0; t < count; ++t) {
        int vert[3], edge[3];
        shared_triangles_corners(f->shared, t, vert, edge);
        for (int k = 0; k < 3; ++k)
            if (uses[edge[k]]++ == 0) first_use[edge[k]] = 3 * t + k;
    }
    for (int t = 0; t < count; ++t) {
        int vert[3], edge[3];
        shared_triangles_corners(f->shared, t, vert, edge);
        for (int k = 0; k < 3; ++k) {
            int q0 = first_use[edge[k]], t0 = q0 / 3, v0[3], e0[3];
            if (uses[edge[k]] != 2 || t0 == t) continue; /* unshared, used thrice or more, or the first use itself */
            shared_triangles_corners(f->shared, t0, v0, e0);
            if (v0[q0 % 3] == vert[(k + 1) % 3]) twin[q0] = t, twin[3 * t + k] = t0; /* run the other way */
        }
    }
    free(uses), free(first_use);
    /* the nodes: ranges of sorted triangles, their bounds and the edges leaving them */
    for (int j = 0; j < f->leaves; ++j) {
        Node *nd = &f->node[f->leaves + j];
        nd->begin = j * LEAF < count ? j * LEAF : count;
        nd->end = nd->begin + LEAF < count ? nd->begin + LEAF : count;
    }
    for (int i = f->leaves - 1; i >= 1; --i) f->node[i].begin = f->node[2 * i].begin, f->node[i].end = f->node[2 * i + 1].end;
    size_t total = 0;
    for (int i = 1; i < 2 * f->leaves; ++i) {
        Node *nd = &f->node[i];
        nd->ebegin = (int)total;
        for (int q = 3 * nd->begin; q < 3 * nd->end; ++q) total += twin[q] < nd->begin || twin[q] >= nd->end;
        nd->eend = (int)total;
        if (nd->end > nd->begin) node_bounds(f, nd);
    }
    f->bedge = total > INT_MAX ? NULL : malloc((total ? total : 1) * sizeof *f->bedge);
    if (!f->bedge) {
        free(twin);
        emitter_facing_destroy(f);
        return NULL;
    }
    for (int i = 1; i < 2 * f->leaves; ++i) {
        const Node *nd = &f->node[i];
        int at = nd->ebegin;
        for (int q = 3 * nd->begin; q < 3 * nd->end; ++q)
            if (twin[q] < nd->begin || twin[q] >= nd->end) f->bedge[at++] = q;
    }
    for (size_t q = 0; q < 3 * n; ++q) f->twin[q / 3][q % 3] = twin[q];
    free(twin);
    return f;
}

void emitter_facing_destroy(EmitterFacing *f)
{
    if (!f) return;
    shared_triangles_destroy(f->shared);
    free(f->tri), free(f->nrm), free(f->node), free(f->bedge), free(f->twin);
    free(f->size), free(f->orig);
    free(f);
}

EmitterFacingAt *emitter_facing_at_create(const EmitterFacing *f)
{
    EmitterFacingAt *at = calloc(1, sizeof *at);
    if (at) {
        at->shared = shared_triangles_at_create(f->shared);
        /* parts: at most every node and every triangle */
        at->label = malloc((size_t)f->tris), at->part = malloc((2 * (size_t)f->leaves + (size_t)f->tris) * sizeof *at->part);
    }
    if (!at || !at->shared || !at->label || !at->part) {
        emitter_facing_at_destroy(at);
        return NULL;
    }
    return at;
}

void emitter_facing_at_destroy(EmitterFacingAt *at)
{
    if (!at) return;
    shared_triangles_at_destroy(at->shared);
    free(at->label), free(at->part);
    free(at);
}

/* Lambert's term of sorted triangle q / 3's edge from corner q % 3 to the next, both ends above
 * the horizon. */
static double edge_term(const EmitterFacing *f, EmitterFacingAt *at, int q)
{
    return shared_triangles_edge_term(f->shared, at->shared, q / 3, q % 3);
}

/* > 0: p in front of sorted triangle t's plane (by its winding), < 0 behind, 0 in it or no area */
static double facing(const EmitterFacing *f, int t, const double p[3])
{
    double c[3];
    for (int a = 0; a < 3; ++a) c[a] = (f->tri[t][0][a] + f->tri[t][1][a] + f->tri[t][2][a]) / 3.0;
    double d[3];
    sub3(p, c, d);
    return polygon_dot3(f->nrm[t], d);
}

/* Triangle t alone: its projected solid angle above the horizon, nothing from behind a one-sided
 * emitter. */
static double triangle_alone(const EmitterFacing *f, int t, const double p[3], const double n[3])
{
    if (!f->two_sided && !(facing(f, t, p) > 0.0)) return 0.0;
    return polygon_projected_solid_angle(p, n, (const double(*)[3])f->tri[t], 3);
}

double emitter_facing_phi_by_triangle(const EmitterFacing *f, const double p[3], const double n[3])
{
    double phi = 0.0;
    for (int t = 0; t < f->tris; ++t) phi += triangle_alone(f, t, p, n);
    return phi;
}

/* +1: every triangle of nd faces p from its front, -1 from its back, 0: not shown. The angle
 * from a triangle's normal to the direction from any of its points to p is at most g, the angle
 * from the cone's axis to the direction from the sphere's centre to p, plus the cone's half angle
 * alpha, plus the sphere's angular radius beta seen from p; all face p when that is below pi / 2,
 * that is when cos g > sin(alpha + margin + beta). */
static int node_side(const Node *nd, const double d[3], double dist)
{
    if (!(nd->alpha < 0.5 * M_PI) || !(dist > nd->r)) return 0;
    double cos_g = -polygon_dot3(nd->axis, d) / dist; /* d: from p to the centre */
    double sin_b = nd->r / dist, cos_b = sqrt(fmax(0.0, 1.0 - sin_b * sin_b));
    if (nd->cos_a * cos_b - nd->sin_a * sin_b <= 0.0) return 0; /* alpha + margin + beta >= pi / 2 */
    double bound = nd->sin_a * cos_b + nd->cos_a * sin_b;
    if (cos_g > bound) return 1;
    if (-cos_g > bound) return -1;
    return 0;
}

/* The edges of a labelled part (node i > 0, or single triangle -1 - i) whose other side is not in
 * the same sum: the boundary of the region that sum covers. */
static double part_edges(const EmitterFacing *f, EmitterFacingAt *at, int i, int label)
{
    double s = 0.0;
    if (i > 0) {
        const Node *nd = &f->node[i];
        for (int e = nd->ebegin; e < nd->eend; ++e) {
            int q = f->bedge[e], other = f->twin[q / 3][q % 3];
            if (other < 0 || at->label[other] != label) s += edge_term(f, at, q);
        }
        return s;
    }
    int t = -1 - i;
    for (int k = 0; k < 3; ++k) {
        int other = f->twin[t][k];
        if (other < 0 || at->label[other] != label) s += edge_term(f, at, 3 * t + k);
    }
    return s;
}

/* A triangle's distance from its plane that rounding may put on either side, over its size plus
 * its distance from the receiver: below it the triangle is summed alone. */
#define PLANE_CLEAR_REL 1e-7

double emitter_facing_phi(const EmitterFacing *f, EmitterFacingAt *at, const double p[3], const double n[3],
                          double (*alone_fn)(void *ctx, int t), void *ctx)
{
    shared_triangles_receiver(at->shared, p, n);
    /* label every triangle: FRONT or BACK when it is wholly above the horizon and faces p from
     * that side (its signed sum then joins that side's), else ALONE (summed by itself, or
     * nothing); a whole node at once where its bounds show it */
    double alone = 0.0;
    at->parts = 0;
    int stack[STACK], top = 0;
    stack[top++] = 1;
    while (top > 0) {
        int i = stack[--top];
        const Node *nd = &f->node[i];
        if (nd->end <= nd->begin) continue;
        double d[3];
        sub3(nd->c, p, d);
        double dist = sqrt(polygon_dot3(d, d)), hc = polygon_dot3(n, d), margin = HORIZON_MARGIN_REL * (dist + nd->r);
        int side = hc - nd->r > margin ? node_side(nd, d, dist) : 0;
        /* wholly below the horizon (every triangle clipped away) or the back of a one-sided
         * emitter: nothing */
        bool nothing = hc + nd->r < -margin || (side < 0 && !f->two_sided);
        if (nothing || side != 0) {
            unsigned char label = nothing ? ALONE : side > 0 ? FRONT : BACK;
            memset(at->label + nd->begin, label, (size_t)(nd->end - nd->begin));
            if (!nothing) at->part[at->parts++] = i;
            continue;
        }
        if (i < f->leaves) {
            stack[top++] = 2 * i + 1;
            stack[top++] = 2 * i;
            continue;
        }
        for (int t = nd->begin; t < nd->end; ++t) {
            int v[3], e[3];
            shared_triangles_corners(f->shared, t, v, e);
            double fc = facing(f, t, p), rel[3];
            sub3(f->tri[t][0], p, rel);
            bool clear = fabs(fc) > PLANE_CLEAR_REL * (f->size[t] + sqrt(polygon_dot3(rel, rel)));
            bool above = shared_triangles_height(f->shared, at->shared, v[0]) > 0.0 &&
                         shared_triangles_height(f->shared, at->shared, v[1]) > 0.0 &&
                         shared_triangles_height(f->shared, at->shared, v[2]) > 0.0;
            if (above && clear && (fc > 0.0 || f->two_sided)) {
                at->label[t] = fc > 0.0 ? FRONT : BACK;
                at->part[at->parts++] = -1 - t;
            } else {
                at->label[t] = ALONE;
                alone += alone_fn ? alone_fn(ctx, f->orig[t]) : triangle_alone(f, t, p, n);
            }
        }
    }
    /* each side's signed sum over the boundary of the region it labelled */
    double front = 0.0, back = 0.0;
    for (int k = 0; k < at->parts; ++k) {
        int i = at->part[k];
        int label = at->label[i > 0 ? f->node[i].begin : -1 - i];
        double s = part_edges(f, at, i, label);
        if (label == FRONT) front += s;
        else back += s;
    }
    return polygon_phi_of_sum(front) + polygon_phi_of_sum(back) + alone;
}
