/* Subdivision through OpenSubdiv: counts derived from Euler-style recurrences, limit points
 * inside the cage's convex hull, closed-form limit positions at level 0, boundary rule,
 * and the normal/winding orientation convention (pbrt-v4's, see subdiv.h). */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/vec.h"
#include "geometry/subdiv.h"

static vec3 vget(const float *a, int i) { return v3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }

/* Number of distinct undirected edges of a polygon mesh (brute force). */
static int count_edges(int face_count, const int *face_size, const int *index)
{
    int total = 0;
    for (int f = 0; f < face_count; f++) total += face_size ? face_size[f] : 3;
    int *a = malloc(sizeof(int) * (size_t)total), *b = malloc(sizeof(int) * (size_t)total);
    int n = 0, at = 0;
    for (int f = 0; f < face_count; f++) {
        int k = face_size ? face_size[f] : 3;
        for (int j = 0; j < k; j++) {
            int u = index[at + j], v = index[at + (j + 1) % k];
            int lo = u < v ? u : v, hi = u < v ? v : u;
            bool seen = false;
            for (int e = 0; e < n && !seen; e++) seen = a[e] == lo && b[e] == hi;
            if (!seen) a[n] = lo, b[n] = hi, n++;
        }
        at += k;
    }
    free(a);
    free(b);
    return n;
}

/* Checks orientation: every output triangle's counter-clockwise normal agrees with the
 * shading normals at its corners, and every normal has unit length. */
static void check_normals_and_winding(const SubdivOutput *o)
{
    int bad_len = 0, bad_wind = 0;
    for (int i = 0; i < o->vertex_count; i++)
        bad_len += fabsf(v3_length(vget(o->n, i)) - 1.0f) > 1e-5f;
    for (int t = 0; t < o->triangle_count; t++) {
        const uint32_t *c = o->index + 3 * t;
        vec3 a = vget(o->p, (int)c[0]), b = vget(o->p, (int)c[1]), d = vget(o->p, (int)c[2]);
        vec3 ng = v3_cross(v3_sub(b, a), v3_sub(d, a));
        vec3 ns = v3_add(v3_add(vget(o->n, (int)c[0]), vget(o->n, (int)c[1])), vget(o->n, (int)c[2]));
        bad_wind += v3_dot(ng, ns) <= 0;
    }
    CHECK(bad_len == 0);
    CHECK(bad_wind == 0);
}

/* Every limit point must satisfy n_f . (p - a_f) <= eps for every outward cage face plane. */
static int outside_hull(const SubdivOutput *o, int face_count, const int *face_size, const int *index,
                        const float *cage, float eps)
{
    int outside = 0;
    for (int i = 0; i < o->vertex_count; i++) {
        vec3 p = vget(o->p, i);
        int at = 0;
        for (int f = 0; f < face_count; f++) {
            int k = face_size ? face_size[f] : 3;
            vec3 a = vget(cage, index[at]), b = vget(cage, index[at + 1]), c = vget(cage, index[at + 2]);
            vec3 n = v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a)));
            if (v3_dot(n, v3_sub(p, a)) > eps) { outside++; break; }
            at += k;
        }
    }
    return outside;
}

/* Regular tetrahedron, faces counter-clockwise seen from outside. */
static const float TET_P[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const int TET_I[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};

static void tetrahedron_loop(void)
{
    /* the cage really is outward counter-clockwise */
    for (int f = 0; f < 4; f++) {
        vec3 a = vget(TET_P, TET_I[3 * f]), b = vget(TET_P, TET_I[3 * f + 1]), c = vget(TET_P, TET_I[3 * f + 2]);
        CHECK(v3_dot(v3_cross(v3_sub(b, a), v3_sub(c, a)), v3_add(v3_add(a, b), c)) > 0);
    }
    const int V = 4, E = count_edges(4, NULL, TET_I), F = 4;
    CHECK(E == 6);
    for (int L = 0; L <= 3; L++) {
        SubdivInput in = {SUBDIV_LOOP, L, V, TET_P, F, NULL, TET_I};
        SubdivOutput o;
        char msg[256];
        bool ok = subdiv_refine(&in, &o, msg, sizeof msg);
        CHECK(ok);
        if (!ok) { fprintf(stderr, "%s\n", msg); continue; }
        /* Loop on a closed triangle mesh: F_L = F 4^L, and since every level adds one
         * vertex per edge and E_L = 3 F_L / 2: V_L = V + E (4^L - 1) / 3. */
        long pow4 = 1L << (2 * L);
        CHECK(o.triangle_count == F * pow4);
        CHECK(o.triangle_count == subdiv_triangle_count(SUBDIV_LOOP, L, F, NULL));
        CHECK(o.vertex_count == V + E * (pow4 - 1) / 3);
        CHECK(outside_hull(&o, F, NULL, TET_I, TET_P, 1e-5f) == 0);
        check_normals_and_winding(&o);
        /* pbrt-v4 convention: normals face away from the counter-clockwise side, i.e. into
         * this convex, outward-wound solid */
        int outward = 0;
        for (int i = 0; i < o.vertex_count; i++) outward += v3_dot(vget(o.n, i), vget(o.p, i)) >= 0;
        CHECK(outward == 0);
        if (L == 0) {
            /* Loop limit mask (Loop 1987): p_inf = (1 - n g) p + g sum(ring), g = 1/(n + 3/(8 beta)),
             * beta(3) = 3/16 -> g = 1/5; the ring of a tetrahedron vertex sums to -p: p_inf = p/5.
             * By symmetry the limit normal is along -p. */
            for (int i = 0; i < 4; i++) {
                vec3 p = vget(TET_P, i), q = vget(o.p, i);
                CHECK_NEAR(v3_length(v3_sub(q, v3_scale(p, 0.2f))), 0.0, 1e-6);
                CHECK_NEAR(v3_dot(vget(o.n, i), v3_normalize(v3_neg(p))), 1.0, 1e-6);
            }
        }
        subdiv_output_free(&o);
    }
}

/* Cube [-1,1]^3 as six quads, counter-clockwise from outside. */
static const float CUBE_P[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                 -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
static const int CUBE_I[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 2, 3, 7, 6, 1, 2, 6, 5, 0, 4, 7, 3};
static const int CUBE_S[6] = {4, 4, 4, 4, 4, 4};

static void cube_catmull_clark(void)
{
    for (int f = 0; f < 6; f++) {
        const int *q = CUBE_I + 4 * f;
        vec3 a = vget(CUBE_P, q[0]), b = vget(CUBE_P, q[1]), c = vget(CUBE_P, q[2]);
        CHECK(v3_dot(v3_cross(v3_sub(b, a), v3_sub(c, a)), a) > 0);
    }
    /* Catmull-Clark on quads: each level adds a vertex per edge and per face;
     * E' = 2E + 4F (each edge splits, each quad adds 4 interior edges), F' = 4F. */
    long V = 8, E = count_edges(6, CUBE_S, CUBE_I), F = 6;
    CHECK(E == 12);
    for (int L = 0; L <= 3; L++) {
        SubdivInput in = {SUBDIV_CATMULL_CLARK, L, 8, CUBE_P, 6, CUBE_S, CUBE_I};
        SubdivOutput o;
        char msg[256];
        bool ok = subdiv_refine(&in, &o, msg, sizeof msg);
        CHECK(ok);
        if (!ok) { fprintf(stderr, "%s\n", msg); continue; }
        CHECK(o.vertex_count == V);
        CHECK(o.triangle_count == 2 * F);
        CHECK(o.triangle_count == subdiv_triangle_count(SUBDIV_CATMULL_CLARK, L, 6, CUBE_S));
        CHECK(outside_hull(&o, 6, CUBE_S, CUBE_I, CUBE_P, 1e-5f) == 0);
        check_normals_and_winding(&o);
        int outward = 0;
        for (int i = 0; i < o.vertex_count; i++) outward += v3_dot(vget(o.n, i), vget(o.p, i)) >= 0;
        CHECK(outward == 0);
        if (L == 0) {
            /* Catmull-Clark limit mask (Halstead et al. 1993): (n^2 v + 4 sum(edge nbrs) +
             * sum(face opposite)) / (n (n + 5)); corner of the cube, n = 3: (9 + 4 - 1)/24 v = v/2 */
            for (int i = 0; i < 8; i++)
                CHECK_NEAR(v3_length(v3_sub(vget(o.p, i), v3_scale(vget(CUBE_P, i), 0.5f))), 0.0, 1e-6);
        }
        subdiv_output_free(&o);
        long V2 = V + E + F, E2 = 2 * E + 4 * F, F2 = 4 * F;
        V = V2, E = E2, F = F2;
    }
}

/* An open 3x3-vertex grid on [0,2]^2 (z = 0), 8 triangles, counter-clockwise from +z.
 * Boundary edges are creases: the surface stays in the plane, inside the square, the
 * limit of a straight boundary stays on the boundary, and a corner vertex goes to
 * (p_prev + 4 p + p_next) / 6 (cubic B-spline crease rule). */
static void open_grid_boundary(void)
{
    float P[27];
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            P[3 * (3 * j + i)] = (float)i;
            P[3 * (3 * j + i) + 1] = (float)j;
            P[3 * (3 * j + i) + 2] = 0;
        }
    int I[24], n = 0;
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            int a = 3 * j + i, b = a + 1, c = a + 4, d = a + 3;
            I[n++] = a, I[n++] = b, I[n++] = c;
            I[n++] = a, I[n++] = c, I[n++] = d;
        }
    for (int L = 0; L <= 2; L++) {
        SubdivInput in = {SUBDIV_LOOP, L, 9, P, 8, NULL, I};
        SubdivOutput o;
        char msg[256];
        bool ok = subdiv_refine(&in, &o, msg, sizeof msg);
        CHECK(ok);
        if (!ok) { fprintf(stderr, "%s\n", msg); continue; }
        CHECK(o.triangle_count == 8 << (2 * L));
        int off_plane = 0, outside = 0, bad_normal = 0;
        for (int i = 0; i < o.vertex_count; i++) {
            vec3 p = vget(o.p, i);
            off_plane += fabsf(p.z) > 1e-6f;
            outside += p.x < -1e-6f || p.x > 2 + 1e-6f || p.y < -1e-6f || p.y > 2 + 1e-6f;
            bad_normal += fabsf(o.n[3 * i + 2] + 1.0f) > 1e-6f; /* (0,0,-1): pbrt-v4 side */
        }
        CHECK(off_plane == 0);
        CHECK(outside == 0);
        CHECK(bad_normal == 0);
        check_normals_and_winding(&o);
        if (L == 0) {
            /* edge midpoint (1,0) stays; corner (0,0) -> ((1,0) + (0,1)) / 6 */
            CHECK_NEAR(o.p[3 * 1], 1.0, 1e-6);
            CHECK_NEAR(o.p[3 * 1 + 1], 0.0, 1e-6);
            CHECK_NEAR(o.p[0], 1.0 / 6.0, 1e-6);
            CHECK_NEAR(o.p[1], 1.0 / 6.0, 1e-6);
        }
        subdiv_output_free(&o);
    }
}

/* Catmull-Clark on mixed polygons: a square pyramid (4 triangles + 1 quad). */
static void pyramid_mixed(void)
{
    const float P[15] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0, 0, 1.5f};
    const int S[5] = {4, 3, 3, 3, 3};
    const int I[16] = {0, 3, 2, 1, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    for (int L = 0; L <= 2; L++) {
        SubdivInput in = {SUBDIV_CATMULL_CLARK, L, 5, P, 5, S, I};
        SubdivOutput o;
        char msg[256];
        bool ok = subdiv_refine(&in, &o, msg, sizeof msg);
        CHECK(ok);
        if (!ok) { fprintf(stderr, "%s\n", msg); continue; }
        /* level 0: 2 + 4 triangles; level 1: sum of sizes = 16 quads; then x4 */
        long expect = L == 0 ? 6 : 2L * 16 << (2 * (L - 1));
        CHECK(o.triangle_count == expect);
        CHECK(o.triangle_count == subdiv_triangle_count(SUBDIV_CATMULL_CLARK, L, 5, S));
        CHECK(outside_hull(&o, 5, S, I, P, 1e-5f) == 0);
        check_normals_and_winding(&o);
        subdiv_output_free(&o);
    }
}

/* Awkward topology (degenerate faces, a non-manifold edge, unused vertices, inconsistent
 * winding, a duplicated face) must refine without failure, give finite unit normals,
 * indices in range and the predicted triangle count. */
static void awkward_topology(void)
{
    const float P[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 5, 5, 5};
    const int degenerate[6] = {0, 0, 1, 0, 1, 2}, nonmanifold[9] = {0, 1, 2, 0, 1, 3, 1, 0, 4},
              unused[3] = {0, 1, 2}, flipped[6] = {0, 1, 2, 0, 1, 3}, duplicate[6] = {0, 1, 2, 0, 1, 2};
    const int *cases[5] = {degenerate, nonmanifold, unused, flipped, duplicate};
    const int faces[5] = {2, 3, 1, 2, 2};
    for (int scheme = 0; scheme < 2; scheme++)
        for (int c = 0; c < 5; c++)
            for (int L = 0; L <= 2; L++) {
                SubdivInput in = {(SubdivScheme)scheme, L, 6, P, faces[c], NULL, cases[c]};
                SubdivOutput o;
                char msg[256];
                bool ok = subdiv_refine(&in, &o, msg, sizeof msg);
                CHECK(ok);
                if (!ok) { fprintf(stderr, "case %d level %d: %s\n", c, L, msg); continue; }
                CHECK(o.triangle_count == subdiv_triangle_count((SubdivScheme)scheme, L, faces[c], NULL));
                int bad = 0;
                for (int i = 0; i < 3 * o.vertex_count; i++) bad += !isfinite(o.p[i]) || !isfinite(o.n[i]);
                for (int i = 0; i < o.vertex_count; i++) bad += fabsf(v3_length(vget(o.n, i)) - 1) > 1e-5f;
                for (int t = 0; t < 3 * o.triangle_count; t++) bad += o.index[t] >= (uint32_t)o.vertex_count;
                CHECK(bad == 0);
                subdiv_output_free(&o);
            }
}

int main(void)
{
    awkward_topology();
    tetrahedron_loop();
    cube_catmull_clark();
    open_grid_boundary();
    pyramid_mixed();
    CHECK(subdiv_triangle_count(SUBDIV_LOOP, 15, 1 << 20, NULL) == -1); /* overflow caught */
    CHECK_DONE();
}
