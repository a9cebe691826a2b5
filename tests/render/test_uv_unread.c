/* Hits whose uv nothing reads (Geom.uv_unread, issue 22): spheres and disks then skip their
 * uv (an atan2 and an acos per hit) and must give every other field of the hit exactly as
 * before. Checked here:
 *  - material_reads_uv: false for constant diffuse and untextured glossy materials, true
 *    for a textured diffuse or glossy material and for a mix;
 *  - the renderer marks exactly the shapes whose material reads no uv;
 *  - tracer_intersect on a whole sphere, a partial sphere and a partial disk, over random
 *    rays, with uv_unread off and on: the same hit or miss, t, p, normals, offset and
 *    light bit for bit, and uv 0 when unread. */
#include <stdint.h>

#include "check.h"
#include "core/rng.h"
#include "render/material.h"
#include "render/renderer.h"
#include "render/tracer.h"
#include "render/warp.h"
#include "render_test_util.h"

static const char *SCENE_TEXT =
    "LookAt 0 0 -6  0 0 0  0 1 0 Camera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 4 ]\n"
    "WorldBegin\n"
    "LightSource \"point\" \"rgb I\" [ 5 5 5 ] \"point3 from\" [ 0 3 -3 ]\n"
    "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 8 ] \"float vscale\" [ 8 ]\n"
    "  \"rgb tex1\" [ 0.8 0.8 0.8 ] \"rgb tex2\" [ 0.1 0.1 0.1 ]\n"
    /* material 0: constant diffuse, on a whole sphere */
    "AttributeBegin Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "  Translate -1.2 0.3 0.7 Shape \"sphere\" \"float radius\" [ 0.8 ] AttributeEnd\n"
    /* material 1: textured diffuse, on a partial sphere (rotated: the per-ray code) */
    "AttributeBegin Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
    "  Translate 1.2 0.2 0.5 Rotate 30 1 1 0 Shape \"sphere\" \"float radius\" [ 0.7 ] \"float zmin\" [ -0.5 ]\n"
    "  \"float zmax\" [ 0.6 ] \"float phimax\" [ 300 ] AttributeEnd\n"
    /* material 2: untextured conductor, on a partial disk */
    "AttributeBegin Material \"conductor\" \"float roughness\" [ 0.2 ]\n"
    "  Translate 0 -1 1 Rotate 80 1 0 0 Shape \"disk\" \"float radius\" [ 1.5 ] \"float innerradius\" [ 0.3 ]\n"
    "  \"float phimax\" [ 270 ] AttributeEnd\n"
    /* a mix of the first two, on a triangle */
    "AttributeBegin MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
    "  MakeNamedMaterial \"b\" \"string type\" \"diffuse\" \"texture reflectance\" \"checks\"\n"
    "  Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"float amount\" [ 0.5 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -3 -2 3  3 -2 3  0 2 3 ] \"integer indices\" [ 0 1 2 ] AttributeEnd\n";

/* Which kind of geometry carries which material in SCENE_TEXT: the renderer's marks. */
static void check_marks(void)
{
    TestRender t;
    memset(&t, 0, sizeof t);
    Diag err = {0};
    bool parsed = scene_parse_string(SCENE_TEXT, strlen(SCENE_TEXT), "<test>", NULL, &t.scene, &err);
    CHECK(parsed);
    if (!parsed) return;
    RenderOptions o = {0};
    o.threads = 1;
    bool created = renderer_create(&t.scene, &o, &t.r, &err);
    CHECK(created);
    if (!created) {
        scene_desc_free(&t.scene);
        return;
    }
    const IntegratorScene *isc = renderer_integrator_scene(t.r);
    const MaterialTable *mt = isc->materials;
    const Layer *l = &isc->tracer->layers[0];
    int spheres = 0, disks = 0, meshes = 0;
    for (int i = 0; i < l->geom_count; ++i) {
        const Geom *g = &l->geoms[i];
        bool reads = material_reads_uv(mt, g->material);
        CHECK(g->uv_unread == !reads);
        if (g->kind == GEOM_SPHERE) {
            ++spheres;
            /* the whole sphere is constant diffuse, the partial one textured */
            CHECK(reads == (g->zmin > -g->radius));
        } else if (g->kind == GEOM_DISK) {
            ++disks;
            CHECK(!reads); /* an untextured conductor */
            CHECK(material_get(mt, g->material)->kind == MATERIAL_GLOSSY);
        } else if (g->kind == GEOM_TRIANGLES) {
            ++meshes;
            CHECK(reads); /* a mix */
            CHECK(material_get(mt, g->material)->kind == MATERIAL_MIX);
        }
    }
    CHECK(spheres == 2 && disks == 1 && meshes == 1);
    test_render_free(&t);
}

/* Every field of two hits equal bit for bit, uv aside. */
static bool same_but_uv(const SurfaceHit *a, const SurfaceHit *b)
{
    return memcmp(&a->t, &b->t, sizeof a->t) == 0 && memcmp(&a->p, &b->p, sizeof a->p) == 0 &&
           memcmp(&a->ng, &b->ng, sizeof a->ng) == 0 && memcmp(&a->ns, &b->ns, sizeof a->ns) == 0 &&
           memcmp(&a->err, &b->err, sizeof a->err) == 0 && a->geom == b->geom && a->prim == b->prim &&
           a->instance == b->instance && a->object_id == b->object_id && a->light == b->light;
}

static void check_hits(void)
{
    SceneDesc scene;
    Tracer tr;
    bool built = test_build_tracer(SCENE_TEXT, &scene, &tr);
    CHECK(built);
    if (!built) return;
    Pcg32 rng;
    pcg32_seed(&rng, 23, 4);
    long quadric_hits = 0, differ = 0, uv_nonzero = 0;
    for (int i = 0; i < 20000; ++i) {
        vec3 o = v3_scale(warp_uniform_sphere(v2(pcg32_float(&rng), pcg32_float(&rng))), 5.0f);
        vec3 target = v3(3.0f * pcg32_float(&rng) - 1.5f, 3.0f * pcg32_float(&rng) - 1.5f, 3.0f * pcg32_float(&rng) - 1.0f);
        vec3 d = v3_normalize(v3_sub(target, o));
        Layer *l = &tr.layers[0];
        for (int g = 0; g < l->geom_count; ++g) l->geoms[g].uv_unread = false;
        SurfaceHit with, without;
        bool found_with = tracer_intersect(&tr, o, d, INFINITY, 0.0f, &with);
        for (int g = 0; g < l->geom_count; ++g) l->geoms[g].uv_unread = l->geoms[g].kind != GEOM_TRIANGLES;
        bool found_without = tracer_intersect(&tr, o, d, INFINITY, 0.0f, &without);
        if (found_with != found_without) {
            ++differ;
            continue;
        }
        if (!found_with || with.geom->kind == GEOM_TRIANGLES) continue;
        ++quadric_hits;
        differ += !same_but_uv(&with, &without) || without.uv.x != 0.0f || without.uv.y != 0.0f;
        uv_nonzero += with.uv.x != 0.0f || with.uv.y != 0.0f;
    }
    printf("%ld sphere and disk hits, %ld differ, %ld with uv computed nonzero\n", quadric_hits, differ, uv_nonzero);
    CHECK(differ == 0);
    CHECK(quadric_hits > 2000);
    CHECK(uv_nonzero > quadric_hits * 9 / 10); /* the uv it skipped was real work */
    tracer_free(&tr);
    scene_desc_free(&scene);
}

int main(void)
{
    check_marks();
    check_hits();
    CHECK_DONE();
}
