/* fsf_light_from_renderer's choice of light: the emitter shape with the most power (luminance
 * times its triangles' total area), found with one sum a shape. Checked against a brute force
 * (for every triangle light, its shape's power summed over every light, the first of the
 * brightest kept) on scenes whose brightest shape is first, last, a mesh of many small
 * triangles, or tied with an earlier one (the earlier wins). A mesh whose first triangle is
 * degenerate (a latitude-longitude sphere's pole) gives the frame of the same mesh without it,
 * bit for bit: the degenerate triangle has no normal to set the axes by (it made fsf refuse the
 * light, "has no extent"). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/fsf/fsf_light.h"
#include "recon_test_util.h"
#include "scene/scene_desc.h"

/* the old rule, quadratic in the lights: the shape of the first light of the brightest shape */
static int brute_force_shape(const Renderer *r)
{
    int count = renderer_light_count(r), best = -1;
    float best_power = 0.0f;
    for (int l = 0; l < count; ++l) {
        RenderLightInfo a;
        if (!renderer_light_info(r, l, &a) || a.kind != RENDER_LIGHT_AREA || !a.is_triangle) continue;
        float power = 0.0f;
        for (int m = 0; m < count; ++m) {
            RenderLightInfo b;
            if (renderer_light_info(r, m, &b) && b.kind == RENDER_LIGHT_AREA && b.is_triangle && b.shape == a.shape)
                power += v3_luminance(b.radiance) * b.area_world;
        }
        if (power > best_power) best_power = power, best = a.shape;
    }
    return best;
}

/* a quad light of half side h at height y, centred at x, radiance L; or a grid of n x n quads */
static void add_quad(char *buf, size_t size, float x, float y, float h, float L, int n)
{
    size_t at = strlen(buf);
    at += (size_t)snprintf(buf + at, size - at, "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ %g %g %g ]\n",
                           L, L, L);
    at += (size_t)snprintf(buf + at, size - at, "  Shape \"trianglemesh\" \"point3 P\" [");
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            at += (size_t)snprintf(buf + at, size - at, " %g %g %g", x - h + 2 * h * i / n, y, -h + 2 * h * j / n);
    at += (size_t)snprintf(buf + at, size - at, " ] \"integer indices\" [");
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            at += (size_t)snprintf(buf + at, size - at, " %d %d %d %d %d %d", a, b, d, a, d, c);
        }
    snprintf(buf + at, size - at, " ]\nAttributeEnd\n");
}

static const char *const CAMERA_AND_FLOOR =
    "LookAt 0 4 -6   0 0 0   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"string filename\" [ \"t.exr\" ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -6 0 -6  6 0 -6  6 0 6  -6 0 6 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n";

static void check_scene(const char *lights, const char *what)
{
    static char text[1 << 20];
    snprintf(text, sizeof text, "%s%s", CAMERA_AND_FLOOR, lights);
    SceneDesc scene;
    Renderer *r;
    if (!recon_test_renderer(text, 1, 4, false, &scene, &r)) {
        CHECK(false);
        return;
    }
    FsfLight light;
    Diag d = {0};
    CHECK(fsf_light_from_renderer(r, &light, &d));
    int want = brute_force_shape(r);
    if (light.shape != want) fprintf(stderr, "%s: shape %d, the brute force %d\n", what, light.shape, want);
    CHECK(light.shape == want && want >= 0);
    renderer_destroy(r);
    scene_desc_free(&scene);
}

/* the frame fsf_light_from_renderer gives the scene with these lights (false: refused) */
static bool frame_of(const char *lights, FsfLight *light)
{
    static char text[1 << 16];
    snprintf(text, sizeof text, "%s%s", CAMERA_AND_FLOOR, lights);
    SceneDesc scene;
    Renderer *r;
    if (!recon_test_renderer(text, 1, 4, false, &scene, &r)) return false;
    Diag d = {0};
    memset(light, 0, sizeof *light);
    bool ok = fsf_light_from_renderer(r, light, &d);
    if (!ok) fprintf(stderr, "%s\n", d.message);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return ok;
}

static void check_degenerate_first(void)
{
    const char *quad = "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
                       "  Shape \"trianglemesh\" \"point3 P\" [ -0.5 3 -0.4  0.7 3 -0.5  0.6 3 0.5  -0.4 3 0.6 ]"
                       " \"integer indices\" [ %s0 2 1  0 3 2 ]\nAttributeEnd\n";
    char plain[1024], degenerate[1024];
    snprintf(plain, sizeof plain, quad, "");
    snprintf(degenerate, sizeof degenerate, quad, "1 1 3  "); /* two equal corners: no area, no normal */
    FsfLight a, b;
    bool ok_a = frame_of(plain, &a), ok_b = frame_of(degenerate, &b);
    CHECK(ok_a && ok_b);
    b.shape = a.shape; /* the same shape index in both scenes, but say so rather than assume it */
    CHECK(memcmp(&a, &b, sizeof a) == 0);
}

int main(void)
{
    static char lights[1 << 19];
    /* the brightest first, then last */
    lights[0] = '\0';
    add_quad(lights, sizeof lights, -2, 3, 0.5f, 8, 1);
    add_quad(lights, sizeof lights, 0, 3, 0.5f, 2, 1);
    add_quad(lights, sizeof lights, 2, 3, 0.5f, 1, 1);
    check_scene(lights, "brightest first");
    lights[0] = '\0';
    add_quad(lights, sizeof lights, -2, 3, 0.5f, 1, 1);
    add_quad(lights, sizeof lights, 0, 3, 0.5f, 2, 1);
    add_quad(lights, sizeof lights, 2, 3, 0.5f, 8, 1);
    check_scene(lights, "brightest last");
    /* a mesh of 2 x 24 x 24 small triangles outweighs one brighter quad by its area */
    lights[0] = '\0';
    add_quad(lights, sizeof lights, -2, 3, 0.3f, 6, 1);
    add_quad(lights, sizeof lights, 1, 3, 0.8f, 3, 24);
    check_scene(lights, "a mesh light");
    /* two shapes of equal power: the first wins */
    lights[0] = '\0';
    add_quad(lights, sizeof lights, -2, 3, 0.5f, 4, 1);
    add_quad(lights, sizeof lights, 2, 3, 0.5f, 4, 2);
    check_scene(lights, "a tie");
    check_degenerate_first();
    CHECK_DONE();
}
