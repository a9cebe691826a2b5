/* Sphere hits shaded in a batch (sphere_shade_batch, sphere_shade_batch_translated, through
 * tracer_intersect_batch) against the same rays shaded one by one (tracer_intersect_ex:
 * shade_hit), every SurfaceHit field bit for bit; and a top-level translated sphere's hit
 * (shaded mostly in float) against the closed form in double within its error bound. Spheres
 * translated, rotated and unevenly scaled, with reversed orientation, tiny, far from the
 * origin (where the scene is scaled for Embree) and small at 3700 from it with a centre that
 * is not a float, several in one chunk of rays, and at the top level only (an instanced one
 * and a sphere whose uv is read take the one-by-one path in both). Rays from all around each
 * sphere towards points inside it, some of them tangent at the rim. */
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
    /* a top-level translated sphere's hit against the closed form in double from the same t
     * (docs/algorithms.md, "A translated sphere's hit in float"): the normal within
     * 16 eps (|o - c| + t) / r + 8 eps, the point within r times that plus two roundings of
     * a coordinate of size |c| + r (eps = 2^-23) */
    long closed = 0, beyond = 0;
    double worst = 0.0;
    for (int i = 0; i < RAYS; ++i) {
        const SurfaceHit *h = &batch[i];
        if (!found[i] || h->instance >= 0 || h->geom->kind != GEOM_SPHERE || !h->geom->object_translation_only) continue;
        const Geom *g = h->geom;
        double c[3] = {g->geom_from_object.m[0][3], g->geom_from_object.m[1][3], g->geom_from_object.m[2][3]}, v[3];
        double oc = 0.0, len = 0.0, cmax = 0.0, sign = g->flip_normal ? -1.0 : 1.0;
        for (int j = 0; j < 3; ++j) {
            double o = (double)v3_get(rays[i].o, j) - c[j];
            v[j] = o + (double)h->t * (double)v3_get(rays[i].d, j);
            oc += o * o, len += v[j] * v[j], cmax = fmax(cmax, fabs(c[j]));
        }
        len = sqrt(len);
        double eps = 0x1p-23, n_bound = 16.0 * eps * (sqrt(oc) + h->t) / g->radius + 8.0 * eps;
        double p_bound = g->radius * n_bound + 2.0 * eps * (cmax + g->radius), n_err = 0.0, p_err = 0.0;
        for (int j = 0; j < 3; ++j) {
            double n = v[j] / len;
            n_err = fmax(n_err, fabs(sign * (double)v3_get(h->ng, j) - n));
            p_err = fmax(p_err, fabs((double)v3_get(h->p, j) - (c[j] + g->radius * n)));
        }
        ++closed;
        beyond += !(n_err <= n_bound && p_err <= p_bound);
        worst = fmax(worst, fmax(n_err / n_bound, p_err / p_bound));
    }
    printf("%d rays, %ld hits, %ld differ; %ld translated-sphere hits against the closed form, %ld beyond the "
           "bound, worst %.3g of it\n",
           RAYS, hits, differ, closed, beyond, worst);
    CHECK(beyond == 0);
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
    /* a small sphere 3700 from the origin whose centre is not a float (two translations, composed
     * in double): the offset from the centre must be taken in double (in float it would be off
     * by up to ulp(3000) / 2 = 1.2e-4, 2.4e-4 of the radius) */
    const vec3 cn = v3(3000.1f, -2000.3f, 1000.7f);
    const float rn = 0.5f;
    check_scene("LookAt 3000.1 -2000.3 995  3000.1 -2000.3 1000.7  0 1 0 Camera \"perspective\" WorldBegin\n"
                "AttributeBegin Translate 3000 -2000 1000 Translate 0.1 -0.3 0.7 Shape \"sphere\" \"float radius\" [ 0.5 ] "
                "AttributeEnd\n",
                1, &cn, &rn, true, RAYS / 3);
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
