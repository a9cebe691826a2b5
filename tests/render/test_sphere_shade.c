/* Sphere hits shaded in a batch (sphere_shade_batch, through tracer_intersect_batch) against
 * the same rays shaded one by one (tracer_intersect_ex: shade_hit), every SurfaceHit field
 * bit for bit. Spheres translated, rotated and unevenly scaled, with reversed orientation,
 * tiny and far from the origin (where the scene is scaled for Embree), several in one chunk
 * of rays, and at the top level only (an instanced one and a sphere whose uv is read take
 * the one-by-one path in both). Rays from all around each sphere towards points inside
 * it, some of them tangent at the rim. */
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/tracer.h"
#include "render/warp.h"
#include "render_test_util.h"

enum { RAYS = 6000 };

/* Every field shade_hit writes, compared by bits (padding excluded). */
static bool same_hit(const SurfaceHit *a, const SurfaceHit *b)
{
    return !memcmp(&a->t, &b->t, sizeof a->t) && !memcmp(&a->p, &b->p, sizeof a->p) &&
           !memcmp(&a->ng, &b->ng, sizeof a->ng) && !memcmp(&a->ns, &b->ns, sizeof a->ns) &&
           !memcmp(&a->uv, &b->uv, sizeof a->uv) && !memcmp(&a->err, &b->err, sizeof a->err) && a->geom == b->geom &&
           a->prim == b->prim && a->instance == b->instance && a->object_id == b->object_id && a->light == b->light;
}

/* Rays towards spheres of centres c[] and radii r[] (world units); every hit of the batch
 * and of the single rays must agree, and at least min_hits of the rays must hit. */
static void check_scene(const char *text, int spheres, const vec3 *c, const float *r, bool uv_unread, long min_hits)
{
    SceneDesc scene;
    Tracer tr;
    bool built = test_build_tracer(text, &scene, &tr);
    CHECK(built);
    if (!built) return;
    /* the renderer sets it (no material reads uv); tracer_build leaves it false */
    for (int i = 0; i < tr.layers[0].geom_count; ++i) tr.layers[0].geoms[i].uv_unread = uv_unread;
    Pcg32 rng;
    pcg32_seed(&rng, 23, 5);
    static TracerRay rays[RAYS];
    static SurfaceHit batch[RAYS], single[RAYS];
    static bool found[RAYS];
    for (int i = 0; i < RAYS; ++i) {
        int s = (int)(pcg32_float(&rng) * (float)spheres) % spheres;
        vec3 dir_o = warp_uniform_sphere(v2(pcg32_float(&rng), pcg32_float(&rng)));
        vec3 o = v3_add(c[s], v3_scale(dir_o, r[s] * (1.5f + 4.0f * pcg32_float(&rng))));
        vec3 target = v3_add(c[s], v3_scale(warp_uniform_sphere(v2(pcg32_float(&rng), pcg32_float(&rng))),
                                            r[s] * pcg32_float(&rng)));
        if (pcg32_float(&rng) < 0.3f) { /* at the rim, give or take a little */
            vec3 to_c = v3_normalize(v3_sub(c[s], o));
            vec3 side = v3_normalize(v3_cross(to_c, warp_uniform_sphere(v2(pcg32_float(&rng), pcg32_float(&rng)))));
            target = v3_add(c[s], v3_scale(side, r[s] * (1.0f + 1e-6f * (pcg32_float(&rng) - 0.5f))));
        }
        rays[i] = (TracerRay){o, v3_normalize(v3_sub(target, o)), INFINITY, 0.0f, 0u};
    }
    tracer_intersect_batch(&tr, rays, RAYS, true, true, batch, found);
    long hits = 0, differ = 0;
    for (int i = 0; i < RAYS; ++i) {
        bool ref = tracer_intersect_ex(&tr, rays[i].o, rays[i].d, rays[i].tmax, rays[i].time01, true, &single[i]);
        hits += ref;
        differ += ref != found[i] || (ref && !same_hit(&batch[i], &single[i]));
    }
    printf("%d rays, %ld hits, %ld differ\n", RAYS, hits, differ);
    CHECK(differ == 0);
    CHECK(hits >= min_hits);
    tracer_free(&tr);
    scene_desc_free(&scene);
}

int main(void)
{
    const char *camera = "LookAt 0 0 -6  0 0 0  0 1 0 Camera \"perspective\" WorldBegin\n";
    char text[2048];
    /* three spheres: translated; rotated and unevenly scaled, reversed; tiny */
    snprintf(text, sizeof text,
             "%sAttributeBegin Translate -1.2 0.3 0.7 Shape \"sphere\" \"float radius\" [ 0.8 ] AttributeEnd\n"
             "AttributeBegin Translate 2 -1 3 Rotate 30 1 2 3 Scale 1 0.5 2 ReverseOrientation\n"
             "  Shape \"sphere\" \"float radius\" [ 0.6 ] AttributeEnd\n"
             "AttributeBegin Translate 0.1 1.9 -0.4 Shape \"sphere\" \"float radius\" [ 0.001 ] AttributeEnd\n",
             camera);
    const vec3 c3[3] = {v3(-1.2f, 0.3f, 0.7f), v3(2.0f, -1.0f, 3.0f), v3(0.1f, 1.9f, -0.4f)};
    const float r3[3] = {0.8f, 0.6f, 0.001f};
    check_scene(text, 3, c3, r3, true, RAYS / 3);
    /* the same with uv read: shade_hit for both */
    check_scene(text, 3, c3, r3, false, RAYS / 3);
    /* far from the origin: the scene scaled for Embree */
    const vec3 cf = v3(3e6f, -1e6f, 2e6f);
    const float rf = 2e6f;
    check_scene("LookAt 0 0 -6e6  0 0 0  0 1 0 Camera \"perspective\" WorldBegin\n"
                "AttributeBegin Translate 3e6 -1e6 2e6 Shape \"sphere\" \"float radius\" [ 2e6 ] AttributeEnd\n",
                1, &cf, &rf, true, RAYS / 3);
    /* an instanced sphere: shaded by shade_hit through the instance */
    const vec3 ci = v3(0.5f, 0.0f, 1.0f);
    const float ri = 0.7f;
    snprintf(text, sizeof text,
             "%sObjectBegin \"ball\" Shape \"sphere\" \"float radius\" [ 0.7 ] ObjectEnd\n"
             "AttributeBegin Translate 0.5 0 1 ObjectInstance \"ball\" AttributeEnd\n",
             camera);
    check_scene(text, 1, &ci, &ri, true, RAYS / 3);
    CHECK_DONE();
}
