/* Embree scene construction and ray queries (see tracer.h for the layer layout). */
#include "render/tracer.h"

#include <float.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/clock.h"
#include "core/env_knob.h"
#include "core/vectorise.h"
#include "geometry/mesh.h"
#include "render/layer_build.h"
#include "render/sphere_packet.h"
#include "render/sphere_packet_float.h"
#include "render/sphere_shade.h"

/* Relative size of the offset that lifts a new ray's origin off the surface it starts on.
 * Float rounding in a hit point is a few ulps (~1e-7) of the coordinates involved; 1e-5
 * leaves two orders of magnitude of margin and is invisible at any scene scale because it
 * scales with the coordinates (cf. pbrt-v4's error bounds, which scale the same way). */
static const float OFFSET_REL = 1e-5f;

/* ---- Embree device callbacks ---- */

typedef struct {
    char message[256];
} ErrorSlot;

static void on_embree_error(void *user, enum RTCError code, const char *str)
{
    ErrorSlot *slot = user;
    if (slot && !slot->message[0]) snprintf(slot->message, sizeof slot->message, "error %d: %s", (int)code, str ? str : "");
}

static bool on_embree_memory(void *user, ssize_t bytes, bool post)
{
    (void)post;
    Tracer *tr = user;
    long long now = __atomic_add_fetch(&tr->embree_bytes, (long long)bytes, __ATOMIC_RELAXED);
    long long peak = __atomic_load_n(&tr->embree_bytes_peak, __ATOMIC_RELAXED);
    while (now > peak && !__atomic_compare_exchange_n(&tr->embree_bytes_peak, &peak, now, true, __ATOMIC_RELAXED,
                                                      __ATOMIC_RELAXED)) {
    }
    return true;
}

/* ---- small double-precision helpers ---- */

static void apply_point_d(const Mat4 *m, const double p[3], double out[3])
{
    for (int i = 0; i < 3; ++i) out[i] = m->m[i][0] * p[0] + m->m[i][1] * p[1] + m->m[i][2] * p[2] + m->m[i][3];
}

static void apply_vector_d(const Mat4 *m, const double v[3], double out[3])
{
    for (int i = 0; i < 3; ++i) out[i] = m->m[i][0] * v[0] + m->m[i][1] * v[1] + m->m[i][2] * v[2];
}

/* v3_max_abs over a triangle's three vertices for vertices without NaN (Embree builds no
 * triangle with a non-finite vertex, so every hit triangle qualifies): `a > b ? a : b` is
 * one maxss, where fmax_nonneg's NaN test costs a compare and a blend more per operand. */
static inline float max_abs_vertices(vec3 p0, vec3 p1, vec3 p2)
{
    float v[9] = {p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z}, m = fabsf(v[0]);
    for (int k = 1; k < 9; ++k) m = m > fabsf(v[k]) ? m : fabsf(v[k]);
    return m;
}

/* Largest factor by which the 3x3 part can stretch a vector (row-sum norm bound). */
static double max_stretch(const Mat4 *m)
{
    double s = 0.0;
    for (int i = 0; i < 3; ++i) {
        double row = fabs(m->m[i][0]) + fabs(m->m[i][1]) + fabs(m->m[i][2]);
        s = (row > s || s != s) ? row : s; /* fmax(s, row) inline (never -0; a moving instance's hits ask) */
    }
    return s;
}

/* ---- exact spheres and disks (pbrt-v4 Sphere / Disk, intersected in object space) ---- */

/* Nearest object-space hit in (tnear, tfar) of the ray o + t d given in geometry space. */
bool tracer_quadric_hit(const Geom *g, const double o_geom[3], const double d_geom[3], double tnear, double tfar,
                       double *t_out)
{
    double o[3], d[3];
    if (g->object_translation_only) {
        /* A translated shape (the usual "Translate; Shape sphere"): 1 x + 0 y + 0 z + t is
         * x + t for the finite coordinates of a ray, so the products with the 3x3 part's ones
         * and zeros are skipped (the same values, but perhaps the sign of a zero
         * coordinate); 21 of the callback's double operations per ray. */
        for (int i = 0; i < 3; ++i) o[i] = o_geom[i] + g->object_from_geom.m[i][3], d[i] = d_geom[i];
    } else {
        apply_point_d(&g->object_from_geom, o_geom, o);
        apply_vector_d(&g->object_from_geom, d_geom, d);
    }
    if (g->kind == GEOM_DISK) {
        if (d[2] == 0.0) return false;
        double t = (g->height - o[2]) / d[2];
        if (!(t > tnear && t < tfar)) return false;
        double x = o[0] + t * d[0], y = o[1] + t * d[1];
        double r2 = x * x + y * y;
        if (r2 > g->radius * g->radius || r2 < g->inner_radius * g->inner_radius) return false;
        if (g->phimax_rad < 2.0 * M_PI) {
            double phi = atan2(y, x);
            if (phi < 0.0) phi += 2.0 * M_PI;
            if (phi > g->phimax_rad) return false;
        }
        *t_out = t;
        return true;
    }
    /* Sphere: a t^2 + b t + c = 0 with the discriminant computed from the distance of the
     * centre to the line (pbrt-v4 section 6.8.1), which stays accurate for distant spheres. */
    double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (!(a > 0.0)) return false;
    double b = 2.0 * (d[0] * o[0] + d[1] * o[1] + d[2] * o[2]);
    double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - g->radius * g->radius;
    double f = b / (2.0 * a);
    double v[3] = {o[0] - f * d[0], o[1] - f * d[1], o[2] - f * d[2]};
    double len2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    /* A line clearly farther from the centre than the radius misses, and the test below
     * would find disc < 0 (r - len is then exactly negative): decided here without its
     * square root, the latency a miss waited on. The relative margin 1e-9 is far above the
     * rounding of len2 and r^2, so only sure misses leave early and every result is the
     * same as without the test; NaN falls through to it. */
    if (len2 > g->radius * g->radius * (1.0 + 1e-9)) return false;
    double len = sqrt(len2);
    double disc = 4.0 * a * (g->radius + len) * (g->radius - len);
    if (disc < 0.0) return false;
    double root = sqrt(disc);
    double q = b < 0.0 ? -0.5 * (b - root) : -0.5 * (b + root);
    double t0 = q / a, t1 = (q != 0.0) ? c / q : t0;
    if (t0 > t1) {
        double tmp = t0;
        t0 = t1, t1 = tmp;
    }
    double cand[2] = {t0, t1};
    for (int k = 0; k < 2; ++k) {
        double t = cand[k];
        if (!(t > tnear && t < tfar)) continue;
        double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
        bool partial_z = g->zmin > -g->radius || g->zmax < g->radius;
        if (partial_z && (p[2] < g->zmin || p[2] > g->zmax)) continue;
        if (g->phimax_rad < 2.0 * M_PI) {
            double phi = atan2(p[1], p[0]);
            if (phi < 0.0) phi += 2.0 * M_PI;
            if (phi > g->phimax_rad) continue;
        }
        *t_out = t;
        return true;
    }
    return false;
}

static void quadric_object_bounds(const Geom *g, double lo[3], double hi[3])
{
    if (g->kind == GEOM_DISK) {
        lo[0] = lo[1] = -g->radius, hi[0] = hi[1] = g->radius;
        lo[2] = hi[2] = g->height;
    } else {
        lo[0] = lo[1] = -g->radius, hi[0] = hi[1] = g->radius;
        lo[2] = g->zmin, hi[2] = g->zmax;
    }
}

/* Embree keeps all of a scene's user primitives in one BVH. With a single one, the root of
 * that BVH is a leaf, and traversal enters a leaf root without a box test: every ray of the
 * scene calls the quadric's callback (on soft_shadows.pbrt, 95% of the callback's calls
 * were rays that did not pass the sphere's box). So a layer's only sphere or disk is given
 * a second primitive, this one: a point at the centre of the shape's box, which the
 * callbacks ignore. The BVH then has an inner root, and Embree tests each ray against the
 * shape's box before calling back. (A ray through exactly that point costs a call that
 * reports nothing; results are unchanged.) */
enum { QUADRIC_PRIM_SHAPE = 0, QUADRIC_PRIM_ANCHOR = 1 };

static void quadric_bounds_cb(const struct RTCBoundsFunctionArguments *args)
{
    const Geom *g = args->geometryUserPtr;
    double lo[3], hi[3], bmin[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, bmax[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    quadric_object_bounds(g, lo, hi);
    for (int c = 0; c < 8; ++c) {
        double p[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]}, q[3];
        apply_point_d(&g->geom_from_object, p, q);
        for (int i = 0; i < 3; ++i) bmin[i] = fmin(bmin[i], q[i]), bmax[i] = fmax(bmax[i], q[i]);
    }
    /* pad by a relative epsilon so float rounding of the box never clips the surface */
    double pad = 1e-6 * fmax(fmax(fabs(bmin[0]), fabs(bmax[0])), fmax(fmax(fabs(bmin[1]), fabs(bmax[1])),
                                                                    fmax(fabs(bmin[2]), fabs(bmax[2])))) + 1e-30;
    double k = 1.0 / g->geom_from_tracer; /* a power of two: exact */
    args->bounds_o->lower_x = (float)(k * (bmin[0] - pad)), args->bounds_o->upper_x = (float)(k * (bmax[0] + pad));
    args->bounds_o->lower_y = (float)(k * (bmin[1] - pad)), args->bounds_o->upper_y = (float)(k * (bmax[1] + pad));
    args->bounds_o->lower_z = (float)(k * (bmin[2] - pad)), args->bounds_o->upper_z = (float)(k * (bmax[2] + pad));
    if (args->primID == QUADRIC_PRIM_ANCHOR) {
        struct RTCBounds *b = args->bounds_o;
        b->lower_x = b->upper_x = 0.5f * (b->lower_x + b->upper_x);
        b->lower_y = b->upper_y = 0.5f * (b->lower_y + b->upper_y);
        b->lower_z = b->upper_z = 0.5f * (b->lower_z + b->upper_z);
    }
}

/* Embree hands user geometry N rays at once (N = 1 for single rays, 4/8/16 for packets and
 * for coherent streams) as structure-of-arrays: field k of ray i is element k N + i of a
 * float (or uint) array; the hit fields start at element 12 N (rtcore_ray.h's RTCRayN
 * layout). Only rays with valid[i] == -1 are live. */
enum { RAYN_ORG_X, RAYN_ORG_Y, RAYN_ORG_Z, RAYN_TNEAR, RAYN_DIR_X, RAYN_DIR_Y, RAYN_DIR_Z, RAYN_TIME, RAYN_TFAR };
enum { HITN_NG_X = 12, HITN_NG_Y, HITN_NG_Z, HITN_U, HITN_V, HITN_PRIM, HITN_GEOM, HITN_INST };

static inline float *rayn_f(void *rays, unsigned n, int field, unsigned i) { return (float *)rays + (size_t)field * n + i; }
static inline unsigned *rayn_u(void *rays, unsigned n, int field, unsigned i)
{
    return (unsigned *)rays + (size_t)field * n + i;
}

/* Embree's ray is in the layer's tracer space, p = o + t d with p = k p_geom (k the layer's
 * tracer_from_geom) and t in top-level tracer units. Dividing o and d by k gives the same
 * ray in geometry space with the same parameter t, so the quadric is solved there in
 * double and t goes back unchanged. k is a power of two: the division is exact, and at
 * k = 1 this is the unscaled computation. */
static bool quadric_hit_rayn(const Geom *g, void *rays, unsigned n, unsigned i, double *t)
{
    double w = g->geom_from_tracer;
    double o[3] = {w * *rayn_f(rays, n, RAYN_ORG_X, i), w * *rayn_f(rays, n, RAYN_ORG_Y, i),
                   w * *rayn_f(rays, n, RAYN_ORG_Z, i)};
    double d[3] = {w * *rayn_f(rays, n, RAYN_DIR_X, i), w * *rayn_f(rays, n, RAYN_DIR_Y, i),
                   w * *rayn_f(rays, n, RAYN_DIR_Z, i)};
    return tracer_quadric_hit(g, o, d, *rayn_f(rays, n, RAYN_TNEAR, i), *rayn_f(rays, n, RAYN_TFAR, i), t);
}

/* The usual sphere, whole and only translated, takes sphere_packet_hits_fast: a packet's
 * lanes in one vectorised loop in single precision, with tracer_quadric_hit's hits and its t
 * to a bound; the lanes the bound cannot decide take sphere_packet_hits' answers (the double
 * test, tracer_quadric_hit's results bit for bit). Embree 3 packets hold at most 16
 * rays; larger N (none today) would go lane by lane. */
enum { PACKET_MAX = 16 };
_Static_assert((int)PACKET_MAX <= (int)SPHERE_PACKET_FLOAT_MAX, "a packet fits the float test");
static bool packet_sphere(const Geom *g)
{
    return g->kind == GEOM_SPHERE && g->object_translation_only && !(g->zmin > -g->radius || g->zmax < g->radius) &&
           !(g->phimax_rad < 2.0 * M_PI);
}

/* Lanes first .. first + count - 1 (count <= PACKET_MAX) of an N-ray packet: whether each
 * live one hits (hit[i - first]) and where (t[i - first]). */
static void quadric_hits_rayn(const Geom *g, void *rays, const int *valid, unsigned n, unsigned first, unsigned count,
                              int *hit, double *t)
{
    if (first == 0 && count == n && packet_sphere(g)) {
        const double translation[3] = {g->object_from_geom.m[0][3], g->object_from_geom.m[1][3], g->object_from_geom.m[2][3]};
        sphere_packet_hits_fast(rays, valid, n, g->geom_from_tracer, translation, g->radius, hit, t);
        return;
    }
    for (unsigned k = 0; k < count; ++k) hit[k] = valid[first + k] == -1 && quadric_hit_rayn(g, rays, n, first + k, &t[k]);
}

static void quadric_intersect_cb(const struct RTCIntersectFunctionNArguments *args)
{
    const Geom *g = args->geometryUserPtr;
    void *rh = args->rayhit;
    unsigned n = args->N;
    if (args->primID == QUADRIC_PRIM_ANCHOR) return;
    for (unsigned first = 0; first < n; first += PACKET_MAX) {
        unsigned count = n - first < PACKET_MAX ? n - first : PACKET_MAX;
        int hit[PACKET_MAX];
        double t_hit[PACKET_MAX];
        quadric_hits_rayn(g, rh, args->valid, n, first, count, hit, t_hit);
        for (unsigned k = 0; k < count; ++k) {
            if (!hit[k]) continue;
            unsigned i = first + k;
            *rayn_f(rh, n, RAYN_TFAR, i) = (float)t_hit[k];
            *rayn_f(rh, n, HITN_U, i) = *rayn_f(rh, n, HITN_V, i) = 0.0f;
            *rayn_f(rh, n, HITN_NG_X, i) = *rayn_f(rh, n, HITN_NG_Y, i) = 0.0f;
            *rayn_f(rh, n, HITN_NG_Z, i) = 1.0f;
            *rayn_u(rh, n, HITN_PRIM, i) = args->primID;
            *rayn_u(rh, n, HITN_GEOM, i) = args->geomID;
            *rayn_u(rh, n, HITN_INST, i) = args->context->instID[0];
        }
    }
}

static void quadric_occluded_cb(const struct RTCOccludedFunctionNArguments *args)
{
    const Geom *g = args->geometryUserPtr;
    unsigned n = args->N;
    if (args->primID == QUADRIC_PRIM_ANCHOR) return;
    for (unsigned first = 0; first < n; first += PACKET_MAX) {
        unsigned count = n - first < PACKET_MAX ? n - first : PACKET_MAX;
        int hit[PACKET_MAX];
        double t_hit[PACKET_MAX];
        quadric_hits_rayn(g, args->ray, args->valid, n, first, count, hit, t_hit);
        for (unsigned k = 0; k < count; ++k)
            if (hit[k]) *rayn_f(args->ray, n, RAYN_TFAR, first + k) = -INFINITY;
    }
}

/* ---- building ---- */

static Geom *layer_add(Layer *l)
{
    if (l->geom_count == l->geom_cap) {
        int cap = l->geom_cap ? 2 * l->geom_cap : 8;
        Geom *g = realloc(l->geoms, (size_t)cap * sizeof *g);
        if (!g) return NULL;
        l->geoms = g, l->geom_cap = cap;
    }
    Geom *g = &l->geoms[l->geom_count++];
    memset(g, 0, sizeof *g);
    g->shape = -1, g->material = -1, g->area_light = -1, g->light_first = -1, g->instance = -1, g->owner_instance = -1;
    g->geom_from_tracer = 1.0;
    g->geom_from_object = g->object_from_geom = mat4_identity();
    return g;
}

static void forward_mesh_warning(void *ctx, SrcLoc loc, const char *text)
{
    scene_warn((SceneDesc *)ctx, loc, "%s", text);
}

/* Fills a Geom from a shape placed by geom_from_object (object -> geometry space). */
static bool geom_from_shape(Geom *g, SceneDesc *scene, int shape_index, const Mat4 *geom_from_object, Diag *err)
{
    ShapeDesc *s = &scene->shapes[shape_index];
    g->shape = shape_index;
    g->material = s->material;
    g->flip_normal = s->reverse_orientation != mat4_swaps_handedness(geom_from_object);
    g->geom_from_object = *geom_from_object;
    if (!mat4_inverse(geom_from_object, &g->object_from_geom)) {
        diag_set(err, WEDGE_EXIT_INPUT, s->loc, "shape transform is singular");
        return false;
    }
    const Mat4 *ofg = &g->object_from_geom;
    g->object_translation_only = ofg->m[0][0] == 1.0 && ofg->m[1][1] == 1.0 && ofg->m[2][2] == 1.0 && ofg->m[0][1] == 0.0 &&
                                 ofg->m[0][2] == 0.0 && ofg->m[1][0] == 0.0 && ofg->m[1][2] == 0.0 && ofg->m[2][0] == 0.0 &&
                                 ofg->m[2][1] == 0.0;
    if (!strcmp(s->type, "sphere")) {
        g->kind = GEOM_SPHERE;
        g->radius = fabs(params_float(&s->params, "radius", 1.0f));
        double zmin = params_float(&s->params, "zmin", (float)-g->radius);
        double zmax = params_float(&s->params, "zmax", (float)g->radius);
        g->zmin = fmax(-g->radius, fmin(zmin, zmax));
        g->zmax = fmin(g->radius, fmax(zmin, zmax));
        g->phimax_rad = fmin(360.0, fmax(0.0, params_float(&s->params, "phimax", 360.0f))) * M_PI / 180.0;
        double r = g->radius > 0.0 ? g->radius : 1.0;
        g->theta_zmin_rad = acos(fmax(-1.0, fmin(1.0, g->zmin / r)));
        g->theta_zmax_rad = acos(fmax(-1.0, fmin(1.0, g->zmax / r)));
        g->quadric_reach = g->radius * max_stretch(&g->geom_from_object);
        return true;
    }
    if (!strcmp(s->type, "disk")) {
        g->kind = GEOM_DISK;
        g->height = params_float(&s->params, "height", 0.0f);
        g->radius = fabs(params_float(&s->params, "radius", 1.0f));
        g->inner_radius = fabs(params_float(&s->params, "innerradius", 0.0f));
        g->phimax_rad = fmin(360.0, fmax(0.0, params_float(&s->params, "phimax", 360.0f))) * M_PI / 180.0;
        g->quadric_reach = g->radius * max_stretch(&g->geom_from_object);
        return true;
    }
    TriMesh mesh = {0};
    if (!mesh_from_shape_warn(s, &mesh, forward_mesh_warning, scene, err)) return false;
    g->kind = GEOM_TRIANGLES;
    g->vertex_count = mesh.vertex_count;
    g->triangle_count = mesh.triangle_count;
    /* Embree reads vertices with 16-byte loads: pad the last one. */
    float *p = realloc(mesh.p, (size_t)mesh.vertex_count * sizeof(vec3) + 16);
    if (!p) {
        mesh_free(&mesh);
        diag_set(err, WEDGE_EXIT_RUNTIME, s->loc, "out of memory loading mesh");
        return false;
    }
    bool identity = mat4_is_identity(geom_from_object);
    Mat4 normal_xf = g->object_from_geom; /* normals use the inverse transpose */
    for (int i = 0; i < mesh.vertex_count; ++i) {
        vec3 *v = (vec3 *)p + i;
        if (!identity) *v = mat4_apply_point(geom_from_object, *v);
        if (!(fabsf(v->x) < TRACER_COORD_MAX && fabsf(v->y) < TRACER_COORD_MAX && fabsf(v->z) < TRACER_COORD_MAX)) {
            diag_set(err, WEDGE_EXIT_INPUT, s->loc,
                     "the shape reaches (%g, %g, %g), beyond the coordinates the ray tracer can represent (magnitude "
                     "below %g): scale the scene down or move it towards the origin",
                     (double)v->x, (double)v->y, (double)v->z, (double)TRACER_COORD_MAX);
            free(p);
            mesh.p = NULL;
            mesh_free(&mesh);
            return false;
        }
        if (mesh.n) {
            vec3 n = identity ? mesh.n[i] : mat4_apply_normal(&normal_xf, mesh.n[i]);
            n = v3_normalize(n);
            mesh.n[i] = s->reverse_orientation ? v3_neg(n) : n;
        }
    }
    g->p = g->p_tracer = p;
    g->index = mesh.index;
    g->n = mesh.n;
    g->uv = mesh.uv;
    /* A hit's geometric normal and error bound are the triangle's: computed here once (16
     * bytes a triangle) instead of a normalisation and a nine-way maximum at every hit. */
    g->tri_shading = malloc((size_t)(g->triangle_count > 0 ? g->triangle_count : 1) * sizeof *g->tri_shading);
    if (!g->tri_shading) {
        diag_set(err, WEDGE_EXIT_RUNTIME, s->loc, "out of memory loading mesh");
        return false;
    }
    for (int t = 0; t < g->triangle_count; ++t) {
        const uint32_t *ix = g->index + 3 * (size_t)t;
        vec3 p0 = ((const vec3 *)p)[ix[0]], p1 = ((const vec3 *)p)[ix[1]], p2 = ((const vec3 *)p)[ix[2]];
        g->tri_shading[t].n = v3_normalize(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)));
        g->tri_shading[t].mag = max_abs_vertices(p0, p1, p2);
    }
    return true;
}

static void geom_free(Geom *g)
{
    if (g->kind == GEOM_TRIANGLES) {
        if (g->p_tracer != g->p) free((void *)g->p_tracer);
        free((void *)g->p);
        free((void *)g->index);
        free(g->n);
        free(g->uv);
        free(g->tri_shading);
    }
}

/* Gram-Schmidt QR of the 3x3 part: A = Q U with Q a rotation and U upper triangular (what
 * Embree's quaternion decomposition can represent: M = T R S, S upper triangular). */
static void qr_decompose(const Mat4 *m, double q[3][3], double u[3][3])
{
    double a[3][3]; /* columns */
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) a[j][i] = m->m[i][j];
    memset(u, 0, 9 * sizeof(double));
    double e[3][3];
    for (int j = 0; j < 3; ++j) {
        double v[3] = {a[j][0], a[j][1], a[j][2]};
        for (int k = 0; k < j; ++k) {
            double r = e[k][0] * a[j][0] + e[k][1] * a[j][1] + e[k][2] * a[j][2];
            u[k][j] = r;
            for (int i = 0; i < 3; ++i) v[i] -= r * e[k][i];
        }
        double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        u[j][j] = len;
        if (len > 0.0) {
            for (int i = 0; i < 3; ++i) e[j][i] = v[i] / len;
        } else { /* degenerate column: any unit vector orthogonal to the previous ones */
            double t[3] = {j == 0 ? 1.0 : 0.0, j == 1 ? 1.0 : 0.0, j == 2 ? 1.0 : 0.0};
            if (j == 2) {
                t[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
                t[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
                t[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
            }
            for (int i = 0; i < 3; ++i) e[j][i] = t[i];
        }
    }
    /* A mirror ends up in U (negative last scale) so that Q stays a proper rotation. */
    double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[1][0] * (e[0][1] * e[2][2] - e[0][2] * e[2][1]) +
                 e[2][0] * (e[0][1] * e[1][2] - e[0][2] * e[1][1]);
    if (det < 0.0) {
        for (int i = 0; i < 3; ++i) e[2][i] = -e[2][i];
        for (int k = 2; k < 3; ++k) u[2][k] = -u[2][k];
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) q[i][j] = e[j][i];
}

static Quat quat_from_rotation(double r[3][3])
{
    Quat q;
    double trace = r[0][0] + r[1][1] + r[2][2];
    if (trace > 0.0) {
        double s = sqrt(trace + 1.0) * 2.0;
        q.w = 0.25 * s;
        q.x = (r[2][1] - r[1][2]) / s;
        q.y = (r[0][2] - r[2][0]) / s;
        q.z = (r[1][0] - r[0][1]) / s;
    } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
        double s = sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]) * 2.0;
        q.w = (r[2][1] - r[1][2]) / s;
        q.x = 0.25 * s;
        q.y = (r[0][1] + r[1][0]) / s;
        q.z = (r[0][2] + r[2][0]) / s;
    } else if (r[1][1] > r[2][2]) {
        double s = sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]) * 2.0;
        q.w = (r[0][2] - r[2][0]) / s;
        q.x = (r[0][1] + r[1][0]) / s;
        q.y = 0.25 * s;
        q.z = (r[1][2] + r[2][1]) / s;
    } else {
        double s = sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]) * 2.0;
        q.w = (r[1][0] - r[0][1]) / s;
        q.x = (r[0][2] + r[2][0]) / s;
        q.y = (r[1][2] + r[2][1]) / s;
        q.z = 0.25 * s;
    }
    return q;
}

static bool polar_scale_is_diagonal(const Mat4 *s)
{
    double diag = fmax(fabs(s->m[0][0]), fmax(fabs(s->m[1][1]), fabs(s->m[2][2])));
    double off = fmax(fabs(s->m[0][1]), fmax(fabs(s->m[0][2]), fabs(s->m[1][2])));
    return off <= 1e-9 * diag;
}

/* Motion of an instance: pbrt-v4 AnimatedTransform poses handed to Embree as quaternion
 * decompositions. With a diagonal polar scale at both ends, two time steps reproduce pbrt's
 * interpolation (T lerp, R slerp, S lerp) exactly; otherwise 17 exact poses bound the error
 * of Embree's per-segment interpolation. In tracer space an instance transform M (world
 * from layer) becomes k_w M / k_l, k_w the world's and k_l the layer's tracer scale: the
 * 3x3 part times k_w / k_l, the translation times k_w (as in set_instance_static). */
static void set_instance_motion(RTCGeometry g, const AnimXform *a, double k_world, double k_layer)
{
    int steps = (polar_scale_is_diagonal(&a->s[0]) && polar_scale_is_diagonal(&a->s[1])) ? 2 : 17;
    rtcSetGeometryTimeStepCount(g, (unsigned)steps);
    Quat prev = {0, 0, 0, 1};
    for (int k = 0; k < steps; ++k) {
        Mat4 m = k == 0 ? a->start : (k == steps - 1 ? a->end : anim_xform_at(a, (double)k / (steps - 1)));
        double q[3][3], u[3][3];
        qr_decompose(&m, q, u);
        Quat r = quat_from_rotation(q);
        if (k > 0 && r.x * prev.x + r.y * prev.y + r.z * prev.z + r.w * prev.w < 0.0)
            r.x = -r.x, r.y = -r.y, r.z = -r.z, r.w = -r.w; /* shorter arc */
        prev = r;
        struct RTCQuaternionDecomposition qd;
        rtcInitQuaternionDecomposition(&qd);
        double r3 = k_world / k_layer; /* M = T R U: U carries the 3x3 part's scale */
        rtcQuaternionDecompositionSetScale(&qd, (float)(r3 * u[0][0]), (float)(r3 * u[1][1]), (float)(r3 * u[2][2]));
        rtcQuaternionDecompositionSetSkew(&qd, (float)(r3 * u[0][1]), (float)(r3 * u[0][2]), (float)(r3 * u[1][2]));
        rtcQuaternionDecompositionSetQuaternion(&qd, (float)r.w, (float)r.x, (float)r.y, (float)r.z);
        double s = k_world;
        rtcQuaternionDecompositionSetTranslation(&qd, (float)(s * m.m[0][3]), (float)(s * m.m[1][3]), (float)(s * m.m[2][3]));
        rtcSetGeometryTransformQuaternion(g, (unsigned)k, &qd);
    }
}

static void set_instance_static(RTCGeometry g, const Mat4 *m, double k_world, double k_layer)
{
    float xf[12];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) xf[i * 4 + j] = (float)((j == 3 ? k_world : k_world / k_layer) * m->m[i][j]);
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xf);
}

static Instance *add_instance(Tracer *tr, int *cap)
{
    if (tr->instance_count == *cap) {
        int c = *cap ? 2 * *cap : 8;
        Instance *in = realloc(tr->instances, (size_t)c * sizeof *in);
        if (!in) return NULL;
        tr->instances = in, *cap = c;
    }
    Instance *in = &tr->instances[tr->instance_count++];
    memset(in, 0, sizeof *in);
    return in;
}

static Layer *add_layer(Tracer *tr, int *cap)
{
    if (tr->layer_count == *cap) {
        int c = *cap ? 2 * *cap : 8;
        Layer *l = realloc(tr->layers, (size_t)c * sizeof *l);
        if (!l) return NULL;
        tr->layers = l, *cap = c;
    }
    Layer *l = &tr->layers[tr->layer_count++];
    memset(l, 0, sizeof *l);
    l->tracer_from_geom = 1.0f;
    return l;
}

/* Creates the Embree geometries of a layer (after its Geom array is final, since Embree
 * keeps pointers to the Geoms) and commits its scene. */
static bool commit_layer(Tracer *tr, Layer *l, ErrorSlot *slot, Diag *err)
{
    l->scene = rtcNewScene(tr->device);
    rtcSetSceneFlags(l->scene, tr->robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    /* Embree's two-level build where the layer's meshes favour it (design.md 12.27): the
     * same triangles and tests in another tree */
    bool two_level = tr->two_level == TRACER_TWO_LEVEL_AUTO ? layer_build_two_level(l->geoms, l->geom_count)
                                                            : tr->two_level == TRACER_TWO_LEVEL_ALWAYS;
    rtcSetSceneBuildQuality(l->scene, two_level ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_MEDIUM);
    /* A lone sphere or disk gets a second, empty primitive (QUADRIC_PRIM_ANCHOR) */
    int quadrics = 0, mask_bits = 0;
    bool masks = l == &tr->layers[0] && rtcGetDeviceProperty(tr->device, RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED);
    for (int i = 0; i < l->geom_count; ++i) quadrics += l->geoms[i].kind == GEOM_SPHERE || l->geoms[i].kind == GEOM_DISK;
    for (int i = 0; i < l->geom_count; ++i) {
        Geom *g = &l->geoms[i];
        RTCGeometry eg = NULL;
        switch (g->kind) {
        case GEOM_TRIANGLES:
            eg = rtcNewGeometry(tr->device, RTC_GEOMETRY_TYPE_TRIANGLE);
            rtcSetSharedGeometryBuffer(eg, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, g->p_tracer, 0, sizeof(vec3),
                                       (size_t)g->vertex_count);
            rtcSetSharedGeometryBuffer(eg, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, g->index, 0, 3 * sizeof(uint32_t),
                                       (size_t)g->triangle_count);
            break;
        case GEOM_SPHERE:
        case GEOM_DISK:
            eg = rtcNewGeometry(tr->device, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(eg, quadrics == 1 ? 2 : 1);
            rtcSetGeometryUserData(eg, g);
            rtcSetGeometryBoundsFunction(eg, quadric_bounds_cb, g);
            rtcSetGeometryIntersectFunction(eg, quadric_intersect_cb);
            rtcSetGeometryOccludedFunction(eg, quadric_occluded_cb);
            /* A shadow ray ends just short of the point it sampled on this emitter, and a
             * sphere or a disk cannot cover that segment (the point is the segment's first
             * crossing of the convex full shape, a partial shape being part of it): the
             * emitter need not be tested at all, which sphere lights otherwise cost on every
             * shadow ray aimed at them (docs/design.md 12.2). 31 bits, one per emitter;
             * further emitters keep every bit and are always tested. */
            if (masks && g->area_light >= 0 && mask_bits < 31) {
                g->mask_bit = 1u << ++mask_bits;
                rtcSetGeometryMask(eg, g->mask_bit);
            }
            break;
        case GEOM_INSTANCE: {
            Instance *in = &tr->instances[g->instance];
            eg = rtcNewGeometry(tr->device, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(eg, tr->layers[in->layer].scene);
            in->geometry = eg;
            break;
        }
        }
        if (!eg) break;
        if (g->kind == GEOM_INSTANCE) {
            Instance *in = &tr->instances[g->instance];
            double k_layer = tr->layers[in->layer].tracer_from_geom;
            if (in->moving)
                set_instance_motion(eg, &in->motion, tr->tracer_from_world, k_layer);
            else
                set_instance_static(eg, &in->world_from_inst, tr->tracer_from_world, k_layer);
        }
        rtcCommitGeometry(eg);
        rtcAttachGeometryByID(l->scene, eg, (unsigned)i);
        if (g->kind != GEOM_INSTANCE) rtcReleaseGeometry(eg); /* instances: released in tracer_free */
    }
    rtcCommitScene(l->scene);
    if (slot->message[0] || rtcGetDeviceError(tr->device) != RTC_ERROR_NONE) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "building the Embree scene failed: %s",
                 slot->message[0] ? slot->message : "unknown error");
        return false;
    }
    return true;
}

/* The power of two k = 2^e that brings the largest coordinate magnitude m of the scene near
 * 1, or 1 when m is in [2^-10, 2^20]: there Embree's float triangle test is accurate (its
 * determinant, a product of edge lengths, neither underflows nor overflows) and images stay
 * exactly what they were before the normalisation. */
static float tracer_scale_for(double m)
{
    if (!(m > 0.0) || !isfinite(m) || (m >= 0x1p-10 && m <= 0x1p20)) return 1.0f;
    int e = -(int)lround(log2(m));
    e = e < -100 ? -100 : (e > 100 ? 100 : e); /* m is below TRACER_COORD_MAX and a float above 0 */
    return ldexpf(1.0f, e);
}

/* After the first build (unscaled, which gave the bounds): when the world or an instanced
 * layer is far from unit size, multiply what Embree sees of it by its k and build again.
 * Triangles get a scaled copy of their vertices (the world-unit ones stay for shading and
 * lights); spheres and disks read k in their callbacks; instance transforms are scaled
 * when set (commit_layer). Every layer has its own k because an instanced layer is in its
 * own units (a moving shape's layer is in object space, usually unit-size in a huge
 * world). Powers of two multiply exactly, so only Embree's own rounding changes, and it
 * is then the rounding of a unit-size scene. */
static bool normalise_scale(Tracer *tr, ErrorSlot *slot, Diag *err)
{
    bool any = false;
    for (int li = 0; li < tr->layer_count; ++li) {
        Layer *l = &tr->layers[li];
        struct RTCBounds b;
        rtcGetSceneBounds(l->scene, &b);
        double lo[3] = {b.lower_x, b.lower_y, b.lower_z}, hi[3] = {b.upper_x, b.upper_y, b.upper_z}, m = 0.0;
        if (l->geom_count > 0)
            for (int i = 0; i < 3; ++i) m = fmax(m, fmax(fabs(lo[i]), fabs(hi[i])));
        l->tracer_from_geom = tracer_scale_for(m);
        any |= l->tracer_from_geom != 1.0f;
    }
    if (!any) return true;
    tr->tracer_from_world = tr->layers[0].tracer_from_geom;
    tr->world_from_tracer = 1.0f / tr->tracer_from_world;
    for (int i = 0; i < tr->instance_count; ++i)
        if (tr->instances[i].geometry) rtcReleaseGeometry(tr->instances[i].geometry), tr->instances[i].geometry = NULL;
    for (int li = 0; li < tr->layer_count; ++li) {
        Layer *l = &tr->layers[li];
        if (l->scene) rtcReleaseScene(l->scene), l->scene = NULL;
        float k = l->tracer_from_geom;
        for (int gi = 0; gi < l->geom_count; ++gi) {
            Geom *g = &l->geoms[gi];
            g->geom_from_tracer = 1.0 / k;
            if (g->kind != GEOM_TRIANGLES || k == 1.0f) continue;
            size_t n = 3 * (size_t)g->vertex_count;
            float *pt = malloc(n * sizeof(float) + 16); /* Embree's 16-byte loads, as in geom_from_shape */
            if (!pt) {
                diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory building the scene");
                return false;
            }
            for (size_t j = 0; j < n; ++j) pt[j] = k * g->p[j];
            memset(pt + n, 0, 16);
            g->p_tracer = pt;
        }
    }
    for (int li = 1; li < tr->layer_count; ++li)
        if (!commit_layer(tr, &tr->layers[li], slot, err)) return false;
    return commit_layer(tr, &tr->layers[0], slot, err);
}

static const char *const batch_names[TRACER_BATCH_MODE_COUNT] = {
    [TRACER_BATCH_SINGLE] = "single", [TRACER_BATCH_STREAM] = "stream", [TRACER_BATCH_PACKET16] = "packet16"};

bool tracer_build(Tracer *tr, SceneDesc *scene, int threads, Diag *err)
{
    *tr = (Tracer){0};
    tr->tracer_from_world = tr->world_from_tracer = 1.0f;
    double t0 = clock_wall_seconds();
    /* The batch interface, for benchmarks comparing them (docs/benchmarks.md). */
    tr->batch_mode = (TracerBatchMode)env_knob_choice("WEDGE_TRACE_BATCH", batch_names, TRACER_BATCH_MODE_COUNT,
                                                      TRACER_BATCH_DEFAULT);
    /* Embree's robust mode (commit_layer), on unless WEDGE_EMBREE_ROBUST=0: the knob of
     * the leak measurements (test_watertight, docs/benchmarks.md) */
    tr->robust = env_knob_switch("WEDGE_EMBREE_ROBUST", true);
    static const char *const two_level_names[TRACER_TWO_LEVEL_CHOICES] = {"auto", "0", "1"};
    tr->two_level = env_knob_choice("WEDGE_EMBREE_TWO_LEVEL", two_level_names, TRACER_TWO_LEVEL_CHOICES,
                                    TRACER_TWO_LEVEL_AUTO);
    ErrorSlot *slot = NULL;
    slot = calloc(1, sizeof *slot); /* filled by Embree's error callback */
    if (!slot) goto oom;
    char config[64];
    snprintf(config, sizeof config, "threads=%d", threads > 0 ? threads : 0);
    tr->device = rtcNewDevice(threads > 0 ? config : NULL);
    if (!tr->device) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot create the Embree device (error %d)",
                 (int)rtcGetDeviceError(NULL));
        return false;
    }
    rtcSetDeviceErrorFunction(tr->device, on_embree_error, slot);
    rtcSetDeviceMemoryMonitorFunction(tr->device, on_embree_memory, tr);

    const CameraDesc *cam = &scene->camera;
    bool shutter_open = cam->shutter_open < cam->shutter_close;
    /* With a closed shutter, moving things are frozen at the shutter time, expressed as
     * the fraction between the two transform times (TransformTimes, default 0 1). */
    double xf_span = scene->transform_end_time - scene->transform_start_time;
    double frozen_u = xf_span > 0.0 ? (cam->shutter_open - scene->transform_start_time) / xf_span : 0.0;
    frozen_u = fmin(1.0, fmax(0.0, frozen_u));
    int layer_cap = 0, instance_cap = 0;
    /* layer 0: top level; layers 1..object_count: ObjectBegin prototypes */
    for (int i = 0; i <= scene->object_count; ++i)
        if (!add_layer(tr, &layer_cap)) goto oom;

    bool warned_instanced_light = false, warned_interface = false;
    for (int si = 0; si < scene->shape_count; ++si) {
        ShapeDesc *s = &scene->shapes[si];
        if (s->material >= 0 && s->material < scene->material_count && scene->materials[s->material].type &&
            !strcmp(scene->materials[s->material].type, "interface")) {
            /* pbrt-v4: an "interface" shape only bounds a participating medium and is
             * invisible to rays; media are not modelled, so the shape is left out. */
            if (!warned_interface)
                scene_warn(scene, s->loc, "shapes with material \"interface\" only bound media, which are not supported; "
                                          "they are left out");
            warned_interface = true;
            continue;
        }
        bool moving = xform_pair_animated(&s->world_from_object) && shutter_open;
        Mat4 pose = s->world_from_object.m[0];
        if (xform_pair_animated(&s->world_from_object) && !shutter_open) {
            AnimXform a;
            anim_xform_init(&a, &s->world_from_object.m[0], &s->world_from_object.m[1]);
            pose = anim_xform_at(&a, frozen_u);
        }
        if (s->object >= 0) {
            /* Inside ObjectBegin: transforms are instance-from-object, taken at shutter open. */
            Layer *l = &tr->layers[1 + s->object];
            Geom *g = layer_add(l);
            if (!g) goto oom;
            if (!geom_from_shape(g, scene, si, &s->world_from_object.m[0], err)) goto fail;
            if (s->area_light >= 0 && !warned_instanced_light) {
                scene_warn(scene, s->loc, "area lights inside object instances are not supported; the shape does not emit");
                warned_instanced_light = true;
            }
            continue;
        }
        if (!moving) {
            Geom *g = layer_add(&tr->layers[0]);
            if (!g) goto oom;
            if (!geom_from_shape(g, scene, si, &pose, err)) goto fail;
            g->area_light = s->area_light;
            continue;
        }
        /* A moving shape: its own layer in object space, instanced with motion. */
        Layer *l = add_layer(tr, &layer_cap);
        if (!l) goto oom;
        int layer_index = tr->layer_count - 1;
        Geom *g = layer_add(l);
        if (!g) goto oom;
        Mat4 id = mat4_identity();
        if (!geom_from_shape(g, scene, si, &id, err)) goto fail;
        g->area_light = s->area_light;
        g->flip_normal = s->reverse_orientation != mat4_swaps_handedness(&s->world_from_object.m[0]);
        Instance *in = add_instance(tr, &instance_cap);
        if (!in) goto oom;
        in->layer = layer_index;
        in->moving = true;
        in->world_from_inst = s->world_from_object.m[0];
        anim_xform_init(&in->motion, &s->world_from_object.m[0], &s->world_from_object.m[1]);
        g->owner_instance = tr->instance_count - 1;
        Geom *ig = layer_add(&tr->layers[0]);
        if (!ig) goto oom;
        ig->kind = GEOM_INSTANCE;
        ig->instance = tr->instance_count - 1;
        tr->has_motion = true;
    }
    for (int ii = 0; ii < scene->instance_count; ++ii) {
        InstanceDesc *d = &scene->instances[ii];
        if (d->object < 0 || d->object >= scene->object_count || tr->layers[1 + d->object].geom_count == 0) continue;
        Instance *in = add_instance(tr, &instance_cap);
        if (!in) goto oom;
        in->layer = 1 + d->object;
        in->moving = xform_pair_animated(&d->world_from_instance) && shutter_open;
        in->world_from_inst = d->world_from_instance.m[0];
        anim_xform_init(&in->motion, &d->world_from_instance.m[0], &d->world_from_instance.m[1]);
        if (xform_pair_animated(&d->world_from_instance) && !shutter_open) {
            AnimXform a;
            anim_xform_init(&a, &d->world_from_instance.m[0], &d->world_from_instance.m[1]);
            in->world_from_inst = anim_xform_at(&a, frozen_u);
        }
        Geom *ig = layer_add(&tr->layers[0]);
        if (!ig) goto oom;
        ig->kind = GEOM_INSTANCE;
        ig->instance = tr->instance_count - 1;
        tr->has_motion |= in->moving;
    }
    for (int i = 0; i < tr->instance_count; ++i) {
        Instance *in = &tr->instances[i];
        if (!mat4_inverse(&in->world_from_inst, &in->inst_from_world)) {
            diag_set(err, WEDGE_EXIT_INPUT, (SrcLoc){0}, "object instance transform is singular");
            goto fail;
        }
    }
    for (int li = 0; li < tr->layer_count; ++li)
        for (int gi = 0; gi < tr->layers[li].geom_count; ++gi)
            if (tr->layers[li].geoms[gi].kind == GEOM_TRIANGLES) tr->triangle_count += tr->layers[li].geoms[gi].triangle_count;

    /* Prototype layers first (instances need their committed scenes), the top level last. */
    for (int li = 1; li < tr->layer_count; ++li)
        if (!commit_layer(tr, &tr->layers[li], slot, err)) goto fail;
    if (!commit_layer(tr, &tr->layers[0], slot, err)) goto fail;
    {
        struct RTCBounds b;
        rtcGetSceneBounds(tr->layers[0].scene, &b);
        tr->bounds_min[0] = b.lower_x, tr->bounds_min[1] = b.lower_y, tr->bounds_min[2] = b.lower_z;
        tr->bounds_max[0] = b.upper_x, tr->bounds_max[1] = b.upper_y, tr->bounds_max[2] = b.upper_z;
        if (tr->layers[0].geom_count == 0)
            for (int i = 0; i < 3; ++i) tr->bounds_min[i] = tr->bounds_max[i] = 0.0f;
        /* instances, spheres and moving shapes are checked here, as a whole */
        for (int i = 0; i < 3; ++i)
            if (!(fabsf(tr->bounds_min[i]) < TRACER_COORD_MAX && fabsf(tr->bounds_max[i]) < TRACER_COORD_MAX)) {
                diag_set(err, WEDGE_EXIT_INPUT, (SrcLoc){0},
                         "the scene's geometry extends from (%g, %g, %g) to (%g, %g, %g), beyond the coordinates the ray "
                         "tracer can represent (magnitude below %g): scale the scene down or move it towards the origin",
                         (double)tr->bounds_min[0], (double)tr->bounds_min[1], (double)tr->bounds_min[2],
                         (double)tr->bounds_max[0], (double)tr->bounds_max[1], (double)tr->bounds_max[2],
                         (double)TRACER_COORD_MAX);
                goto fail;
            }
        /* Below this size the tracer still normalises the scene, but lights and shading work
         * in world units in float: an area of (1e-19)^2 underflows, and nothing smaller than
         * TRACER_EXTENT_TESTED_MIN is tested (test_robustness, tests/stress). */
        float extent = 0.0f;
        for (int i = 0; i < 3; ++i) extent = fmaxf(extent, tr->bounds_max[i] - tr->bounds_min[i]);
        if (extent > 0.0f && extent < TRACER_EXTENT_TESTED_MIN)
            scene_warn(scene, (SrcLoc){0},
                       "the scene's geometry is %g units across, below %g, the smallest scale tested; lights and "
                       "shading lose precision in float from about 1e-19 (areas underflow): model in larger units",
                       (double)extent, (double)TRACER_EXTENT_TESTED_MIN);
    }
    if (!normalise_scale(tr, slot, err)) goto fail;
    /* the moving instances' poses at the ends of time, as Embree gives them (the same values
     * as asking again: tracer_world_from_instance returns these from now on) */
    for (int i = 0; i < tr->instance_count; ++i) {
        Instance *in = &tr->instances[i];
        if (!in->moving) continue;
        in->pose_at_end[0] = tracer_world_from_instance(tr, i, 0.0f);
        in->pose_at_end[1] = tracer_world_from_instance(tr, i, 1.0f);
        in->pose_kept = true;
    }
    for (int i = 0; i < tr->layers[0].geom_count; ++i) tr->top_spheres |= tr->layers[0].geoms[i].kind == GEOM_SPHERE;
    /* A scene with ObjectBegin prototypes traces its shadow rays incoherent: a coherent
     * occlusion stream entering an instanced prototype runs Embree's coherent 16-ray packet
     * traversal (BVHNIntersectorKHybrid::occludedCoherent), which the Embree 3.13.5 build
     * this project links (Debian's, GCC) miscompiles: it stores the 16-bit mask of live rays
     * into a 64-bit stack slot and reads the slot back whole, so stale stack bytes above the
     * mask keep its loop over octants from ending (design.md 12.31; Embree's later releases
     * work around the same GCC fault, RenderKit/embree#574). Whether a frame hung thus
     * depended on what earlier calls left on the stack. Moving shapes' own instanced layers
     * do not enter that kernel (test_coherent_instances) and keep the hint (10-15% of a
     * frame); no bench scene has prototypes. */
    tr->shadow_coherent_ok = scene->object_count == 0;
    rtcSetDeviceErrorFunction(tr->device, NULL, NULL);
    free(slot);
    tr->seconds_build = clock_wall_seconds() - t0;
    return true;
oom:
    diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory building the scene");
fail:
    if (tr->device) rtcSetDeviceErrorFunction(tr->device, NULL, NULL);
    free(slot);
    tracer_free(tr);
    return false;
}

void tracer_free(Tracer *tr)
{
    for (int li = 0; li < tr->layer_count; ++li) {
        Layer *l = &tr->layers[li];
        if (l->scene) rtcReleaseScene(l->scene);
        for (int gi = 0; gi < l->geom_count; ++gi) geom_free(&l->geoms[gi]);
        free(l->geoms);
    }
    for (int i = 0; i < tr->instance_count; ++i)
        if (tr->instances[i].geometry) rtcReleaseGeometry(tr->instances[i].geometry);
    free(tr->layers);
    free(tr->instances);
    if (tr->device) rtcReleaseDevice(tr->device);
    *tr = (Tracer){0};
}

/* ---- queries ---- */

Mat4 tracer_world_from_instance(const Tracer *tr, int instance, float time01)
{
    const Instance *in = &tr->instances[instance];
    if (!in->moving) return in->world_from_inst;
    if (in->pose_kept && (time01 == 0.0f || time01 == 1.0f)) return in->pose_at_end[time01 == 1.0f];
    /* Ask Embree for its own interpolated pose so shading agrees with the traversal. */
    float xf[12];
    rtcGetGeometryTransform(in->geometry, time01, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xf);
    Mat4 m = mat4_identity();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) /* undo set_instance_motion's scaling (exact: powers of two) */
            m.m[i][j] = (j == 3 ? tr->world_from_tracer : tr->world_from_tracer * tr->layers[in->layer].tracer_from_geom) *
                        xf[i * 4 + j];
    return m;
}

/* A world ray as Embree's, in tracer space: origin and tmax times k = tracer_from_world
 * (exact, a power of two), the direction as it is. */
static void init_ray(struct RTCRay *r, vec3 o, vec3 d, float tmax, float time01, float k, unsigned skip_mask)
{
    r->org_x = k * o.x, r->org_y = k * o.y, r->org_z = k * o.z;
    r->dir_x = d.x, r->dir_y = d.y, r->dir_z = d.z;
    r->tnear = 0.0f;
    r->tfar = k * tmax;
    r->time = time01;
    r->mask = ~skip_mask;
    r->id = 0;
    r->flags = 0;
}

/* Hit point, normals and uv of a triangle hit in geometry space (barycentrics bu, bv). */
static inline void shade_triangle(const Geom *g, int prim, float bu, float bv, vec3 *p, vec3 *ng, vec3 *ns, vec2 *uv,
                                  float *mag)
{
    const uint32_t *ix = g->index + 3 * (size_t)prim;
    const vec3 *P = (const vec3 *)g->p;
    vec3 p0 = P[ix[0]], p1 = P[ix[1]], p2 = P[ix[2]];
    float b0 = 1.0f - bu - bv;
    /* barycentric reconstruction: lies on the triangle up to rounding, unlike o + t d */
    *p = v3_add(v3_add(v3_scale(p0, b0), v3_scale(p1, bu)), v3_scale(p2, bv));
    const TriangleShading *ts = &g->tri_shading[prim];
    *mag = ts->mag;
    vec3 n = ts->n;
    if (g->n) {
        vec3 s = v3_add(v3_add(v3_scale(g->n[ix[0]], b0), v3_scale(g->n[ix[1]], bu)), v3_scale(g->n[ix[2]], bv));
        s = v3_normalize(s);
        if (v3_length2(s) == 0.0f) s = n;
        if (v3_dot(n, s) < 0.0f) n = v3_neg(n); /* pbrt-v4: ng follows the shading normal */
        *ns = s;
    } else {
        if (g->flip_normal) n = v3_neg(n);
        *ns = n;
    }
    *ng = n;
    if (g->uv) {
        vec2 a = g->uv[ix[0]], b = g->uv[ix[1]], c = g->uv[ix[2]];
        *uv = v2(b0 * a.x + bu * b.x + bv * c.x, b0 * a.y + bu * b.y + bv * c.y);
    } else {
        *uv = v2(bu + bv, bv); /* pbrt-v4 default (0,0) (1,0) (1,1) */
    }
}

/* The uv of sphere g's object-space surface point po (pbrt-v4's Sphere: phi over phimax, theta
 * between the polar angles of zmin and zmax); 0 when nothing reads it (Geom.uv_unread). */
static vec2 sphere_uv(const Geom *g, const double po[3])
{
    if (g->uv_unread) return v2(0.0f, 0.0f);
    double phi = atan2(po[1], po[0]);
    if (phi < 0.0) phi += 2.0 * M_PI;
    double r = g->radius > 0.0 ? g->radius : 1.0;
    double theta = acos(fmax(-1.0, fmin(1.0, po[2] / r)));
    double th_min = g->theta_zmin_rad, dv = g->theta_zmax_rad - th_min;
    return v2(g->phimax_rad > 0.0 ? (float)(phi / g->phimax_rad) : 0.0f, dv != 0.0 ? (float)((theta - th_min) / dv) : 0.0f);
}

/* Hit point, normals and uv in geometry space. p_hint_geom is the ray's hit point there. */
static void shade_geom_space(const Geom *g, int prim, float bu, float bv, const double p_hint_geom[3], vec3 *p, vec3 *ng,
                             vec3 *ns, vec2 *uv, float *mag)
{
    if (g->kind == GEOM_TRIANGLES) {
        shade_triangle(g, prim, bu, bv, p, ng, ns, uv, mag);
        return;
    }
    double po[3];
    apply_point_d(&g->object_from_geom, p_hint_geom, po);
    double n_obj[3] = {0.0, 0.0, 1.0};
    if (g->kind == GEOM_SPHERE) {
        double len = sqrt(po[0] * po[0] + po[1] * po[1] + po[2] * po[2]);
        if (len > 0.0)
            for (int i = 0; i < 3; ++i) po[i] *= g->radius / len; /* reproject onto the surface */
        for (int i = 0; i < 3; ++i) n_obj[i] = po[i];
        *uv = sphere_uv(g, po);
    } else if (g->uv_unread) {
        po[2] = g->height;
        *uv = v2(0.0f, 0.0f);
    } else {
        po[2] = g->height;
        double rh = sqrt(po[0] * po[0] + po[1] * po[1]);
        double phi = atan2(po[1], po[0]);
        if (phi < 0.0) phi += 2.0 * M_PI;
        double dr = g->radius - g->inner_radius;
        *uv = v2(g->phimax_rad > 0.0 ? (float)(phi / g->phimax_rad) : 0.0f, dr != 0.0 ? (float)((g->radius - rh) / dr) : 0.0f);
    }
    double pg[3];
    apply_point_d(&g->geom_from_object, po, pg);
    *p = v3((float)pg[0], (float)pg[1], (float)pg[2]);
    vec3 n = v3_normalize(mat4_apply_normal(&g->object_from_geom, v3((float)n_obj[0], (float)n_obj[1], (float)n_obj[2])));
    if (g->flip_normal) n = v3_neg(n);
    *ng = *ns = n;
    *mag = v3_max_abs(*p) + (float)g->quadric_reach;
}

bool tracer_intersect(const Tracer *tr, vec3 o, vec3 d, float tmax, float time01, SurfaceHit *hit)
{
    return tracer_intersect_ex(tr, o, d, tmax, time01, true, hit);
}

/* A hit the caller needs no shading of (only emitters matter to it): where and what, no
 * vertex fetches. */
static inline void hit_unshaded(SurfaceHit *hit, float t, const Geom *g, int prim, int instance, int object_id)
{
    memset(hit, 0, sizeof *hit);
    hit->t = t;
    hit->geom = g;
    hit->prim = prim;
    hit->instance = instance;
    hit->object_id = object_id;
    hit->light = -1;
}

/* A shaded hit from its world-space point, normals, uv and offset error. ns is never a zero
 * vector unless ng is the same one: shade_geom_space gives a quadric ns = ng and a triangle
 * its face normal, or an interpolated normal that is unit or replaced by the face normal
 * (shade_triangle); only an instance's transform (shade_hit) can take a unit ns to zero, and
 * it replaces that by ng itself. */
static inline void hit_shaded(SurfaceHit *hit, float t, vec3 p, vec3 ng, vec3 ns, vec2 uv, float err, const Geom *g,
                              int prim, int instance, int object_id)
{
    hit->t = t;
    hit->p = p;
    hit->ng = ng;
    hit->ns = ns;
    hit->uv = uv;
    hit->err = err;
    hit->geom = g;
    hit->prim = prim;
    hit->instance = instance;
    hit->object_id = object_id;
    hit->light = g->light_first >= 0 ? g->light_first + (g->kind == GEOM_TRIANGLES ? prim : 0) : -1;
}

/* The hit of a top-level sphere placed by a translation alone (centre c, radius r), mostly in
 * float (docs/algorithms.md, "A translated sphere's hit in float"): the offset from the centre
 * o - c in double, rounded (an origin far from the world's origin keeps its digits near the
 * sphere), plus t d in float (t is a float anyway: its rounding is the hit's own uncertainty
 * along the ray); the normal, that offset normalised (v3_normalize; sphere_shade_batch_translated
 * takes the plain case of it); the point reprojected onto the surface, c + r n, in double and
 * rounded once; the uv from r n. shade_geom_space does the same in double through two 4x4
 * transforms, a double square root and division, and the normal through the inverse. */
static void sphere_hit_shade(const Geom *g, vec3 o, vec3 d, float t, SurfaceHit *hit, int prim, int object_id)
{
    const Mat4 *m = &g->geom_from_object;
    double cx = m->m[0][3], cy = m->m[1][3], cz = m->m[2][3], r = g->radius;
    vec3 oc = v3((float)((double)o.x - cx), (float)((double)o.y - cy), (float)((double)o.z - cz));
    vec3 n = v3_normalize(v3_madd(oc, d, t));
    double po[3] = {r * (double)n.x, r * (double)n.y, r * (double)n.z};
    vec3 p = v3((float)(cx + po[0]), (float)(cy + po[1]), (float)(cz + po[2]));
    vec2 uv = sphere_uv(g, po);
    if (g->flip_normal) n = v3_neg(n);
    float mag = v3_max_abs(p) + (float)g->quadric_reach;
    hit_shaded(hit, t, p, n, n, uv, OFFSET_REL * mag, g, prim, -1, object_id);
}

/* tracer_intersect_ex's shading of any hit rh of the ray o + t d (instances, spheres and
 * disks included). Out of line: the common case below stays small. */
static __attribute__((noinline)) bool shade_hit(const Tracer *tr, vec3 o, vec3 d, float time01, bool shade_all,
                                                const struct RTCRayHit *hr, SurfaceHit *hit)
{
    struct RTCRayHit rh = *hr;

    const Geom *g;
    int instance = -1, object_id;
    if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
        object_id = (int)rh.hit.instID[0];
        instance = tr->layers[0].geoms[object_id].instance;
        g = &tr->layers[tr->instances[instance].layer].geoms[rh.hit.geomID];
    } else {
        object_id = (int)rh.hit.geomID;
        g = &tr->layers[0].geoms[object_id];
    }
    float t = tr->world_from_tracer * rh.ray.tfar;
    if (!shade_all && g->light_first < 0) {
        hit_unshaded(hit, t, g, (int)rh.hit.primID, instance, object_id);
        return true;
    }
    if (instance < 0 && g->kind == GEOM_SPHERE && g->object_translation_only) {
        sphere_hit_shade(g, o, d, t, hit, (int)rh.hit.primID, object_id);
        return true;
    }
    double pg[3] = {0.0, 0.0, 0.0};
    if (g->kind != GEOM_TRIANGLES || instance >= 0)
        for (int i = 0; i < 3; ++i) pg[i] = (double)v3_get(o, i) + (double)t * v3_get(d, i);
    Mat4 wfi, ifw;
    if (instance >= 0) {
        double pw[3] = {pg[0], pg[1], pg[2]};
        wfi = tracer_world_from_instance(tr, instance, time01);
        if (tr->instances[instance].moving) {
            if (!mat4_inverse(&wfi, &ifw)) ifw = tr->instances[instance].inst_from_world;
        } else {
            ifw = tr->instances[instance].inst_from_world;
        }
        apply_point_d(&ifw, pw, pg);
    }
    vec3 p, ng, ns;
    vec2 uv;
    float mag;
    shade_geom_space(g, (int)rh.hit.primID, rh.hit.u, rh.hit.v, pg, &p, &ng, &ns, &uv, &mag);
    float err = OFFSET_REL * mag;
    if (instance >= 0) {
        vec3 pw_f = mat4_apply_point(&wfi, p);
        ng = v3_normalize(mat4_apply_normal(&ifw, ng));
        ns = v3_normalize(mat4_apply_normal(&ifw, ns));
        if (v3_length2(ns) == 0.0f) ns = ng;
        err = OFFSET_REL * (v3_max_abs(pw_f) + (float)max_stretch(&wfi) * mag);
        p = pw_f;
    }
    hit_shaded(hit, t, p, ng, ns, uv, err, g, (int)rh.hit.primID, instance, object_id);
    return true;
}

/* The common case, a triangle prim of the top level's geometry g (object_id) hit at tracer
 * distance tfar and barycentrics bu, bv, as shade_hit does it. */
static inline void top_triangle_hit(const Tracer *tr, const Geom *g, int prim, int object_id, float tfar, float bu,
                                    float bv, bool shade_all, SurfaceHit *hit)
{
    float t = tr->world_from_tracer * tfar;
    if (!shade_all && g->light_first < 0) {
        hit_unshaded(hit, t, g, prim, -1, object_id);
        return;
    }
    vec3 p, ng, ns;
    vec2 uv;
    float mag;
    shade_triangle(g, prim, bu, bv, &p, &ng, &ns, &uv, &mag);
    hit_shaded(hit, t, p, ng, ns, uv, OFFSET_REL * mag, g, prim, -1, object_id);
}

/* The hit of a traced ray o + t d as a SurfaceHit (false on a miss). */
static inline bool hit_from_rayhit(const Tracer *tr, vec3 o, vec3 d, float time01, bool shade_all,
                                   const struct RTCRayHit *rh, SurfaceHit *hit)
{
    if (rh->hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    if (rh->hit.instID[0] != RTC_INVALID_GEOMETRY_ID) return shade_hit(tr, o, d, time01, shade_all, rh, hit);
    const Geom *g = &tr->layers[0].geoms[rh->hit.geomID];
    if (g->kind != GEOM_TRIANGLES) return shade_hit(tr, o, d, time01, shade_all, rh, hit);
    top_triangle_hit(tr, g, (int)rh->hit.primID, (int)rh->hit.geomID, rh->ray.tfar, rh->hit.u, rh->hit.v, shade_all, hit);
    return true;
}

static inline void init_rayhit(struct RTCRayHit *rh, vec3 o, vec3 d, float tmax, float time01, float k,
                               unsigned skip_mask)
{
    init_ray(&rh->ray, o, d, tmax, time01, k, skip_mask);
    rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

bool tracer_intersect_ex(const Tracer *tr, vec3 o, vec3 d, float tmax, float time01, bool shade_all, SurfaceHit *hit)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    init_rayhit(&rh, o, d, tmax, time01, tr->tracer_from_world, 0u);
    rtcIntersect1(tr->layers[0].scene, &ctx, &rh);
    return hit_from_rayhit(tr, o, d, time01, shade_all, &rh, hit);
}

bool tracer_occluded(const Tracer *tr, vec3 o, vec3 d, float tmax, float time01)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay r;
    init_ray(&r, o, d, tmax, time01, tr->tracer_from_world, 0u);
    rtcOccluded1(tr->layers[0].scene, &ctx, &r);
    return r.tfar == -INFINITY;
}

/* ---- batches ---- */

/* Rays go to Embree in chunks of this many (on the stack). */
enum { TRACE_CHUNK = 64 };

const char *tracer_batch_mode_name(TracerBatchMode mode)
{
    return (unsigned)mode < TRACER_BATCH_MODE_COUNT ? batch_names[mode] : "?";
}

static void context_init(const Tracer *tr, struct RTCIntersectContext *ctx, bool coherent)
{
    rtcInitIntersectContext(ctx);
    /* Embree 3.13's coherent rtcOccluded16 never returned on the rays of
     * tests/render/test_wave.c (spheres, a disk, an instance): packets go incoherent */
    if (tr->batch_mode == TRACER_BATCH_PACKET16) coherent = false;
    ctx->flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
}

/* Whether a batch goes to Embree as packets of 16 (rtcIntersect16 / rtcOccluded16): in the
 * packet mode, and in the stream mode for rays the caller calls incoherent (bounce rays, a
 * sky's cosine-distributed shadow rays, and lanes mostly inactive). Embree 3.13 traces an
 * incoherent stream as packets of 16 gathered from it, so these rays meet the same packets in
 * the same order and get the same answers; what goes is the stream's gather and, for
 * occlusion, the octant sort and the coherent stream's frustum walk, which scattered rays
 * do not share (docs/benchmarks.md, "Issue 22, forty-fourth round"; design.md 12.34). */
static inline bool packets_of_16(const Tracer *tr, bool incoherent)
{
    return tr->batch_mode == TRACER_BATCH_PACKET16 || (tr->batch_mode == TRACER_BATCH_STREAM && incoherent);
}

/* Packets of 16: the chunk's rays k0 .. k0 + 15 as structure-of-arrays (lanes past n off). */
static void packet16_fill(struct RTCRay16 *p, int valid[16], const TracerRay *rays, int n, float k)
{
    for (int i = 0; i < 16; ++i) {
        const TracerRay *r = &rays[i < n ? i : 0];
        valid[i] = i < n ? -1 : 0;
        p->org_x[i] = k * r->o.x, p->org_y[i] = k * r->o.y, p->org_z[i] = k * r->o.z; /* as init_ray */
        p->dir_x[i] = r->d.x, p->dir_y[i] = r->d.y, p->dir_z[i] = r->d.z;
        p->tnear[i] = 0.0f;
        p->tfar[i] = k * r->tmax;
        p->time[i] = r->time01;
        p->mask[i] = ~r->skip_mask;
        p->id[i] = 0;
        p->flags[i] = 0;
    }
}

/* The direction octant of a ray: the signs of d's coordinates as three bits. */
static inline int ray_octant(vec3 d) { return (d.x < 0.0f) | (d.y < 0.0f) << 1 | (d.z < 0.0f) << 2; }

/* A chunk's rays grouped by their octants key[0 .. m), each octant's rays in their order:
 * order[0 .. m) lists the rays so (order has room for m + 1: the branch-free compaction
 * writes one past). counts holds the rays per octant, one byte each (octant o in bits
 * 8 o .. 8 o + 7).
 *
 * Why: Embree 3 traces a coherent stream in groups of consecutive rays (32 or 64), and a
 * group takes its frustum traversal (one walk of the tree for all its packets) only when all
 * its rays share an octant; otherwise it traces the group's packets one by one. The shadow
 * rays of a wave's vertices to two delta lights alternate ray by ray (defocus.pbrt: the
 * point light's, then the distant light's, for each receiver), so nearly every group mixed
 * two octants. Occlusion is an any-hit question, whose answer per ray does not depend on the
 * ray's neighbours; the images stay the same bit for bit (docs/benchmarks.md, issue 22,
 * twenty-second round). Closest-hit batches are not reordered: no gain measured there. */
static void octant_order(const int *key, uint64_t counts, int m, int *order)
{
    int n = 0;
    for (int o = 0; o < 8; ++o) {
        if (!((counts >> (8 * o)) & 255u)) continue;
        for (int i = 0; i < m; ++i) {
            order[n] = i;
            n += key[i] == o;
        }
    }
}

/* Whether hit rh (of a batch) is one shade_sphere_hits shades: on a sphere at the top level
 * whose uv nobody reads, to be shaded (what shade_hit would do with it otherwise). */
static inline bool sphere_hit_batched(const Tracer *tr, const struct RTCRayHit *rh, bool shade_all)
{
    if (rh->hit.geomID == RTC_INVALID_GEOMETRY_ID || rh->hit.instID[0] != RTC_INVALID_GEOMETRY_ID) return false;
    const Geom *g = &tr->layers[0].geoms[rh->hit.geomID];
    return g->kind == GEOM_SPHERE && g->uv_unread && (shade_all || g->light_first >= 0);
}

/* The hits rh[lane[0 .. count)] of a chunk that sphere_hit_batched chose, shaded sphere by
 * sphere in sphere_shade_batch's vectorised loop: the SurfaceHits shade_hit would write, bit
 * for bit (a lane whose normal fell outside v3_normalize's plain range goes to shade_hit). */
static void shade_sphere_hits(const Tracer *tr, const TracerRay *r, const struct RTCRayHit *rh, int *lane, int count,
                              bool shade_all, SurfaceHit *hits, bool *found)
{
    _Static_assert((int)TRACE_CHUNK <= (int)SPHERE_SHADE_MAX, "a chunk's sphere hits fit one batch");
    while (count > 0) {
        unsigned geom = rh[lane[0]].hit.geomID;
        const Geom *g = &tr->layers[0].geoms[geom];
        SphereShadeBatch b;
        int of[TRACE_CHUNK], rest = 0;
        b.count = 0;
        for (int q = 0; q < count; ++q) {
            int i = lane[q];
            if (rh[i].hit.geomID != geom) {
                lane[rest++] = i;
                continue;
            }
            int k = b.count++;
            of[k] = i;
            b.o[0][k] = r[i].o.x, b.o[1][k] = r[i].o.y, b.o[2][k] = r[i].o.z;
            b.d[0][k] = r[i].d.x, b.d[1][k] = r[i].d.y, b.d[2][k] = r[i].d.z;
            b.tfar[k] = rh[i].ray.tfar;
        }
        count = rest;
        if (g->object_translation_only) {
            const double centre[3] = {g->geom_from_object.m[0][3], g->geom_from_object.m[1][3], g->geom_from_object.m[2][3]};
            sphere_shade_batch_translated(&b, centre, g->radius, tr->world_from_tracer, g->quadric_reach);
        } else {
            sphere_shade_batch(&b, &g->object_from_geom, &g->geom_from_object, g->radius, tr->world_from_tracer,
                               g->quadric_reach);
        }
        for (int k = 0; k < b.count; ++k) {
            int i = of[k];
            if (!b.ok[k]) {
                found[i] = shade_hit(tr, r[i].o, r[i].d, r[i].time01, shade_all, &rh[i], &hits[i]);
                continue;
            }
            vec3 n = v3(b.n[0][k], b.n[1][k], b.n[2][k]);
            if (g->flip_normal) n = v3_neg(n);
            hit_shaded(&hits[i], b.t[k], v3(b.p[0][k], b.p[1][k], b.p[2][k]), n, n, v2(0.0f, 0.0f),
                       OFFSET_REL * b.mag[k], g, (int)rh[i].hit.primID, -1, (int)geom);
            found[i] = true;
        }
    }
}

/* tracer_intersect_batch's rays r[0 .. m) (m <= TRACE_CHUNK), one chunk: hits[0 .. m), found[0 .. m). */
static void intersect_chunk(const Tracer *tr, RTCScene scene, struct RTCIntersectContext *ctx, const TracerRay *r, int m,
                            bool packets, bool shade_all, SurfaceHit *hits, bool *found)
{
    struct RTCRayHit rh[TRACE_CHUNK];
    if (packets) {
        for (int p0 = 0; p0 < m; p0 += 16) {
            struct RTCRayHit16 pk;
            _Alignas(64) int valid[16]; /* Embree reads the mask and the packet 64-byte aligned */
            int c = m - p0 < 16 ? m - p0 : 16;
            packet16_fill(&pk.ray, valid, r + p0, c, tr->tracer_from_world);
            for (int i = 0; i < 16; ++i) pk.hit.geomID[i] = pk.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect16(valid, scene, ctx, &pk);
            for (int i = 0; i < c; ++i) { /* back to one RTCRayHit per ray for the shading below */
                struct RTCRayHit *h = &rh[p0 + i];
                h->ray.tfar = pk.ray.tfar[i];
                h->hit.u = pk.hit.u[i], h->hit.v = pk.hit.v[i];
                h->hit.primID = pk.hit.primID[i], h->hit.geomID = pk.hit.geomID[i];
                h->hit.instID[0] = pk.hit.instID[0][i];
            }
        }
    } else {
        for (int i = 0; i < m; ++i)
            init_rayhit(&rh[i], r[i].o, r[i].d, r[i].tmax, r[i].time01, tr->tracer_from_world, r[i].skip_mask);
        if (tr->batch_mode == TRACER_BATCH_STREAM)
            rtcIntersect1M(scene, ctx, rh, (unsigned)m, sizeof rh[0]);
        else
            for (int i = 0; i < m; ++i) rtcIntersect1(scene, ctx, &rh[i]);
    }
    if (!tr->top_spheres) {
        for (int i = 0; i < m; ++i)
            found[i] = hit_from_rayhit(tr, r[i].o, r[i].d, r[i].time01, shade_all, &rh[i], &hits[i]);
        return;
    }
    /* top-level sphere hits are shaded together, the others one by one */
    int spheres[TRACE_CHUNK], sphere_count = 0;
    for (int i = 0; i < m; ++i) {
        if (sphere_hit_batched(tr, &rh[i], shade_all)) spheres[sphere_count++] = i;
        else found[i] = hit_from_rayhit(tr, r[i].o, r[i].d, r[i].time01, shade_all, &rh[i], &hits[i]);
    }
    shade_sphere_hits(tr, r, rh, spheres, sphere_count, shade_all, hits, found);
}

void tracer_intersect_batch(const Tracer *tr, const TracerRay *rays, int n, bool shade_all, bool coherent,
                            SurfaceHit *hits, bool *found)
{
    RTCScene scene = tr->layers[0].scene;
    struct RTCIntersectContext ctx;
    bool packets = packets_of_16(tr, !coherent);
    context_init(tr, &ctx, coherent && !packets);
    for (int k0 = 0; k0 < n; k0 += TRACE_CHUNK)
        intersect_chunk(tr, scene, &ctx, rays + k0, n - k0 < TRACE_CHUNK ? n - k0 : TRACE_CHUNK, packets, shade_all,
                        hits + k0, found + k0);
}

/* Lane k of a as a TracerRay (tmax NULL: INFINITY). */
static inline TracerRay lane_ray(const TracerRayArrays *a, int k)
{
    return (TracerRay){v3(a->o[0][k], a->o[1][k], a->o[2][k]), v3(a->d[0][k], a->d[1][k], a->d[2][k]),
                       a->tmax ? a->tmax[k] : INFINITY, a->time01[k], a->skip_mask};
}

/* The fields of intersect_lanes_np's rays that are the same in every chunk of a call (Embree
 * only reads them). */
typedef struct {
    _Alignas(64) float tnear[TRACE_CHUNK];
    _Alignas(64) unsigned mask[TRACE_CHUNK], id[TRACE_CHUNK], flags[TRACE_CHUNK];
} NpConstants;

static void np_constants(NpConstants *c, unsigned skip_mask)
{
    for (int i = 0; i < TRACE_CHUNK; ++i) c->tnear[i] = 0.0f, c->mask[i] = ~skip_mask, c->id[i] = 0, c->flags[i] = 0;
}

/* Lanes k0 .. k0 + m of a (m <= TRACE_CHUNK) to Embree's stream as structure of arrays
 * (rtcIntersectNp): the directions and times by pointer into a, the origins and lengths
 * scaled as init_ray scales them. Embree's stream gathers the same packets in the same order
 * from these arrays as from init_rayhit's structs (embree 3.13 kernels/bvh/
 * bvh_intersector_stream_filters.cpp, filterSOP beside filterAOS; test_wave checks it), so
 * the hits are the same; what goes is the copy of every ray into a 112-byte RTCRayHit and
 * Embree's gather from it. The hits are shaded as intersect_chunk does, the lanes' rays
 * read in place. */
static void intersect_lanes_np(const Tracer *tr, RTCScene scene, struct RTCIntersectContext *ctx,
                               const TracerRayArrays *a, const NpConstants *fixed, int k0, int m, bool shade_all,
                               SurfaceHit *hits, bool *found)
{
    float k = tr->tracer_from_world;
    _Alignas(64) float ox[TRACE_CHUNK], oy[TRACE_CHUNK], oz[TRACE_CHUNK], tfar[TRACE_CHUNK];
    _Alignas(64) float ng[3][TRACE_CHUNK], u[TRACE_CHUNK], v[TRACE_CHUNK];
    _Alignas(64) unsigned prim[TRACE_CHUNK], geom[TRACE_CHUNK], inst[TRACE_CHUNK];
    const float *restrict o0 = a->o[0] + k0, *restrict o1 = a->o[1] + k0, *restrict o2 = a->o[2] + k0;
    for (int i = 0; i < m; ++i) ox[i] = k * o0[i], oy[i] = k * o1[i], oz[i] = k * o2[i];
    if (a->tmax) {
        const float *restrict tmax = a->tmax + k0;
        for (int i = 0; i < m; ++i) tfar[i] = k * tmax[i];
    } else {
        for (int i = 0; i < m; ++i) tfar[i] = k * INFINITY;
    }
    for (int i = 0; i < m; ++i) geom[i] = inst[i] = RTC_INVALID_GEOMETRY_ID;
    /* Embree writes only tfar and the hit fields; the const arrays are read */
    struct RTCRayHitNp np = {
        {ox, oy, oz, (float *)fixed->tnear, (float *)a->d[0] + k0, (float *)a->d[1] + k0, (float *)a->d[2] + k0,
         (float *)a->time01 + k0, tfar, (unsigned *)fixed->mask, (unsigned *)fixed->id, (unsigned *)fixed->flags},
        {ng[0], ng[1], ng[2], u, v, prim, geom, {inst}}};
    rtcIntersectNp(scene, ctx, &np, (unsigned)m);
    /* intersect_chunk's shading, the lanes read in place: a top-level sphere's hits (if any)
     * are shaded together afterwards, from TracerRays of their lanes alone */
    struct RTCRayHit rh[TRACE_CHUNK];
    int spheres[TRACE_CHUNK], sphere_count = 0;
    for (int i = 0; i < m; ++i) {
        /* a miss, and a triangle of the top level, from the arrays (hit_from_rayhit's first
         * cases, with no RTCRayHit filled for them) */
        if (geom[i] == RTC_INVALID_GEOMETRY_ID) {
            found[i] = false;
            continue;
        }
        if (inst[i] == RTC_INVALID_GEOMETRY_ID) {
            const Geom *g = &tr->layers[0].geoms[geom[i]];
            if (g->kind == GEOM_TRIANGLES) {
                top_triangle_hit(tr, g, (int)prim[i], (int)geom[i], tfar[i], u[i], v[i], shade_all, &hits[i]);
                found[i] = true;
                continue;
            }
        }
        struct RTCRayHit *h = &rh[i];
        h->ray.tfar = tfar[i], h->hit.u = u[i], h->hit.v = v[i];
        h->hit.primID = prim[i], h->hit.geomID = geom[i], h->hit.instID[0] = inst[i];
        if (tr->top_spheres && sphere_hit_batched(tr, h, shade_all)) {
            spheres[sphere_count++] = i;
            continue;
        }
        int q = k0 + i;
        found[i] = hit_from_rayhit(tr, v3(a->o[0][q], a->o[1][q], a->o[2][q]), v3(a->d[0][q], a->d[1][q], a->d[2][q]),
                                   a->time01[q], shade_all, h, &hits[i]);
    }
    if (sphere_count == 0) return;
    TracerRay r[TRACE_CHUNK];
    for (int j = 0; j < sphere_count; ++j) r[spheres[j]] = lane_ray(a, k0 + spheres[j]);
    shade_sphere_hits(tr, r, rh, spheres, sphere_count, shade_all, hits, found);
}

void tracer_intersect_arrays(const Tracer *tr, const TracerRayArrays *a, int n, bool shade_all, bool coherent,
                             SurfaceHit *hits, bool *found)
{
    RTCScene scene = tr->layers[0].scene;
    struct RTCIntersectContext ctx;
    bool packets = packets_of_16(tr, !coherent);
    context_init(tr, &ctx, coherent && !packets);
    if (tr->batch_mode == TRACER_BATCH_STREAM && !packets) {
        NpConstants fixed;
        np_constants(&fixed, a->skip_mask);
        for (int k0 = 0; k0 < n; k0 += TRACE_CHUNK)
            intersect_lanes_np(tr, scene, &ctx, a, &fixed, k0, n - k0 < TRACE_CHUNK ? n - k0 : TRACE_CHUNK, shade_all,
                               hits + k0, found + k0);
        return;
    }
    TracerRay chunk[TRACE_CHUNK];
    for (int k0 = 0; k0 < n; k0 += TRACE_CHUNK) {
        int m = n - k0 < TRACE_CHUNK ? n - k0 : TRACE_CHUNK;
        for (int i = 0; i < m; ++i) chunk[i] = lane_ray(a, k0 + i);
        intersect_chunk(tr, scene, &ctx, chunk, m, packets, shade_all, hits + k0, found + k0);
    }
}

static void occluded_rays(const Tracer *tr, RTCScene scene, struct RTCIntersectContext *ctx, struct RTCRay *ray,
                          const int *key, uint64_t counts, int m, bool *occluded);

/* tracer_occluded_batch's rays r[0 .. m) (m <= TRACE_CHUNK), one chunk: answers to occluded[0 .. m). */
static void occluded_chunk(const Tracer *tr, RTCScene scene, struct RTCIntersectContext *ctx, const TracerRay *r, int m,
                           bool packets, bool *occluded)
{
    struct RTCRay ray[TRACE_CHUNK];
    if (packets) {
        for (int p0 = 0; p0 < m; p0 += 16) {
            struct RTCRay16 pk;
            _Alignas(64) int valid[16]; /* Embree reads the mask and the packet 64-byte aligned */
            int c = m - p0 < 16 ? m - p0 : 16;
            packet16_fill(&pk, valid, r + p0, c, tr->tracer_from_world);
            rtcOccluded16(valid, scene, ctx, &pk);
            for (int i = 0; i < c; ++i) occluded[p0 + i] = pk.tfar[i] == -INFINITY;
        }
        return;
    }
    int key[TRACE_CHUNK];
    uint64_t counts = 0; /* rays per octant, a byte each (no chain through memory) */
    for (int i = 0; i < m; ++i) {
        init_ray(&ray[i], r[i].o, r[i].d, r[i].tmax, r[i].time01, tr->tracer_from_world, r[i].skip_mask);
        key[i] = ray_octant(r[i].d);
        counts += 1ull << (8 * key[i]);
    }
    occluded_rays(tr, scene, ctx, ray, key, counts, m, occluded);
}

/* Embree's occlusion of ray[0 .. m) as they are ordered: one stream call in the stream mode,
 * else a call a ray (tfar -INFINITY: occluded). */
static void occluded_in_order(const Tracer *tr, RTCScene scene, struct RTCIntersectContext *ctx, struct RTCRay *ray,
                              int m)
{
    if (tr->batch_mode == TRACER_BATCH_STREAM)
        rtcOccluded1M(scene, ctx, ray, (unsigned)m, sizeof ray[0]);
    else
        for (int i = 0; i < m; ++i) rtcOccluded1(scene, ctx, &ray[i]);
}

/* occluded_chunk's rays in Embree's layout (not a packet mode), with each one's octant key
 * and the chunk's counts per octant: the answers. */
static void occluded_rays(const Tracer *tr, RTCScene scene, struct RTCIntersectContext *ctx, struct RTCRay *ray,
                          const int *key, uint64_t counts, int m, bool *occluded)
{
    _Static_assert(TRACE_CHUNK < 256, "a chunk's count per octant fits a byte");
    if (tr->batch_mode == TRACER_BATCH_STREAM && m > 0 && counts != (uint64_t)m << (8 * key[0])) {
        /* octants mixed: the chunk's rays to Embree by octant, the answers back in place */
        int order[TRACE_CHUNK + 1];
        struct RTCRay sorted[TRACE_CHUNK];
        octant_order(key, counts, m, order);
        for (int j = 0; j < m; ++j) sorted[j] = ray[order[j]];
        rtcOccluded1M(scene, ctx, sorted, (unsigned)m, sizeof sorted[0]);
        for (int j = 0; j < m; ++j) occluded[order[j]] = sorted[j].tfar == -INFINITY;
        return;
    }
    occluded_in_order(tr, scene, ctx, ray, m);
    for (int i = 0; i < m; ++i) occluded[i] = ray[i].tfar == -INFINITY;
}

void tracer_occluded_batch(const Tracer *tr, const TracerRay *rays, int n, bool coherent, bool *occluded)
{
    RTCScene scene = tr->layers[0].scene;
    struct RTCIntersectContext ctx;
    bool packets = packets_of_16(tr, !coherent);
    context_init(tr, &ctx, coherent && tr->shadow_coherent_ok && !packets);
    for (int k0 = 0; k0 < n; k0 += TRACE_CHUNK)
        occluded_chunk(tr, scene, &ctx, rays + k0, n - k0 < TRACE_CHUNK ? n - k0 : TRACE_CHUNK, packets, occluded + k0);
}

/* tracer_occluded_arrays' packets (packets_of_16): a's active lanes, 16 at a time in their
 * order, gathered from the arrays straight into Embree's packets (no TracerRay between). An
 * inactive lane costs a compare: the active ones are listed first (written for every lane,
 * kept for the active ones: no branch on a lane's flag). */
static void occluded_lanes_packets(const Tracer *tr, RTCScene scene, struct RTCIntersectContext *ctx,
                                   const TracerRayArrays *a, int n, bool *occluded)
{
    float k = tr->tracer_from_world;
    int lane[16];
    for (int i = 0; i < n;) {
        int c = 0;
        for (; i < n && c < 16; ++i) {
            lane[c] = i;
            c += a->active[i] != 0;
        }
        if (c == 0) break;
        struct RTCRay16 pk;
        _Alignas(64) int valid[16]; /* Embree reads the mask and the packet 64-byte aligned */
        for (int j = 0; j < 16; ++j) {
            int q = lane[j < c ? j : 0]; /* lanes past c: off, filled with the first ray */
            valid[j] = j < c ? -1 : 0;
            pk.org_x[j] = k * a->o[0][q], pk.org_y[j] = k * a->o[1][q], pk.org_z[j] = k * a->o[2][q]; /* as init_ray */
            pk.dir_x[j] = a->d[0][q], pk.dir_y[j] = a->d[1][q], pk.dir_z[j] = a->d[2][q];
            pk.tnear[j] = 0.0f;
            pk.tfar[j] = k * (a->tmax ? a->tmax[q] : INFINITY);
            pk.time[j] = a->time01[q];
            pk.mask[j] = ~a->skip_mask;
            pk.id[j] = 0;
            pk.flags[j] = 0;
        }
        rtcOccluded16(valid, scene, ctx, &pk);
        for (int j = 0; j < c; ++j) occluded[lane[j]] = pk.tfar[j] == -INFINITY;
    }
}

/* How many direction octants (ray_octant's) a's active lanes 0 .. n use: each lane's octant
 * as one bit of eight, or-ed together, an inactive lane's bit masked off. Every lane's octant
 * is computed, so that no compare waits on the lane's flag: with the compares under it, GCC
 * made the loop a branch per lane (C11's -ftrapping-math keeps it from comparing the floats of
 * lanes the source does not compare); compiled for AVX2 and AVX-512 as well
 * (WEDGE_VECTORISED), as the per-lane shift by a variable count has no SSE2 form. It was 0.7%
 * of envlight's CPU lane by lane (docs/design.md 12.35). Only the route depends on it: an
 * occlusion answer does not depend on how the rays are grouped (12.18). */
static WEDGE_VECTORISED int lanes_octants(const TracerRayArrays *a, int n)
{
    const int *restrict active = a->active;
    const float *restrict dx = a->d[0], *restrict dy = a->d[1], *restrict dz = a->d[2];
    unsigned used = 0u;
    for (int i = 0; i < n; ++i) {
        unsigned key = (unsigned)(dx[i] < 0.0f) | (unsigned)(dy[i] < 0.0f) << 1 | (unsigned)(dz[i] < 0.0f) << 2;
        used |= (1u << key) & (0u - (unsigned)(active[i] != 0));
    }
    return __builtin_popcount(used);
}

/* Whether a's arrays may be given to Embree as a stream's as they are: 16-byte aligned, as
 * Embree asks (chunks start 64 lanes apart, so a chunk's arrays are aligned with them). The
 * delta lights' arrays are (integrator.c, WaveDeltaSamples); the triangle and sky groups'
 * (WaveTriangleSamples) are not, and keep the sorted rays: aligned, their lanes as arrays
 * took 2% more CPU on tilted_stack (docs/benchmarks.md, "Issue 22, thirty-eighth round"). */
static bool lanes_stream_aligned(const TracerRayArrays *a)
{
    uintptr_t bits = (uintptr_t)a->time01;
    for (int c = 0; c < 3; ++c) bits |= (uintptr_t)a->o[c] | (uintptr_t)a->d[c];
    return (bits & 15u) == 0u;
}

/* Lanes k0 .. k0 + m (m <= TRACE_CHUNK) of a (lanes_stream_aligned) to Embree's
 * structure-of-arrays stream (rtcOccludedNp) as they are: origins, directions and times by
 * pointer into a, the origins scaled into a copy where the tracer's scale is not 1 (as
 * init_ray scales them; k o = o exactly where k = 1); the lengths scaled into a small array in
 * which an inactive lane gets tfar -1 < tnear 0, a ray a stream skips, and whose answer is not
 * written. No RTCRay is filled, none copied to be sorted, and Embree gathers no packet from
 * 48-byte rays: what occluded_rays costs per ray. */
static void occluded_lanes_np(const Tracer *tr, RTCScene scene, struct RTCIntersectContext *ctx,
                              const TracerRayArrays *a, const NpConstants *fixed, int k0, int m, bool *occluded)
{
    float k = tr->tracer_from_world;
    _Alignas(64) float o_copy[3][TRACE_CHUNK], tfar[TRACE_CHUNK];
    const int *restrict active = a->active + k0;
    const float *o[3];
    for (int c = 0; c < 3; ++c) {
        o[c] = a->o[c] + k0;
        if (k != 1.0f) {
            for (int i = 0; i < m; ++i) o_copy[c][i] = k * o[c][i];
            o[c] = o_copy[c];
        }
    }
    if (a->tmax) {
        const float *restrict tmax = a->tmax + k0;
        for (int i = 0; i < m; ++i) tfar[i] = active[i] != 0 ? k * tmax[i] : -1.0f;
    } else {
        for (int i = 0; i < m; ++i) tfar[i] = active[i] != 0 ? k * INFINITY : -1.0f;
    }
    /* Embree writes tfar alone (-inf where occluded); the const arrays are read */
    struct RTCRayNp np = {(float *)o[0],
                          (float *)o[1],
                          (float *)o[2],
                          (float *)fixed->tnear,
                          (float *)a->d[0] + k0,
                          (float *)a->d[1] + k0,
                          (float *)a->d[2] + k0,
                          (float *)a->time01 + k0,
                          tfar,
                          (unsigned *)fixed->mask,
                          (unsigned *)fixed->id,
                          (unsigned *)fixed->flags};
    rtcOccludedNp(scene, ctx, &np, (unsigned)m);
    for (int i = 0; i < m; ++i)
        if (active[i] != 0) occluded[k0 + i] = tfar[i] == -INFINITY;
}

/* The active lanes of a (n lanes) straight into Embree's rays, as occluded_chunk fills them
 * from TracerRays (no TracerRay between), in chunks of TRACE_CHUNK active lanes; a chunk whose
 * rays mix direction octants goes to Embree grouped by octant, each octant's rays in their
 * order: what occluded_rays hands it (octant_order), written there in one pass (each ray
 * straight to its place, after its octant's count) instead of built, listed and copied. */
static void occluded_lanes_sorted(const Tracer *tr, RTCScene scene, struct RTCIntersectContext *ctx,
                                  const TracerRayArrays *a, int n, bool *occluded)
{
    _Static_assert(TRACE_CHUNK < 256, "a chunk's count per octant fits a byte");
    const float *restrict ox = a->o[0], *restrict oy = a->o[1], *restrict oz = a->o[2];
    const float *restrict dx = a->d[0], *restrict dy = a->d[1], *restrict dz = a->d[2];
    const float *restrict tmax = a->tmax, *restrict time01 = a->time01;
    const int *restrict active = a->active;
    float k = tr->tracer_from_world;
    unsigned skip_mask = a->skip_mask;
    struct RTCRay ray[TRACE_CHUNK];
    int lane[TRACE_CHUNK + 1], key[TRACE_CHUNK + 1], place[TRACE_CHUNK];
    for (int i = 0; i < n;) {
        /* the chunk's lanes (the next TRACE_CHUNK active ones; the branch-free compaction
         * writes one past) and their octants */
        int m = 0;
        for (; i < n && m < TRACE_CHUNK; ++i) {
            lane[m] = i;
            key[m] = ray_octant(v3(dx[i], dy[i], dz[i]));
            m += active[i] != 0;
        }
        if (m == 0) break;
        int count[8] = {0};
        for (int j = 0; j < m; ++j) ++count[key[j]];
        /* each octant's first place (one octant: every ray where it is) */
        int first[8], at = 0;
        for (int o = 0; o < 8; ++o) first[o] = at, at += count[o];
        for (int j = 0; j < m; ++j) place[j] = first[key[j]]++;
        for (int j = 0; j < m; ++j) {
            int q = lane[j];
            init_ray(&ray[place[j]], v3(ox[q], oy[q], oz[q]), v3(dx[q], dy[q], dz[q]), tmax ? tmax[q] : INFINITY,
                     time01[q], k, skip_mask);
        }
        occluded_in_order(tr, scene, ctx, ray, m);
        for (int j = 0; j < m; ++j) occluded[lane[j]] = ray[place[j]].tfar == -INFINITY;
    }
}

/* tracer_occluded_arrays hands Embree the lanes themselves (occluded_lanes_np) when their
 * active rays use at most this many direction octants. Embree's coherent stream walks a group
 * of rays together only where they share an octant (12.18), so unsorted lanes of many
 * octants (a sky's cosine-distributed rays) trace slower than the same rays sorted; the
 * rays of a wave's few pixels to a point light use one or two, a distant light's one
 * (docs/benchmarks.md, "Issue 22, thirty-eighth round"). */
enum { OCCLUDED_NP_OCTANTS = 2 };

void tracer_occluded_arrays(const Tracer *tr, const TracerRayArrays *a, int n, bool coherent, bool *occluded)
{
    RTCScene scene = tr->layers[0].scene;
    struct RTCIntersectContext ctx;
    int active = 0;
    for (int i = 0; i < n; ++i) active += a->active[i] != 0;
    /* lanes mostly inactive (the delta lights' lanes of dead paths and of receivers facing
     * away: integrator.c, WaveDeltaSamples) are scattered receivers' rays: packets, as
     * incoherent rays (packets_of_16) */
    bool packets = packets_of_16(tr, !coherent || 2 * active < n);
    context_init(tr, &ctx, coherent && tr->shadow_coherent_ok && !packets);
    if (packets) {
        occluded_lanes_packets(tr, scene, &ctx, a, n, occluded);
        return;
    }
    if (tr->batch_mode == TRACER_BATCH_STREAM && lanes_stream_aligned(a) && lanes_octants(a, n) <= OCCLUDED_NP_OCTANTS) {
        /* the lanes as Embree's arrays, chunk by chunk: an occlusion answer does not depend
         * on the order or grouping of the rays (12.18) */
        NpConstants fixed;
        np_constants(&fixed, a->skip_mask);
        for (int k0 = 0; k0 < n; k0 += TRACE_CHUNK)
            occluded_lanes_np(tr, scene, &ctx, a, &fixed, k0, n - k0 < TRACE_CHUNK ? n - k0 : TRACE_CHUNK, occluded);
        return;
    }
    occluded_lanes_sorted(tr, scene, &ctx, a, n, occluded);
}
