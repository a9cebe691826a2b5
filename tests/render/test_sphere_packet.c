/* sphere_packet_hits (src/render/sphere_packet.c) against tracer_quadric_hit, lane by lane,
 * bit for bit: packets of 1, 4, 8 and 16 rays (the copy of the vectorised loop this CPU
 * runs) with random valid masks, against translated whole spheres at ordinary scale and far
 * from the origin (where the scene is scaled for Embree, so geom_from_tracer is not 1).
 * The rays: random ones around the sphere, rays aimed at its rim (tangent: the
 * discriminant's sign decides), from inside, and with tnear / tfar cutting either root. */
#include <stdint.h>

#include "check.h"
#include "core/rng.h"
#include "render/sphere_packet.h"
#include "render/tracer.h"
#include "render/warp.h"
#include "render_test_util.h"

enum { RAYN_ORG_X, RAYN_ORG_Y, RAYN_ORG_Z, RAYN_TNEAR, RAYN_DIR_X, RAYN_DIR_Y, RAYN_DIR_Z, RAYN_TIME, RAYN_TFAR };
enum { LANES = 16, PACKETS = 4000 };

/* Fills lane i of an n-lane packet (tracer units): a ray near the sphere of centre c and
 * radius r (world units), scaled by k = tracer_from_world. */
static void make_lane(float *rays, unsigned n, unsigned i, Pcg32 *rng, vec3 c, float r, float k)
{
    float kind = pcg32_float(rng);
    vec3 o = v3_add(c, v3_scale(warp_uniform_sphere(v2(pcg32_float(rng), pcg32_float(rng))), r * (1.0f + 3.0f * pcg32_float(rng))));
    if (kind < 0.1f) o = v3_add(c, v3_scale(warp_uniform_sphere(v2(pcg32_float(rng), pcg32_float(rng))), 0.5f * r)); /* inside */
    vec3 target = v3_add(c, v3_scale(warp_uniform_sphere(v2(pcg32_float(rng), pcg32_float(rng))), r * pcg32_float(rng)));
    if (kind > 0.6f) {
        /* at the rim as seen from o: a point on the sphere whose radius is perpendicular to
         * the ray, give or take a little */
        vec3 to_c = v3_normalize(v3_sub(c, o));
        vec3 side = v3_normalize(v3_cross(to_c, warp_uniform_sphere(v2(pcg32_float(rng), pcg32_float(rng)))));
        target = v3_add(c, v3_scale(side, r * (1.0f + 1e-6f * (pcg32_float(rng) - 0.5f))));
    }
    vec3 d = v3_normalize(v3_sub(target, o));
    float tfar = pcg32_float(rng) < 0.3f ? r * 3.0f * pcg32_float(rng) : INFINITY;
    float tnear = pcg32_float(rng) < 0.2f ? r * pcg32_float(rng) : 0.0f;
    rays[RAYN_ORG_X * n + i] = k * o.x, rays[RAYN_ORG_Y * n + i] = k * o.y, rays[RAYN_ORG_Z * n + i] = k * o.z;
    rays[RAYN_DIR_X * n + i] = d.x, rays[RAYN_DIR_Y * n + i] = d.y, rays[RAYN_DIR_Z * n + i] = d.z;
    rays[RAYN_TNEAR * n + i] = k * tnear, rays[RAYN_TFAR * n + i] = k * tfar;
    rays[RAYN_TIME * n + i] = 0.0f;
}

static void check_scene(const char *text, vec3 c, float r)
{
    SceneDesc scene;
    Tracer tr;
    bool built = test_build_tracer(text, &scene, &tr);
    CHECK(built);
    if (!built) return;
    const Geom *g = NULL;
    for (int i = 0; i < tr.layers[0].geom_count; ++i)
        if (tr.layers[0].geoms[i].kind == GEOM_SPHERE) g = &tr.layers[0].geoms[i];
    CHECK(g && g->object_translation_only);
    if (!g) return;
    const double translation[3] = {g->object_from_geom.m[0][3], g->object_from_geom.m[1][3], g->object_from_geom.m[2][3]};
    double w = g->geom_from_tracer;
    float k = (float)(1.0 / w);
    Pcg32 rng;
    pcg32_seed(&rng, 17, 9);
    static const unsigned sizes[4] = {1, 4, 8, 16};
    long lanes = 0, hits = 0, differ = 0;
    float rays[12 * LANES + 8 * LANES];
    for (int p = 0; p < PACKETS; ++p) {
        unsigned n = sizes[p % 4];
        int valid[LANES], hit[LANES];
        double t[LANES];
        for (unsigned i = 0; i < n; ++i) {
            make_lane(rays, n, i, &rng, c, r, k);
            valid[i] = pcg32_float(&rng) < 0.85f ? -1 : 0;
        }
        sphere_packet_hits(rays, valid, n, w, translation, g->radius, hit, t);
        for (unsigned i = 0; i < n; ++i) {
            if (valid[i] != -1) {
                differ += hit[i] != 0;
                continue;
            }
            /* quadric_hit_rayn's conversion of lane i to geometry space */
            double o[3] = {w * rays[RAYN_ORG_X * n + i], w * rays[RAYN_ORG_Y * n + i], w * rays[RAYN_ORG_Z * n + i]};
            double d[3] = {w * rays[RAYN_DIR_X * n + i], w * rays[RAYN_DIR_Y * n + i], w * rays[RAYN_DIR_Z * n + i]};
            double t_ref = 0.0;
            bool ref = tracer_quadric_hit(g, o, d, rays[RAYN_TNEAR * n + i], rays[RAYN_TFAR * n + i], &t_ref);
            ++lanes;
            hits += ref;
            differ += (hit[i] != 0) != ref || (ref && memcmp(&t[i], &t_ref, sizeof t_ref) != 0);
        }
    }
    printf("%ld live lanes, %ld hits, %ld differ (scale %g)\n", lanes, hits, differ, (double)k);
    CHECK(differ == 0);
    CHECK(hits > lanes / 5 && hits < lanes * 9 / 10);
    tracer_free(&tr);
    scene_desc_free(&scene);
}

int main(void)
{
    check_scene("LookAt 0 0 -6  0 0 0  0 1 0 Camera \"perspective\" WorldBegin\n"
                "AttributeBegin Translate -1.2 0.3 0.7 Shape \"sphere\" \"float radius\" [ 0.8 ] AttributeEnd\n",
                v3(-1.2f, 0.3f, 0.7f), 0.8f);
    check_scene("LookAt 0 0 -6e6  0 0 0  0 1 0 Camera \"perspective\" WorldBegin\n"
                "AttributeBegin Translate 3e6 -1e6 2e6 Shape \"sphere\" \"float radius\" [ 2e6 ] AttributeEnd\n",
                v3(3e6f, -1e6f, 2e6f), 2e6f);
    CHECK_DONE();
}
