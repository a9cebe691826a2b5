/* MAAF's light table (maaf_lights.h) against the direct form it replaced: every light's centroid,
 * first-edge axes and extent found by a pass over every light of its shape (the triangle's own
 * normal setting the axes), its sweep copied from the shape's first triangle that has one, its
 * design made afresh. The table must be the same bit for bit on a planar mesh light (its
 * triangles' normals differ in the last bits), a curved one (every triangle its own axes), a
 * moving mesh light, a quad, a lone triangle (each vertex an extreme of its box), a sphere and a
 * point light in one scene; and every triangle's box
 * must hold every vertex of its shape along its axes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/aaf/aaf_stats.h"
#include "recon/maaf/maaf_filter.h"
#include "recon/maaf/maaf_light_sweep.h"
#include "recon/maaf/maaf_lights.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

static float dot3(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static bool same_shape(const RenderLightInfo *info, int l, int k)
{
    return k == l || (info[l].shape >= 0 && info[k].kind == RENDER_LIGHT_AREA && info[k].shape == info[l].shape);
}

/* The direct form: each light looks at every other light. */
static void direct_table(const Renderer *r, const AafLightGeom *geoms, int count, int pairs, float kappa, MaafLight *out)
{
    RenderLightInfo *info = calloc((size_t)count, sizeof *info);
    MaafSweep **poses = calloc((size_t)count, sizeof *poses); /* each sweeping light's own */
    for (int l = 0; l < count; ++l)
        if (!renderer_light_info(r, l, &info[l])) info[l].kind = RENDER_LIGHT_POINT;
    for (int l = 0; l < count; ++l) {
        MaafLight *ml = &out[l];
        memset(ml, 0, sizeof *ml);
        if (info[l].kind != RENDER_LIGHT_AREA || !(geoms[l].sigma_world > 0.0f)) continue;
        double c[3] = {0, 0, 0}, area = 0.0;
        for (int k = 0; k < count; ++k) {
            if (!same_shape(info, l, k)) continue;
            c[0] += info[k].area_world * info[k].center_world.x;
            c[1] += info[k].area_world * info[k].center_world.y;
            c[2] += info[k].area_world * info[k].center_world.z;
            area += info[k].area_world;
        }
        for (int k = 0; k < 3; ++k) ml->center[k] = area > 0.0 ? (float)(c[k] / area) : 0.0f;
        const float *n = geoms[l].normal;
        bool planar = dot3(n, n) > 0.5f;
        if (planar && info[l].is_triangle) {
            int first = l;
            for (int k = 0; k < l && first == l; ++k)
                if (same_shape(info, l, k) && k != l && info[k].is_triangle) first = k;
            const RenderLightInfo *ft = &info[first];
            float e[3] = {ft->tri_world[1].x - ft->tri_world[0].x, ft->tri_world[1].y - ft->tri_world[0].y,
                          ft->tri_world[1].z - ft->tri_world[0].z};
            float en = dot3(e, n);
            for (int k = 0; k < 3; ++k) e[k] -= en * n[k];
            float len = sqrtf(dot3(e, e));
            for (int k = 0; k < 3; ++k) ml->t1[k] = len > 0.0f ? e[k] / len : 0.0f;
            ml->t2[0] = n[1] * ml->t1[2] - n[2] * ml->t1[1];
            ml->t2[1] = n[2] * ml->t1[0] - n[0] * ml->t1[2];
            ml->t2[2] = n[0] * ml->t1[1] - n[1] * ml->t1[0];
            ml->lo[0] = ml->lo[1] = INFINITY;
            ml->hi[0] = ml->hi[1] = -INFINITY;
            for (int k = 0; k < count; ++k) {
                if (!same_shape(info, l, k) || !info[k].is_triangle) continue;
                for (int v = 0; v < 3; ++v) {
                    float d[3] = {info[k].tri_world[v].x - ml->center[0], info[k].tri_world[v].y - ml->center[1],
                                  info[k].tri_world[v].z - ml->center[2]};
                    float a = dot3(d, ml->t1), b = dot3(d, ml->t2);
                    ml->lo[0] = fminf(ml->lo[0], a), ml->hi[0] = fmaxf(ml->hi[0], a);
                    ml->lo[1] = fminf(ml->lo[1], b), ml->hi[1] = fmaxf(ml->hi[1], b);
                }
            }
        } else {
            if (planar) maaf_basis(n, ml->t1, ml->t2);
            float half = 0.5f * sqrtf((float)M_PI) * geoms[l].radius_world;
            ml->lo[0] = ml->lo[1] = -half;
            ml->hi[0] = ml->hi[1] = half;
        }
        bool copied_sweep = false;
        for (int k = 0; info[l].moving && info[l].shape >= 0 && info[l].is_triangle && k < l && !copied_sweep; ++k) {
            const MaafLight *mk = &out[k];
            if (info[k].kind != RENDER_LIGHT_AREA || info[k].shape != info[l].shape || !info[k].is_triangle ||
                !info[k].moving || mk->sweep_nodes == 0)
                continue;
            memcpy(ml->center, mk->center, sizeof ml->center);
            memcpy(ml->lo, mk->lo, sizeof ml->lo);
            memcpy(ml->hi, mk->hi, sizeof ml->hi);
            ml->sweep = mk->sweep;
            ml->sweep_nodes = mk->sweep_nodes;
            copied_sweep = true;
        }
        if (info[l].moving && !copied_sweep) {
            poses[l] = malloc(sizeof *poses[l]);
            maaf_light_sweep(r, l, 0.5f * sqrtf((float)M_PI) * geoms[l].radius_world, poses[l], ml);
        }
        if (!(ml->hi[0] > ml->lo[0]) || !(ml->hi[1] > ml->lo[1]) || !isfinite(ml->hi[0] - ml->lo[0] + ml->hi[1] - ml->lo[1]))
            continue;
        maaf_light_design(geoms[l].sigma_world / kappa, pairs, ml);
    }
    for (int l = 0; l < count; ++l) out[l].sweep = NULL, free(poses[l]); /* as the table leaves them */
    free(poses);
    free(info);
}

/* An n x n grid of quads as one emitter, curved (a half cylinder) or flat, optionally moving. */
static void append_mesh_light(char *s, size_t cap, int n, bool curved, bool moving)
{
    size_t at = strlen(s);
    at += (size_t)snprintf(s + at, cap - at, "AttributeBegin\n%s  AreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ] \"bool twosided\" true\n"
                                             "  Shape \"trianglemesh\" \"point3 P\" [",
                           moving ? "  ActiveTransform EndTime\n  Translate 0.4 0 0.1\n  ActiveTransform All\n" : "");
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            double u = (double)i / n, v = (double)j / n, a = M_PI * u;
            double x = curved ? -0.8 * cos(a) : -0.8 + 1.6 * u, y = curved ? 2.6 - 0.5 * sin(a) : 2.5 + 0.01 * i;
            at += (size_t)snprintf(s + at, cap - at, " %.9g %.9g %.9g", x, y, -0.7 + 1.3 * v + (curved ? 3.0 : 0.0));
        }
    at += (size_t)snprintf(s + at, cap - at, " ] \"integer indices\" [");
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            at += (size_t)snprintf(s + at, cap - at, " %d %d %d %d %d %d", a, c, b, b, c, d);
        }
    snprintf(s + at, cap - at, " ]\nAttributeEnd\n");
}

static void check_scene(const char *what, bool moving)
{
    enum { CAP = 1 << 20 };
    char *s = malloc(CAP);
    snprintf(s, CAP,
             "LookAt 0 2 -5  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
             "Sampler \"stratified\" \"integer pixelsamples\" [ 4 ]\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
             "LightSource \"point\" \"point3 from\" [ 1 3 0 ] \"rgb I\" [ 1 1 1 ]\n"
             "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
             "  Shape \"trianglemesh\" \"point3 P\" [ 1.5 2 -0.5  2.5 2 -0.5  2.5 2 0.5  1.5 2 0.5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "AttributeEnd\n"
             "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
             "  Shape \"trianglemesh\" \"point3 P\" [ -2.5 2 1  -1.5 2.1 1  -2.2 2.2 1.8 ] \"integer indices\" [ 0 1 2 ]\n"
             "AttributeEnd\n"
             "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n  Translate -2 1.5 0\n  Shape \"sphere\" \"float radius\" [ 0.2 ]\nAttributeEnd\n");
    append_mesh_light(s, CAP, 12, false, moving);
    append_mesh_light(s, CAP, 13, true, false); /* 196 vertices: past EXTENT_PLAIN_MAX, the tree's path */
    SceneDesc scene;
    Diag d = {0};
    bool parsed = scene_parse_string(s, strlen(s), "<test>", NULL, &scene, &d);
    CHECK(parsed);
    if (!parsed) {
        fprintf(stderr, "%s\n", d.message);
        free(s);
        return;
    }
    scene_analyze_effects(&scene);
    RenderOptions ro;
    memset(&ro, 0, sizeof ro);
    ro.spp = 4;
    ro.threads = 1;
    Renderer *r = NULL;
    CHECK(renderer_create(&scene, &ro, &r, &d));
    int count = r ? renderer_light_count(r) : 0;
    CHECK(count == 2 + 2 + 1 + 2 * 144 + 2 * 169);
    AafLightGeom *geoms = calloc((size_t)count, sizeof *geoms);
    MaafLight *fast = calloc((size_t)count, sizeof *fast), *direct = calloc((size_t)count, sizeof *direct);
    aaf_lights_from_renderer(r, geoms, count);
    const int pairs = 3;
    const float kappa = 4.0f;
    maaf_lights_from_renderer(r, geoms, count, pairs, kappa, fast);
    direct_table(r, geoms, count, pairs, kappa, direct);
    int differ = 0, designed = 0, outside = 0, moving_lights = 0, poses_left = 0;
    for (int l = 0; l < count; ++l) {
        differ += memcmp(&fast[l], &direct[l], sizeof fast[l]) != 0;
        designed += fast[l].omega_y_max > 0.0f;
        poses_left += fast[l].sweep != NULL;
        moving_lights += fast[l].sweep_nodes > 0;
        RenderLightInfo b, o;
        if (!renderer_light_info(r, l, &b) || b.kind != RENDER_LIGHT_AREA || !b.is_triangle || b.moving || fast[l].omega_y_max <= 0.0f)
            continue;
        for (int k = 0; k < count; ++k) { /* every vertex of the shape inside the triangle's box */
            if (!renderer_light_info(r, k, &o) || o.kind != RENDER_LIGHT_AREA || o.shape != b.shape) continue;
            for (int v = 0; v < 3; ++v) {
                float q[3] = {o.tri_world[v].x - fast[l].center[0], o.tri_world[v].y - fast[l].center[1],
                              o.tri_world[v].z - fast[l].center[2]};
                float a = dot3(q, fast[l].t1), c = dot3(q, fast[l].t2);
                outside += !(a >= fast[l].lo[0] && a <= fast[l].hi[0] && c >= fast[l].lo[1] && c <= fast[l].hi[1]);
            }
        }
    }
    printf("%s: %d lights, %d designed, %d moving; %d differ from the direct form, %d vertices outside a box\n", what, count,
           designed, moving_lights, differ, outside);
    CHECK(designed == count - 1); /* every area light but none of the point light */
    CHECK(moving_lights == (moving ? 2 * 144 : 0));
    CHECK(differ == 0);
    CHECK(outside == 0);
    CHECK(poses_left == 0); /* the table owns no memory */
    free(geoms), free(fast), free(direct);
    if (r) renderer_destroy(r);
    scene_desc_free(&scene);
    free(s);
}

int main(void)
{
    check_scene("static mesh lights", false);
    check_scene("a moving mesh light", true);
    return check_failures ? 1 : 0;
}
