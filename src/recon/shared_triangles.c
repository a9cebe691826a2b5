/* Lambert's formula over triangles with shared vertices and edges (see shared_triangles.h). */
#include "recon/shared_triangles.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/polygon_irradiance.h"
#include "recon/vertex_weld.h"

struct SharedTriangles {
    int count, verts, edges;
    double (*tri)[3][3]; /* as given: the clipped triangles' path */
    double (*pos)[3];    /* per vertex */
    int (*vert)[3];      /* per triangle: its vertices */
    int (*edge)[3];      /* per triangle: the edge from its vertex k to vertex k + 1 */
};

struct SharedTrianglesAt {
    double p[3], n[3];
    int verts, edges;
    unsigned stamp;                 /* the receiver's: a vertex or edge so stamped holds its values */
    unsigned *vert_stamp, *dir_stamp, *edge_stamp; /* h; len and u; theta */
    double (*u)[3];                 /* unit direction from p to the vertex */
    double *h, *len;                /* n . (vertex - p) (>= 0: above the horizon), |vertex - p| */
    double *theta;                  /* the edge's angle */
};

typedef struct {
    int lo, hi, slot;
} EdgeKey;

static int cmp_edge(const void *a, const void *b)
{
    const EdgeKey *x = a, *y = b;
    if (x->lo != y->lo) return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi) return x->hi < y->hi ? -1 : 1;
    return x->slot - y->slot;
}

SharedTriangles *shared_triangles_create(int count, const double (*tri)[3][3])
{
    SharedTriangles *s = calloc(1, sizeof *s);
    size_t slots = 3 * (size_t)(count > 0 ? count : 0);
    EdgeKey *ek = malloc((slots ? slots : 1) * sizeof *ek);
    if (s) {
        s->count = count > 0 ? count : 0;
        s->tri = malloc((slots ? slots : 1) * sizeof(double[3]));
        s->pos = malloc((slots ? slots : 1) * sizeof *s->pos);
        s->vert = malloc((slots ? slots : 1) * sizeof(int));
        s->edge = malloc((slots ? slots : 1) * sizeof(int));
    }
    if (!s || !ek || !s->tri || !s->pos || !s->vert || !s->edge) {
        free(ek);
        shared_triangles_destroy(s);
        return NULL;
    }
    memcpy(s->tri, tri, slots * sizeof(double[3]));
    s->verts = vertex_weld(s->count, tri, s->pos, &s->vert[0][0]);
    if (s->verts < 0) {
        free(ek);
        shared_triangles_destroy(s);
        return NULL;
    }
    /* edges: the same two vertices either way round are one edge */
    for (size_t q = 0; q < slots; ++q) {
        int a = s->vert[q / 3][q % 3], b = s->vert[q / 3][(q % 3 + 1) % 3];
        ek[q] = (EdgeKey){a < b ? a : b, a < b ? b : a, (int)q};
    }
    qsort(ek, slots, sizeof *ek, cmp_edge);
    for (size_t q = 0; q < slots; ++q) {
        if (q == 0 || ek[q].lo != ek[q - 1].lo || ek[q].hi != ek[q - 1].hi) s->edges++;
        s->edge[ek[q].slot / 3][ek[q].slot % 3] = s->edges - 1;
    }
    free(ek);
    return s;
}

void shared_triangles_destroy(SharedTriangles *s)
{
    if (!s) return;
    free(s->tri), free(s->pos), free(s->vert), free(s->edge);
    free(s);
}

SharedTrianglesAt *shared_triangles_at_create(const SharedTriangles *s)
{
    SharedTrianglesAt *at = calloc(1, sizeof *at);
    size_t v = s->verts > 0 ? (size_t)s->verts : 1, e = s->edges > 0 ? (size_t)s->edges : 1;
    if (at) {
        at->vert_stamp = calloc(v, sizeof *at->vert_stamp), at->edge_stamp = calloc(e, sizeof *at->edge_stamp);
        at->dir_stamp = calloc(v, sizeof *at->dir_stamp);
        at->u = malloc(v * sizeof *at->u), at->h = malloc(v * sizeof *at->h), at->len = malloc(v * sizeof *at->len);
        at->theta = malloc(e * sizeof *at->theta);
    }
    if (!at || !at->vert_stamp || !at->dir_stamp || !at->edge_stamp || !at->u || !at->h || !at->len || !at->theta) {
        shared_triangles_at_destroy(at);
        return NULL;
    }
    at->verts = s->verts, at->edges = s->edges;
    return at;
}

void shared_triangles_at_destroy(SharedTrianglesAt *at)
{
    if (!at) return;
    free(at->vert_stamp), free(at->dir_stamp), free(at->edge_stamp), free(at->u), free(at->h), free(at->len), free(at->theta);
    free(at);
}

void shared_triangles_receiver(SharedTrianglesAt *at, const double p[3], const double n[3])
{
    memcpy(at->p, p, sizeof at->p), memcpy(at->n, n, sizeof at->n);
    if (++at->stamp == 0) { /* wrapped: every stamp could look current */
        memset(at->vert_stamp, 0, (size_t)at->verts * sizeof *at->vert_stamp);
        memset(at->dir_stamp, 0, (size_t)at->verts * sizeof *at->dir_stamp);
        memset(at->edge_stamp, 0, (size_t)at->edges * sizeof *at->edge_stamp);
        at->stamp = 1;
    }
}

/* Vertex v's horizon height for the current receiver, as polygon_projected_solid_angle finds it. */
static double height(const SharedTriangles *s, SharedTrianglesAt *at, int v)
{
    if (at->vert_stamp[v] != at->stamp) {
        double rel[3];
        for (int k = 0; k < 3; ++k) rel[k] = s->pos[v][k] - at->p[k];
        at->h[v] = polygon_dot3(at->n, rel);
        at->vert_stamp[v] = at->stamp;
    }
    return at->h[v];
}

/* Vertex v's distance and unit direction for the current receiver, as polygon_projected_solid_angle
 * finds them for an unclipped vertex (the direction read only where the distance is > 0). Apart
 * from the height: a caller that asks only whether a triangle is above the horizon pays no
 * square root. */
static void direction(const SharedTriangles *s, SharedTrianglesAt *at, int v)
{
    if (at->dir_stamp[v] == at->stamp) return;
    double rel[3];
    for (int k = 0; k < 3; ++k) rel[k] = s->pos[v][k] - at->p[k];
    at->len[v] = sqrt(polygon_dot3(rel, rel));
    for (int k = 0; k < 3; ++k) at->u[v][k] = rel[k] / at->len[v];
    at->dir_stamp[v] = at->stamp;
}

/* edge i of triangle t, both ends' directions known */
static double edge_term(const SharedTriangles *s, SharedTrianglesAt *at, int t, int i)
{
    const int *v = s->vert[t];
    const double *a = at->u[v[i]], *b = at->u[v[(i + 1) % 3]];
    double c[3], sn = polygon_edge_cross(a, b, c);
    if (!(sn > 0.0)) return 0.0; /* coincident directions */
    int e = s->edge[t][i];
    if (at->edge_stamp[e] != at->stamp) at->theta[e] = atan2(sn, polygon_dot3(a, b)), at->edge_stamp[e] = at->stamp;
    return at->theta[e] * polygon_dot3(c, at->n) / sn;
}

double shared_triangles_phi(const SharedTriangles *s, SharedTrianglesAt *at, int t)
{
    const int *v = s->vert[t];
    if (!(height(s, at, v[0]) >= 0.0 && height(s, at, v[1]) >= 0.0 && height(s, at, v[2]) >= 0.0)) /* the horizon clips it */
        return polygon_projected_solid_angle(at->p, at->n, (const double(*)[3])s->tri[t], 3);
    for (int k = 0; k < 3; ++k) {
        direction(s, at, v[k]);
        if (!(at->len[v[k]] > 0.0)) return 0.0; /* a vertex at the receiver itself */
    }
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) sum += edge_term(s, at, t, i);
    return polygon_phi_of_sum(sum);
}

int shared_triangles_vertex_count(const SharedTriangles *s) { return s->verts; }

int shared_triangles_edge_count(const SharedTriangles *s) { return s->edges; }

void shared_triangles_corners(const SharedTriangles *s, int t, int vert[3], int edge[3])
{
    for (int k = 0; k < 3; ++k) vert[k] = s->vert[t][k], edge[k] = s->edge[t][k];
}

double shared_triangles_height(const SharedTriangles *s, SharedTrianglesAt *at, int v) { return height(s, at, v); }

double shared_triangles_edge_term(const SharedTriangles *s, SharedTrianglesAt *at, int t, int k)
{
    direction(s, at, s->vert[t][k]), direction(s, at, s->vert[t][(k + 1) % 3]);
    return edge_term(s, at, t, k);
}
