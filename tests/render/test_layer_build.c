/* Embree's two-level build of a layer (layer_build_two_level, WEDGE_EMBREE_TWO_LEVEL; design.md
 * 12.27).
 *
 * The rule: on hand-made layers, a floor with two walls beside it is built two-level, a floor
 * with nine small bars above it (thin_occluders' layout) and a lone mesh are not, spheres do
 * not count, and the share is compared with LAYER_TWO_LEVEL_SHARE on both sides of it.
 *
 * The hits: a room (floor, two walls, a box, a sphere) built both ways answers 4000 random
 * rays (random origins in and around it, random directions: none aimed at an edge) with the
 * same SurfaceHit, field for field and bit for bit, and the same occlusion answers, through
 * the batches the integrator uses (streams, coherent and not). The two-level tree holds the
 * same triangles tested the same way; only the order in which a ray meets hits at one
 * distance differs, and random rays meet none such. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/layer_build.h"
#include "render_test_util.h"

/* ---- the rule ---- */

/* A box mesh lo .. hi as a triangle Geom (only the fields the rule reads); its 8 corners go
 * to p (24 floats). */
static Geom box_geom(float *p, const float lo[3], const float hi[3])
{
    for (int c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a) p[3 * c + a] = (c >> a) & 1 ? hi[a] : lo[a];
    Geom g;
    memset(&g, 0, sizeof g);
    g.kind = GEOM_TRIANGLES;
    g.vertex_count = 8;
    g.triangle_count = 12;
    g.p = p;
    return g;
}

static void test_rule(void)
{
    float p[16][24];
    Geom g[16];
    /* floor 10 x 10 at y = 0, two walls 10 wide, 4 high: the walls' boxes (80 each) against the
     * room's (2 (100 + 40 + 40) = 360): 160 / 360 = 0.44 >= 0.2 */
    g[0] = box_geom(p[0], (float[3]){-5, 0, -5}, (float[3]){5, 0, 5});
    g[1] = box_geom(p[1], (float[3]){-5, 0, 5}, (float[3]){5, 4, 5});
    g[2] = box_geom(p[2], (float[3]){-5, 0, -5}, (float[3]){-5, 4, 5});
    CHECK(layer_build_two_level(g, 3));
    CHECK(!layer_build_two_level(g, 1)); /* a lone mesh */
    /* the floor and nine bars 2.4 x 0.1 x 0.1 at heights 0.5 to 2: their boxes sum to 9 x 1.0
     * against the floor's box grown to 2 high, 2 (100 + 20 + 20) = 280: 0.03 */
    for (int i = 0; i < 9; ++i) {
        float y = 0.5f + 0.15f * (float)i, z = -2.0f + 0.5f * (float)i;
        g[1 + i] = box_geom(p[1 + i], (float[3]){-1.2f, y - 0.05f, z - 0.05f}, (float[3]){1.2f, y + 0.05f, z + 0.05f});
    }
    CHECK(!layer_build_two_level(g, 10));
    /* spheres are not meshes: a floor and spheres is a lone mesh */
    Geom s[3];
    memset(s, 0, sizeof s);
    s[0] = g[0];
    s[1].kind = s[2].kind = GEOM_SPHERE;
    CHECK(!layer_build_two_level(s, 3));
    /* the share on both sides of LAYER_TWO_LEVEL_SHARE: a unit cube and a flat plate w x 1 at
     * its side, which spans the union's x: union area 2 (w + w + 1); the plate's box area 2 w,
     * the cube's 6, so the share left without the largest is 6 / (4 w + 2) for w > 3 */
    for (int side = 0; side < 2; ++side) {
        double share = LAYER_TWO_LEVEL_SHARE * (side ? 0.99 : 1.01); /* just above, just below */
        float w = (float)((6.0 / share - 2.0) / 4.0);
        Geom t[2];
        float q[2][24];
        t[0] = box_geom(q[0], (float[3]){0, 0, 0}, (float[3]){1, 1, 1});
        t[1] = box_geom(q[1], (float[3]){0, 0, 1}, (float[3]){w, 1, 1});
        CHECK(w > 3.0f);
        CHECK(layer_build_two_level(t, 2) == (side == 0));
    }
}

/* ---- the hits ---- */

static const char *ROOM = "LookAt 0 1 -4  0 1 0  0 1 0\n"
                          "Camera \"perspective\" \"float fov\" [ 45 ]\n"
                          "WorldBegin\n"
                          "LightSource \"point\" \"point3 from\" [ 0 3 0 ] \"rgb I\" [ 1 1 1 ]\n"
                          "Material \"diffuse\"\n"
                          "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ]\n"
                          "  \"integer indices\" [ 0 2 1  0 3 2 ]\n"
                          "Shape \"trianglemesh\" \"point3 P\" [ -4 0 4  4 0 4  4 3 4  -4 3 4 ]\n"
                          "  \"integer indices\" [ 0 1 2  0 2 3 ]\n"
                          "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  -4 3 -4  -4 3 4  -4 0 4 ]\n"
                          "  \"integer indices\" [ 0 1 2  0 2 3 ]\n"
                          "AttributeBegin\n"
                          "  Translate 1 0.5 1  Rotate 30 0 1 0  Scale 0.5 0.5 0.5\n"
                          "  Shape \"trianglemesh\" \"point3 P\" [ -1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1 ]\n"
                          "    \"integer indices\" [ 0 2 1  0 3 2  4 5 6  4 6 7  0 1 5  0 5 4  3 7 6  3 6 2  0 4 7  0 7 3  1 2 6  1 6 5 ]\n"
                          "AttributeEnd\n"
                          "AttributeBegin\n"
                          "  Translate -1.5 0.6 0.5\n"
                          "  Shape \"sphere\" \"float radius\" [ 0.6 ]\n"
                          "AttributeEnd\n";

enum { RAYS = 4000 };

static bool build_room(const char *two_level, SceneDesc *scene, Tracer *tr)
{
    setenv("WEDGE_EMBREE_TWO_LEVEL", two_level, 1);
    bool ok = test_build_tracer(ROOM, scene, tr);
    unsetenv("WEDGE_EMBREE_TWO_LEVEL");
    return ok;
}

static bool same_hit(const SurfaceHit *a, const SurfaceHit *b)
{
    return memcmp(&a->t, &b->t, sizeof a->t) == 0 && memcmp(&a->p, &b->p, sizeof a->p) == 0 &&
           memcmp(&a->ng, &b->ng, sizeof a->ng) == 0 && memcmp(&a->ns, &b->ns, sizeof a->ns) == 0 &&
           memcmp(&a->uv, &b->uv, sizeof a->uv) == 0 && memcmp(&a->err, &b->err, sizeof a->err) == 0 &&
           a->prim == b->prim && a->instance == b->instance && a->object_id == b->object_id && a->light == b->light;
}

static void test_same_hits(void)
{
    SceneDesc scene[2];
    Tracer tr[2];
    CHECK(build_room("0", &scene[0], &tr[0]));
    if (check_failures) return;
    CHECK(build_room("1", &scene[1], &tr[1]));
    if (check_failures) return;
    /* the rule itself would build this room two-level */
    CHECK(layer_build_two_level(tr[0].layers[0].geoms, tr[0].layers[0].geom_count));
    TracerRay *rays = malloc(sizeof *rays * RAYS);
    SurfaceHit *hits[2] = {calloc(RAYS, sizeof(SurfaceHit)), calloc(RAYS, sizeof(SurfaceHit))};
    bool *found[2] = {calloc(RAYS, 1), calloc(RAYS, 1)}, *occ[2] = {calloc(RAYS, 1), calloc(RAYS, 1)};
    Pcg32 rng;
    pcg32_seed(&rng, 34, 1);
    for (int i = 0; i < RAYS; ++i) {
        vec3 o = v3(10.0f * pcg32_float(&rng) - 5.0f, 4.0f * pcg32_float(&rng) - 0.5f, 10.0f * pcg32_float(&rng) - 5.0f);
        vec3 d;
        do d = v3(2.0f * pcg32_float(&rng) - 1.0f, 2.0f * pcg32_float(&rng) - 1.0f, 2.0f * pcg32_float(&rng) - 1.0f);
        while (v3_length2(d) > 1.0f || v3_length2(d) < 1e-4f);
        rays[i] = (TracerRay){o, v3_normalize(d), i % 3 ? INFINITY : 2.0f + 6.0f * pcg32_float(&rng), 0.0f, 0u};
    }
    int hit_count = 0, occ_count = 0, bad_hit = 0, bad_occ = 0;
    for (int coherent = 0; coherent < 2; ++coherent) {
        for (int k = 0; k < 2; ++k) {
            tracer_intersect_batch(&tr[k], rays, RAYS, true, coherent, hits[k], found[k]);
            tracer_occluded_batch(&tr[k], rays, RAYS, coherent, occ[k]);
        }
        for (int i = 0; i < RAYS; ++i) {
            bad_hit += found[0][i] != found[1][i] || (found[0][i] && !same_hit(&hits[0][i], &hits[1][i]));
            bad_occ += occ[0][i] != occ[1][i];
            hit_count += found[0][i];
            occ_count += occ[0][i];
        }
    }
    printf("two-level against one tree: %d of %d hits and %d of %d occlusions differ (%d hits, %d occluded)\n",
           bad_hit, 2 * RAYS, bad_occ, 2 * RAYS, hit_count, occ_count);
    CHECK(bad_hit == 0 && bad_occ == 0);
    CHECK(hit_count > RAYS / 2 && hit_count < 2 * RAYS && occ_count > RAYS / 2); /* the rays meet the room */
    for (int k = 0; k < 2; ++k) {
        free(hits[k]), free(found[k]), free(occ[k]);
        tracer_free(&tr[k]);
        scene_desc_free(&scene[k]);
    }
    free(rays);
}

int main(void)
{
    test_rule();
    test_same_hits();
    CHECK_DONE();
}
