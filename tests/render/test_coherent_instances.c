/* Shadow rays through ObjectBegin prototypes must not reach Embree's coherent packet
 * traversal (docs/design.md 12.31). In the Embree 3.13.5 this project links (Debian's build,
 * GCC), the AVX-512 kernel of that traversal (BVHNIntersectorKHybrid::occludedCoherent, 16
 * rays) stores its 16-bit mask of live rays into a 64-bit stack slot and reads the whole
 * slot back: the upper 48 bits are whatever the stack held there before. When they are not
 * zero, the loop over the rays' octants never ends. An occlusion stream flagged coherent
 * reaches that kernel when its rays enter an instanced prototype (of triangles or of a
 * lone sphere: forced coherent, both hang here), so whether a frame hangs depends on what
 * earlier calls left on the stack (a sanitizer build, another code path before the call).
 *
 * This test fills the stack below it with nonzero bytes before each batch, so that, where
 * the kernel is reached, the slot holds garbage and the batch never returns (ctest's TIMEOUT
 * turns that into a failure). With the tracer's rule (Tracer.shadow_coherent_ok: a scene
 * with prototypes traces its shadow rays incoherent) every batch returns, and each answer is
 * the single ray's. The same batches over moving triangles (a moving shape's own instanced
 * layer, traced coherent) return too: those layers do not enter the kernel. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "render_test_util.h"
#include "core/rng.h"
#include "render/tracer.h"
#include "scene/scene_desc.h"

static const char *HEADER = "LookAt 0 0 -6  0 0 0  0 1 0\n"
                            "Camera \"perspective\" \"float fov\" [ 45 ]\n"
                            "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
                            "WorldBegin\n"
                            "Shape \"trianglemesh\" \"point3 P\" [ -4 -2 3  4 -2 3  4 2 3  -4 2 3 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n";

#define BOX                                                                                                            \
    " Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  0.6 0 0  0.6 0.6 0  0 0.6 0  0 0 0.6  0.6 0 0.6  0.6 0.6 0.6  0 0.6 0.6 ]\n" \
    "   \"integer indices\" [ 0 1 2 0 2 3  4 6 5 4 7 6  0 4 5 0 5 1  3 2 6 3 6 7  0 3 7 0 7 4  1 5 6 1 6 2 ]\n"

/* a box prototype instanced three times, still */
static const char *PROTOTYPES = "ObjectBegin \"box\"\n" BOX "ObjectEnd\n"
                                "AttributeBegin Translate -1.5 -0.3 0 ObjectInstance \"box\" AttributeEnd\n"
                                "AttributeBegin Translate -0.3 0.4 0.5 ObjectInstance \"box\" AttributeEnd\n"
                                "AttributeBegin Translate 0.9 -0.6 0.2 Rotate 30 0 1 0 ObjectInstance \"box\" AttributeEnd\n";

/* a sphere prototype (user geometry) instanced three times */
static const char *BALLS = "ObjectBegin \"ball\" Shape \"sphere\" \"float radius\" [ 0.4 ] ObjectEnd\n"
                           "AttributeBegin Translate -1.5 -0.3 0 ObjectInstance \"ball\" AttributeEnd\n"
                           "AttributeBegin Translate -0.3 0.4 0.5 ObjectInstance \"ball\" AttributeEnd\n"
                           "AttributeBegin Translate 0.9 -0.6 0.2 ObjectInstance \"ball\" AttributeEnd\n";

/* two moving boxes (each its own instanced layer) */
static const char *MOVING = "AttributeBegin Translate -1.2 -0.3 0\n ActiveTransform EndTime\n Translate 0.3 0 0\n"
                            " ActiveTransform All\n" BOX "AttributeEnd\n"
                            "AttributeBegin Translate 0.6 0.2 0.4\n ActiveTransform EndTime\n Translate 0 0.3 0\n"
                            " ActiveTransform All\n" BOX "AttributeEnd\n";

enum { RAYS = 150 };

/* Rays from around the camera towards the boxes and the back wall, some shorter than the
 * wall's distance; directions' x and y signs vary, so chunks mix octants. */
static void make_rays(TracerRay *rays, int n)
{
    Pcg32 rng;
    pcg32_seed(&rng, 11, 5);
    for (int i = 0; i < n; ++i) {
        vec3 o = v3(0.4f * (pcg32_float(&rng) - 0.5f), 0.4f * (pcg32_float(&rng) - 0.5f), -6.0f);
        vec3 target = v3(3.0f * (pcg32_float(&rng) - 0.5f), 2.0f * (pcg32_float(&rng) - 0.5f), 0.3f);
        vec3 d = v3_normalize(v3_sub(target, o));
        float tmax = i % 3 == 0 ? 5.0f + 3.0f * pcg32_float(&rng) : INFINITY;
        rays[i] = (TracerRay){o, d, tmax, pcg32_float(&rng), 0u};
    }
}

/* Writes `byte` over the stack the calls after it will use (this frame is gone when it
 * returns; the bytes stay). */
static __attribute__((noinline)) void poison_stack(unsigned char byte)
{
    volatile unsigned char junk[192 * 1024];
    for (size_t i = 0; i < sizeof junk; ++i) junk[i] = byte;
}

/* The scene's shadow rays as a coherent batch and as active lanes, after the stack is
 * filled with `byte`: each answer must be the single ray's. Returns whether the tracer
 * traces the scene's shadow rays coherent. */
static int check_scene(const char *what, const char *world)
{
    char text[8192];
    snprintf(text, sizeof text, "%s%s", HEADER, world);
    SceneDesc scene;
    Tracer tr;
    if (!test_build_tracer(text, &scene, &tr)) {
        CHECK(false);
        return -1;
    }
    TracerRay rays[RAYS];
    make_rays(rays, RAYS);
    bool ref[RAYS];
    int occluded = 0;
    for (int i = 0; i < RAYS; ++i) occluded += ref[i] = tracer_occluded(&tr, rays[i].o, rays[i].d, rays[i].tmax, rays[i].time01);
    CHECK(occluded > 10 && occluded < RAYS - 10);
    static const unsigned char bytes[] = {0x00, 0x41, 0xff};
    for (int b = 0; b < (int)sizeof bytes; ++b) {
        bool occ[RAYS];
        poison_stack(bytes[b]);
        tracer_occluded_batch(&tr, rays, RAYS, true, occ);
        int bad = 0;
        for (int i = 0; i < RAYS; ++i) bad += occ[i] != ref[i];
        /* the same rays as lanes, all active (the wave's dense path) */
        float o[3][RAYS], d[3][RAYS], tmax[RAYS], time01[RAYS];
        int active[RAYS];
        for (int i = 0; i < RAYS; ++i) {
            o[0][i] = rays[i].o.x, o[1][i] = rays[i].o.y, o[2][i] = rays[i].o.z;
            d[0][i] = rays[i].d.x, d[1][i] = rays[i].d.y, d[2][i] = rays[i].d.z;
            tmax[i] = rays[i].tmax, time01[i] = rays[i].time01, active[i] = 1;
        }
        TracerRayArrays a = {{o[0], o[1], o[2]}, {d[0], d[1], d[2]}, tmax, time01, active, 0u};
        bool lanes[RAYS];
        poison_stack(bytes[b]);
        tracer_occluded_arrays(&tr, &a, RAYS, true, lanes);
        for (int i = 0; i < RAYS; ++i) bad += lanes[i] != ref[i];
        /* closest hits, coherent (camera and bounce rays, always traced so): the same
         * surfaces as single rays, hit or miss */
        SurfaceHit hits[RAYS], hit_ref;
        bool found[RAYS];
        poison_stack(bytes[b]);
        tracer_intersect_batch(&tr, rays, RAYS, false, true, hits, found);
        int bad_hits = 0;
        for (int i = 0; i < RAYS; ++i) {
            bool f = tracer_intersect_ex(&tr, rays[i].o, rays[i].d, rays[i].tmax, rays[i].time01, false, &hit_ref);
            bad_hits += f != found[i] || (f && fabsf(hits[i].t - hit_ref.t) > 1e-4f * hit_ref.t);
        }
        poison_stack(bytes[b]);
        tracer_intersect_arrays(&tr, &a, RAYS, false, true, hits, found);
        for (int i = 0; i < RAYS; ++i) {
            bool f = tracer_intersect_ex(&tr, rays[i].o, rays[i].d, rays[i].tmax, rays[i].time01, false, &hit_ref);
            bad_hits += f != found[i] || (f && fabsf(hits[i].t - hit_ref.t) > 1e-4f * hit_ref.t);
        }
        fprintf(stderr, "%s, stack bytes 0x%02x: %d of %d shadow rays occluded, %d answers differ, %d hits differ\n",
                what, bytes[b], occluded, RAYS, bad, bad_hits);
        CHECK(bad_hits == 0);
        CHECK(bad == 0);
    }
    int coherent = tr.shadow_coherent_ok;
    tracer_free(&tr);
    scene_desc_free(&scene);
    return coherent;
}

int main(void)
{
    CHECK(check_scene("triangle prototype", PROTOTYPES) == 0);
    CHECK(check_scene("sphere prototype", BALLS) == 0);
    CHECK(check_scene("moving triangles", MOVING) == 1);
    return check_failures ? 1 : 0;
}
