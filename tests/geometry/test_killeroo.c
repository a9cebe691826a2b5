/* The real pbrt-v4 killeroo (a loopsubdiv, 8316 triangles, levels 1) through our
 * subdivision. The three arrays are pulled out of the file with a minimal extractor (this
 * test must not depend on the scene parser). Checks: counts, limit points in the cage's
 * bounding box, unit normals agreeing with the winding, and agreement with pbrt-v4's own
 * Loop rules re-derived here: at interior vertices of valence 3 and 6, where pbrt-v4's
 * vertex weights equal Loop's, the limit positions must match to float precision; at other
 * valences (pbrt-v4 uses Warren's beta = 3/(8n)) the deviation is reported.
 * Skipped (exit 77, which ctest reports as skipped, not passed) where ../shared/pbrt-v4-scenes
 * is absent. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "geometry/mesh.h"

static char *slurp(const char *path, long *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)*size + 1);
    if (fread(s, 1, (size_t)*size, f) != (size_t)*size) *size = 0;
    s[*size] = '\0';
    fclose(f);
    return s;
}

/* Numbers between the '[' after `key` and the next ']'. */
static double *numbers_after(const char *text, const char *key, int *count)
{
    const char *s = strstr(text, key);
    *count = 0;
    if (!s || !(s = strchr(s, '['))) return NULL;
    const char *end = strchr(s, ']');
    s++;
    int cap = 1024;
    double *v = malloc(sizeof *v * (size_t)cap);
    while (s < end) {
        char *next;
        double x = strtod(s, &next);
        if (next == s) { s++; continue; }
        if (*count == cap) v = realloc(v, sizeof *v * (size_t)(cap *= 2));
        v[(*count)++] = x;
        s = next;
    }
    return v;
}

typedef struct { uint32_t lo, hi; int opp[2]; int nopp; } Edge;
static int edge_cmp(const void *a, const void *b)
{
    const Edge *x = a, *y = b;
    if (x->lo != y->lo) return x->lo < y->lo ? -1 : 1;
    return x->hi < y->hi ? -1 : (x->hi > y->hi);
}

typedef struct { double x, y, z; } D3;
static D3 d3(vec3 v) { return (D3){v.x, v.y, v.z}; }
static D3 dadd(D3 a, D3 b) { return (D3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static D3 dscale(D3 a, double s) { return (D3){a.x * s, a.y * s, a.z * s}; }
static double ddist(D3 a, D3 b) { return sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z)); }

static int find_edge(const Edge *e, int n, uint32_t a, uint32_t b)
{
    Edge key = {a < b ? a : b, a < b ? b : a, {0, 0}, 0};
    const Edge *hit = bsearch(&key, e, (size_t)n, sizeof *e, edge_cmp);
    return hit ? (int)(hit - e) : -1;
}

int main(void)
{
    const char *src = getenv("WEDGE_SOURCE_DIR");
    char path[1024];
    snprintf(path, sizeof path, "%s/../shared/pbrt-v4-scenes/killeroos/geometry/killeroo.pbrt", src ? src : "../..");
    long size = 0;
    char *text = slurp(path, &size);
    if (!text) {
        printf("SKIPPED: %s is absent (the pbrt-v4 scenes live outside the repository)\n", path);
        return 77;
    }
    int np, ni, nl;
    double *Pd = numbers_after(text, "\"point3 P\"", &np);
    double *Id = numbers_after(text, "\"integer indices\"", &ni);
    double *Ld = numbers_after(text, "\"integer levels\"", &nl);
    free(text);
    CHECK(np > 0 && np % 3 == 0 && ni % 3 == 0 && nl == 1);
    if (!(np > 0 && np % 3 == 0 && ni % 3 == 0 && nl == 1)) CHECK_DONE();
    int V = np / 3, F = ni / 3, levels = (int)Ld[0];
    float *P = malloc(sizeof *P * (size_t)np);
    int32_t *I = malloc(sizeof *I * (size_t)ni);
    for (int i = 0; i < np; i++) P[i] = (float)Pd[i];
    for (int i = 0; i < ni; i++) I[i] = (int32_t)Id[i];
    CHECK(V == 4290 && F == 8316 && levels == 1); /* as the scenes' README describes it */

    Param items[3] = {
        {.type = PARAM_INTEGER, .name = "levels", .count = 1, .ints = &levels},
        {.type = PARAM_POINT3, .name = "P", .count = np, .floats = P},
        {.type = PARAM_INTEGER, .name = "indices", .count = ni, .ints = I},
    };
    ShapeDesc shape = {.type = "loopsubdiv", .params = {items, 3}, .material = -1, .area_light = -1,
                       .object = -1, .base_dir = ".", .loc = {path, 1, 1}};
    Diag err = {0};
    CHECK(mesh_triangle_count(&shape, &err) == 33264);
    TriMesh m;
    bool ok = mesh_from_shape(&shape, &m, &err);
    CHECK(ok);
    if (!ok) {
        fprintf(stderr, "%s\n", err.message);
        CHECK_DONE();
    }
    CHECK(m.triangle_count == 33264);

    /* edges of the cage, with their opposite vertices (brute force via sorting) */
    Edge *E = malloc(sizeof *E * (size_t)ni);
    for (int f = 0; f < F; f++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = (uint32_t)I[3 * f + k], b = (uint32_t)I[3 * f + (k + 1) % 3];
            E[3 * f + k] = (Edge){a < b ? a : b, a < b ? b : a, {I[3 * f + (k + 2) % 3], -1}, 1};
        }
    qsort(E, (size_t)ni, sizeof *E, edge_cmp);
    int ne = 0;
    for (int i = 0; i < ni; i++) {
        if (ne > 0 && E[ne - 1].lo == E[i].lo && E[ne - 1].hi == E[i].hi) {
            if (E[ne - 1].nopp < 2) E[ne - 1].opp[E[ne - 1].nopp] = E[i].opp[0];
            E[ne - 1].nopp++;
        } else {
            E[ne++] = E[i];
        }
    }
    /* one level of Loop adds a vertex per edge */
    CHECK(m.vertex_count == V + ne);

    /* bounding box of the cage: Loop's limit weights are positive, so every limit point is
     * a convex combination of cage points */
    vec3 lo = v3s(1e30f), hi = v3s(-1e30f);
    for (int i = 0; i < V; i++) {
        vec3 p = v3(P[3 * i], P[3 * i + 1], P[3 * i + 2]);
        lo = v3(fminf(lo.x, p.x), fminf(lo.y, p.y), fminf(lo.z, p.z));
        hi = v3(fmaxf(hi.x, p.x), fmaxf(hi.y, p.y), fmaxf(hi.z, p.z));
    }
    float diag = v3_length(v3_sub(hi, lo));
    int outside = 0, bad_normal = 0, bad_wind = 0;
    for (int i = 0; i < m.vertex_count; i++) {
        vec3 p = m.p[i];
        float eps = 1e-5f * diag;
        outside += !(p.x >= lo.x - eps && p.y >= lo.y - eps && p.z >= lo.z - eps && p.x <= hi.x + eps &&
                     p.y <= hi.y + eps && p.z <= hi.z + eps);
        bad_normal += !(fabsf(v3_length(m.n[i]) - 1.0f) < 1e-5f);
    }
    for (int t = 0; t < m.triangle_count; t++) {
        const uint32_t *c = m.index + 3 * t;
        vec3 ng = v3_cross(v3_sub(m.p[c[1]], m.p[c[0]]), v3_sub(m.p[c[2]], m.p[c[0]]));
        vec3 ns = v3_add(v3_add(m.n[c[0]], m.n[c[1]]), m.n[c[2]]);
        bad_wind += v3_dot(ng, ns) < 0;
    }
    CHECK(outside == 0);
    CHECK(bad_normal == 0);
    CHECK(bad_wind == 0);

    /* pbrt-v4's rules (loopsubdiv.cpp) for the limit of each original vertex after one
     * level, re-derived: even vertex v1 = (1 - n b) v + b sum(ring) with b = 3/16 (n = 3)
     * or 3/(8n); odd vertex on edge (v, r) = 3/8 (v + r) + 1/8 (c + d); limit
     * = (1 - n g) v1 + g sum(odd ring), g = 1/(n + 3/(8 b)). Interior manifold vertices only. */
    int *valence = calloc((size_t)V, sizeof *valence);
    int *boundary = calloc((size_t)V, sizeof *boundary);
    for (int e = 0; e < ne; e++) {
        valence[E[e].lo]++;
        valence[E[e].hi]++;
        if (E[e].nopp != 2) boundary[E[e].lo] = boundary[E[e].hi] = 1;
    }
    D3 *ring_sum = calloc((size_t)V, sizeof *ring_sum), *odd_sum = calloc((size_t)V, sizeof *odd_sum);
    for (int e = 0; e < ne; e++) {
        D3 a = d3(v3(P[3 * E[e].lo], P[3 * E[e].lo + 1], P[3 * E[e].lo + 2]));
        D3 b = d3(v3(P[3 * E[e].hi], P[3 * E[e].hi + 1], P[3 * E[e].hi + 2]));
        ring_sum[E[e].lo] = dadd(ring_sum[E[e].lo], b);
        ring_sum[E[e].hi] = dadd(ring_sum[E[e].hi], a);
        if (E[e].nopp != 2) continue;
        int c = E[e].opp[0], d = E[e].opp[1];
        D3 cd = dadd(d3(v3(P[3 * c], P[3 * c + 1], P[3 * c + 2])), d3(v3(P[3 * d], P[3 * d + 1], P[3 * d + 2])));
        D3 odd = dadd(dscale(dadd(a, b), 3.0 / 8.0), dscale(cd, 1.0 / 8.0));
        odd_sum[E[e].lo] = dadd(odd_sum[E[e].lo], odd);
        odd_sum[E[e].hi] = dadd(odd_sum[E[e].hi], odd);
    }
    double max_same = 0, max_other = 0, sum_other = 0;
    int n_same = 0, n_other = 0, n_boundary = 0;
    for (int v = 0; v < V; v++) {
        if (boundary[v]) { n_boundary++; continue; }
        int n = valence[v];
        double beta = n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n);
        double gamma = 1.0 / (n + 3.0 / (8.0 * beta));
        D3 p = d3(v3(P[3 * v], P[3 * v + 1], P[3 * v + 2]));
        D3 v1 = dadd(dscale(p, 1 - n * beta), dscale(ring_sum[v], beta));
        D3 lim = dadd(dscale(v1, 1 - n * gamma), dscale(odd_sum[v], gamma));
        /* the first V vertices of OpenSubdiv's refined level are the children of the cage
         * vertices, in order */
        double dev = ddist(lim, d3(m.p[v])) / diag;
        if (n == 3 || n == 6) { max_same = fmax(max_same, dev); n_same++; }
        else { max_other = fmax(max_other, dev); sum_other += dev; n_other++; }
    }
    printf("killeroo: %d cage vertices (%d boundary), %d edges; limit vs pbrt-v4 rules, relative to the "
           "bounding-box diagonal: valence 3/6 max %.2e (%d vertices), other valences max %.2e mean %.2e "
           "(%d vertices)\n", V, n_boundary, ne, max_same, n_same, max_other,
           n_other ? sum_other / n_other : 0.0, n_other);
    CHECK(n_same > 0);
    CHECK(max_same < 1e-6); /* float rounding of coordinates ~1e-7 of the model size */

    /* boundary vertices with two boundary edges: pbrt-v4 pushes them to the limit with
     * weights 1/5 3/5 1/5, OpenSubdiv with the cubic B-spline's 1/6 4/6 1/6 (documented
     * difference); report how far apart that puts them */
    D3 *bsum = calloc((size_t)V, sizeof *bsum);
    int *bcount = calloc((size_t)V, sizeof *bcount);
    for (int e = 0; e < ne; e++) {
        if (E[e].nopp != 1) continue;
        uint32_t a = E[e].lo, b = E[e].hi;
        bsum[a] = dadd(bsum[a], d3(v3(P[3 * b], P[3 * b + 1], P[3 * b + 2])));
        bsum[b] = dadd(bsum[b], d3(v3(P[3 * a], P[3 * a + 1], P[3 * a + 2])));
        bcount[a]++, bcount[b]++;
    }
    double max_b = 0;
    for (int v = 0; v < V; v++) {
        if (bcount[v] != 2) continue;
        D3 p = d3(v3(P[3 * v], P[3 * v + 1], P[3 * v + 2]));
        D3 v1 = dadd(dscale(p, 0.75), dscale(bsum[v], 0.125));
        D3 odd = dadd(dscale(p, 1.0), dscale(bsum[v], 0.5)); /* o0 + o1 = p + (b0 + b1) / 2 */
        D3 pbrt = dadd(dscale(v1, 0.6), dscale(odd, 0.2));
        max_b = fmax(max_b, ddist(pbrt, d3(m.p[v])) / diag);
    }
    printf("killeroo: boundary limit points vs pbrt-v4's 1/5 rule: max deviation %.2e of the diagonal\n", max_b);
    free(bsum);
    free(bcount);

    /* Normal orientation against pbrt-v4's own tangent formula, at level 0 (limit of the
     * cage itself): for an interior vertex pbrt-v4 walks the one-ring through
     * nextVert/nextFace, which visits the neighbours clockwise (seen from the
     * counter-clockwise side), and takes N = S x T with S = sum cos(2 pi j/n) p_j,
     * T = sum sin(2 pi j/n) p_j. Our normals must point to the same side. */
    int zero = 0;
    items[0].ints = &zero;
    TriMesh m0;
    CHECK(mesh_from_shape(&shape, &m0, &err));
    int *first_face = malloc(sizeof *first_face * (size_t)V);
    for (int v = 0; v < V; v++) first_face[v] = -1;
    for (int f = 0; f < F; f++)
        for (int k = 0; k < 3; k++) first_face[I[3 * f + k]] = f;
    int agree = 0, disagree = 0;
    double sum_cos = 0;
    for (int v = 0; v < V; v++) {
        if (boundary[v] || first_face[v] < 0 || valence[v] < 3) continue;
        const int32_t *f = I + 3 * first_face[v];
        int at = f[0] == v ? 0 : (f[1] == v ? 1 : 2);
        int prev = f[(at + 2) % 3], cur = f[(at + 1) % 3], n = valence[v];
        D3 S = {0, 0, 0}, T = {0, 0, 0};
        bool ok_ring = true;
        for (int j = 0; j < n && ok_ring; j++) {
            D3 pj = d3(m0.p[cur]);
            S = dadd(S, dscale(pj, cos(2 * M_PI * j / n)));
            T = dadd(T, dscale(pj, sin(2 * M_PI * j / n)));
            int e = find_edge(E, ne, (uint32_t)v, (uint32_t)cur);
            if (e < 0 || E[e].nopp != 2) { ok_ring = false; break; }
            int next = E[e].opp[0] == prev ? E[e].opp[1] : E[e].opp[0];
            prev = cur;
            cur = next;
        }
        if (!ok_ring) continue;
        D3 N = {S.y * T.z - S.z * T.y, S.z * T.x - S.x * T.z, S.x * T.y - S.y * T.x};
        double len = sqrt(N.x * N.x + N.y * N.y + N.z * N.z);
        if (!(len > 0)) continue;
        double c = (N.x * m0.n[v].x + N.y * m0.n[v].y + N.z * m0.n[v].z) / len;
        if (c > 0) agree++; else disagree++;
        sum_cos += c;
    }
    printf("killeroo: level-0 normals vs pbrt-v4's S x T: %d agree, %d disagree, mean cosine %.5f\n",
           agree, disagree, agree + disagree ? sum_cos / (agree + disagree) : 0.0);
    CHECK(agree > 0 && disagree == 0);
    mesh_free(&m0);
    free(first_face);

    /* orientation: pbrt-v4's normals point away from the counter-clockwise side; report
     * which side of the killeroo that is (signed volume of the cage) */
    double vol = 0;
    for (int f = 0; f < F; f++) {
        D3 a = d3(v3(P[3 * I[3 * f]], P[3 * I[3 * f] + 1], P[3 * I[3 * f] + 2]));
        D3 b = d3(v3(P[3 * I[3 * f + 1]], P[3 * I[3 * f + 1] + 1], P[3 * I[3 * f + 1] + 2]));
        D3 c = d3(v3(P[3 * I[3 * f + 2]], P[3 * I[3 * f + 2] + 1], P[3 * I[3 * f + 2] + 2]));
        vol += (a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x)) / 6;
    }
    printf("killeroo: cage signed volume %.6g (%s-wound), so limit normals point %s\n", vol,
           vol > 0 ? "outward counter-clockwise" : "inward counter-clockwise", vol > 0 ? "inward" : "outward");

    mesh_free(&m);
    free(E); free(valence); free(boundary); free(ring_sum); free(odd_sum);
    free(P); free(I); free(Pd); free(Id); free(Ld);
    CHECK_DONE();
}
