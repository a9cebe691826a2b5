/* MAAF's light table (maaf_lights.h) when memory runs out. Every allocation the table makes is
 * failed in turn (the test is linked with malloc and calloc wrapped, tests/CMakeLists.txt): the
 * table must then either report the failure (false, every entry zero) or be the same bit for bit
 * as the table built with all the memory it asked for. A table that silently differs, such as a
 * moving light designed as if it stood still or a mesh triangle boxed without its shape's
 * vertices, filters with a narrower light than the scene's. The scene has a moving quad light
 * (its own poses), a moving mesh light (the shape's sweep), a curved mesh light of more vertices
 * than the plain extent loop takes (the vertex tree, whose loss only costs time) and a sphere. */
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/aaf/aaf_stats.h"
#include "recon/maaf/maaf_lights.h"
#include "recon_test_util.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t size);

/* armed: the allocation numbered fail_at (from 0) returns NULL; allocations counts them */
static long fail_at = -1, allocations = 0;

static bool fail_now(void) { return fail_at >= 0 && allocations++ == fail_at; }
void *__wrap_malloc(size_t n) { return fail_now() ? NULL : __real_malloc(n); }
void *__wrap_calloc(size_t n, size_t size) { return fail_now() ? NULL : __real_calloc(n, size); }

/* An n x n grid of quads on a half cylinder as one emitter, optionally moving. */
static size_t append_mesh_light(char *s, size_t cap, size_t at, int n, bool curved, bool moving)
{
    at += (size_t)snprintf(s + at, cap - at, "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n%s"
                           "  Shape \"trianglemesh\" \"point3 P\" [",
                           moving ? "  ActiveTransform EndTime\n  Translate 0.4 0 0.1\n  ActiveTransform All\n" : "");
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            float a = 3.14159265f * (float)i / (float)n, z = (float)j / (float)n - 0.5f;
            float x = curved ? 0.5f * cosf(a) : (float)i / (float)n - 0.5f, y = curved ? 2.5f + 0.5f * sinf(a) : 2.5f;
            at += (size_t)snprintf(s + at, cap - at, " %g %g %g", (double)x, (double)y, (double)(z + (moving ? 1.0f : -1.0f)));
        }
    at += (size_t)snprintf(s + at, cap - at, " ] \"integer indices\" [");
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            at += (size_t)snprintf(s + at, cap - at, " %d %d %d %d %d %d", a, c, b, b, c, d);
        }
    return at + (size_t)snprintf(s + at, cap - at, " ]\nAttributeEnd\n");
}

int main(void)
{
    enum { CAP = 1 << 18 };
    char *s = malloc(CAP);
    size_t at = (size_t)snprintf(
        s, CAP,
        "LookAt 0 2 -5  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
        "Sampler \"stratified\" \"integer pixelsamples\" [ 1 ]\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
        "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
        "  ActiveTransform EndTime\n  Translate 0.5 0 0\n  ActiveTransform All\n"
        "  Shape \"bilinearmesh\" \"point3 P\" [ 1.5 2 -0.5  2.5 2 -0.5  1.5 2 0.5  2.5 2 0.5 ]\n"
        "AttributeEnd\n"
        "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n  Translate -2 1.5 0\n  Shape \"sphere\" \"float radius\" [ 0.2 ]\nAttributeEnd\n");
    at = append_mesh_light(s, CAP, at, 4, false, true);
    append_mesh_light(s, CAP, at, 12, true, false); /* 169 vertices: the tree's path */
    SceneDesc scene;
    Renderer *r = NULL;
    bool made = recon_test_renderer(s, 1, 1, false, &scene, &r);
    CHECK(made);
    if (!made) {
        free(s);
        return 1;
    }
    int count = r ? renderer_light_count(r) : 0;
    AafLightGeom *geoms = calloc((size_t)count + 1, sizeof *geoms);
    MaafLight *whole = calloc((size_t)count + 1, sizeof *whole), *table = calloc((size_t)count + 1, sizeof *table);
    aaf_lights_from_renderer(r, geoms, count);
    const int pairs = 3;
    const float kappa = 4.0f;
    CHECK(maaf_lights_from_renderer(r, geoms, count, pairs, kappa, whole));
    int moving = 0, moving_area = 0;
    for (int l = 0; l < count; ++l) {
        RenderLightInfo b;
        moving += whole[l].sweep_nodes > 0;
        moving_area += renderer_light_info(r, l, &b) && b.kind == RENDER_LIGHT_AREA && b.moving;
    }
    CHECK(moving_area > 0 && moving == moving_area); /* every moving light swept when memory suffices */
    int refused = 0, same = 0, differ = 0, dirty = 0;
    long total = 0;
    for (long k = 0;; ++k) {
        memset(table, 0xab, (size_t)count * sizeof *table);
        fail_at = k, allocations = 0;
        bool ok = maaf_lights_from_renderer(r, geoms, count, pairs, kappa, table);
        long made = allocations;
        fail_at = -1;
        if (made <= k) { /* no allocation failed: the sweep is done */
            total = made;
            CHECK(ok && memcmp(table, whole, (size_t)count * sizeof *table) == 0);
            break;
        }
        if (!ok) {
            ++refused;
            for (size_t b = 0; b < (size_t)count * sizeof *table; ++b) dirty += ((unsigned char *)table)[b] != 0;
        } else if (memcmp(table, whole, (size_t)count * sizeof *table) == 0) {
            ++same;
        } else {
            ++differ;
            fprintf(stderr, "allocation %ld failed: the table differs and was not refused\n", k);
        }
    }
    printf("%d lights (%d moving), %ld allocations: %d failures refused, %d degraded to the same table, %d differ\n",
           count, moving, total, refused, same, differ);
    CHECK(differ == 0);
    CHECK(dirty == 0); /* a refused table is all zero, no light half designed */
    CHECK(refused >= 3); /* the light list, the shapes' vertices, a moving light's poses at least */
    CHECK(same >= 1);    /* the design index and the vertex tree: only time is lost */
    free(geoms), free(whole), free(table);
    if (r) renderer_destroy(r);
    scene_desc_free(&scene);
    free(s);
    return check_failures ? 1 : 0;
}
