/* SampleRecord.motion_px (filled by the integrator for LR): a sphere translating at a known
 * speed across a camera looking down +z must report, for every sample that hits it, the
 * pinhole projection's velocity 16 px * dX / z (32-px film, 90-degree field of view: screen
 * half-width 1 = 16 px, a point at depth z moving dX in x moves dX / z on the screen), and 0
 * in y; a static floor reports 0; a moving camera adds minus its own motion. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

/* Per-pixel tallies: a pass never runs two calls for one pixel at once (SampleSink). */
static int *g_sphere, *g_floor, *g_bad;
static int g_w;
static double g_dx, g_camera_dx; /* world translation over the shutter: sphere minus camera, camera */

static void sink_add(void *ctx, int px, int py, const SampleRecord *r)
{
    (void)ctx;
    int i = py * g_w + px;
    if (!r->hit) return;
    if (r->object_id < 0) return;
    /* the floor is at y = -3 below a sphere of radius 2 at y = 0: tell them by height */
    if (r->p_world.y < -2.99f) {
        /* static floor: motion only from the camera (same tolerance as below) */
        double want = -16.0 * g_camera_dx / r->depth_cam;
        if (fabs(r->motion_px[0] - want) <= 1e-3 * (1 + fabs(want)) && fabsf(r->motion_px[1]) <= 1e-3f) ++g_floor[i];
        else ++g_bad[i];
    } else {
        double want = 16.0 * g_dx / r->depth_cam;
        /* float projection: the difference of two raster positions of up to 32 px, each
         * good to a few ulp (2e-6 px), and the hit point's float position (relative 1e-6):
         * 1e-3 px leaves two orders of margin */
        if (fabs(r->motion_px[0] - want) <= 1e-3 * (1 + fabs(want)) && fabsf(r->motion_px[1]) <= 1e-3f) ++g_sphere[i];
        else ++g_bad[i];
    }
}

static void run(const char *text, double dx_expected, double camera_dx)
{
    SceneDesc scene;
    Diag d = {0};
    CHECK(scene_parse_string(text, strlen(text), "<test>", NULL, &scene, &d));
    scene_analyze_effects(&scene);
    RenderOptions ro;
    memset(&ro, 0, sizeof ro);
    ro.seed = 3;
    ro.spp = 4;
    ro.threads = 2;
    ro.record_motion = true;
    Renderer *r = NULL;
    CHECK(renderer_create(&scene, &ro, &r, &d));
    if (!r) {
        fprintf(stderr, "%s\n", d.message);
        scene_desc_free(&scene);
        return;
    }
    int w = renderer_width(r), h = renderer_height(r);
    g_w = w;
    g_dx = dx_expected;
    g_camera_dx = camera_dx;
    g_sphere = calloc((size_t)w * h, sizeof(int));
    g_floor = calloc((size_t)w * h, sizeof(int));
    g_bad = calloc((size_t)w * h, sizeof(int));
    Frame f;
    frame_init(&f, w, h);
    SampleSink sink = {sink_add, NULL};
    CHECK(render_pass(r, 0, NULL, 4, &f, &sink));
    long sphere = 0, floor_n = 0, bad = 0;
    for (int i = 0; i < w * h; ++i) sphere += g_sphere[i], floor_n += g_floor[i], bad += g_bad[i];
    /* the sphere covers a good part of the 32x32 image and the floor the bottom */
    CHECK(sphere > 400 && floor_n > 200 && bad == 0);
    if (bad || sphere <= 400 || floor_n <= 200) fprintf(stderr, "motion vectors: %ld sphere, %ld floor, %ld wrong\n", sphere, floor_n, bad);
    frame_free(&f);
    free(g_sphere), free(g_floor), free(g_bad);
    renderer_destroy(r);
    scene_desc_free(&scene);
}

#define HEAD                                                                                   \
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ] \"string filename\" [ \"t.exr\" ]\n" \
    "Sampler \"stratified\" \"integer pixelsamples\" [ 4 ]\n"                                  \
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"

#define WORLD                                                                                  \
    "WorldBegin\n"                                                                             \
    "LightSource \"point\" \"rgb I\" [ 5 5 5 ] \"point3 from\" [ 0 3 0 ]\n"                  \
    "Shape \"trianglemesh\" \"point3 P\" [ -20 -3 0.5  20 -3 0.5  20 -3 40  -20 -3 40 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n" \
    "AttributeBegin\n"                                                                         \
    "  ActiveTransform StartTime\n"                                                            \
    "  Translate -0.5 0 5\n"                                                                   \
    "  ActiveTransform EndTime\n"                                                              \
    "  Translate 0.5 0 5\n"                                                                    \
    "  ActiveTransform All\n"                                                                  \
    "  Shape \"sphere\" \"float radius\" [ 2 ]\n"                                            \
    "AttributeEnd\n"

int main(void)
{
    /* the sphere moves 1 unit in +x over the shutter; the camera stands still */
    run("LookAt 0 0 0  0 0 1  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 90 ]\n" HEAD WORLD,
        1.0, 0.0);
    /* the camera moves 0.5 in +x as well: the sphere moves 0.5 relative to it, the floor -0.5 */
    run("ActiveTransform StartTime\n"
        "LookAt 0 0 0  0 0 1  0 1 0\n"
        "ActiveTransform EndTime\n"
        "LookAt 0.5 0 0  0.5 0 1  0 1 0\n"
        "ActiveTransform All\n"
        "Camera \"perspective\" \"float fov\" [ 90 ]\n" HEAD WORLD,
        0.5, 0.5);
    CHECK_DONE();
}
