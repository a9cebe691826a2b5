/* renderer_set_overscan: with a band of M pixels, pixel (x + M, y + M) of the enlarged raster
 * shoots the camera rays pixel (x, y) shot without it (same film position, lens point and
 * time), for a wide, a tall and an explicit-screenwindow image, a thin lens and a moving
 * camera. The film position is formed as the integrator forms it ((float)px + u), so the
 * two positions differ by the rounding of a sum of magnitude W + 2M against one of W: the
 * rays agree to that rounding (a few ulps of the raster coordinate, turned into an angle by
 * the screen extent of a pixel), not bit for bit. M = 0 restores the plain camera bit for
 * bit, and the enlarged raster renders: every sample of pixel (x, y) lies in [x, x + 1). */
#include <float.h>

#include "check.h"
#include "render_test_util.h"

static const char *const SCENES[] = {
    /* wide, thin lens, camera moving during the shutter */
    "ActiveTransform StartTime\nLookAt 0 1 -5  0 0.5 0  0 1 0\n"
    "ActiveTransform EndTime\nLookAt 0.4 1.1 -5  0 0.5 0  0 1 0\nActiveTransform All\n"
    "Camera \"perspective\" \"float fov\" [ 40 ] \"float lensradius\" [ 0.2 ] \"float focaldistance\" [ 4 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 40 ] \"integer yresolution\" [ 24 ]\n"
    "Sampler \"independent\" \"integer pixelsamples\" [ 2 ]\n"
    "WorldBegin\nLightSource \"distant\" \"rgb L\" [ 1 1 1 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -5 0 -4  5 0 -4  5 0 4  -5 0 4 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n",
    /* tall, pinhole */
    "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 17 ] \"integer yresolution\" [ 33 ]\n"
    "WorldBegin\nShape \"sphere\" \"float radius\" [ 1 ]\n",
    /* an explicit, off-centre screen window */
    "LookAt 0 0 -5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 50 ] \"float screenwindow\" [ -0.5 1.5 -1 0.25 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 20 ]\n"
    "WorldBegin\nShape \"sphere\" \"float radius\" [ 1 ]\n",
};

static unsigned next_u32(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}
static float unit01(unsigned *s) { return (float)next_u32(s) / 16777216.0f; }

static bool make(const char *text, SceneDesc *scene, Renderer **r)
{
    Diag err = {0};
    if (!scene_parse_string(text, strlen(text), "<test>", NULL, scene, &err)) {
        fprintf(stderr, "parse failed: %s\n", err.message);
        return false;
    }
    RenderOptions o = {0};
    o.threads = 1;
    if (!renderer_create(scene, &o, r, &err)) {
        fprintf(stderr, "renderer_create failed: %s\n", err.message);
        scene_desc_free(scene);
        return false;
    }
    return true;
}

static float vdist(vec3 a, vec3 b) { return v3_length(v3_sub(a, b)); }

/* Every sample of pixel (x, y) has its film position inside the pixel. */
typedef struct {
    long samples, outside;
} FilmCheck;

static void film_add(void *ctx, int px, int py, const SampleRecord *rec)
{
    FilmCheck *c = ctx;
    c->samples++;
    c->outside += !(rec->px_raster >= (float)px && rec->px_raster <= (float)px + 1.0f && rec->py_raster >= (float)py &&
                    rec->py_raster <= (float)py + 1.0f);
}

static void check_scene(const char *text, int margin)
{
    SceneDesc s0, s1;
    Renderer *r0, *r1;
    if (!make(text, &s0, &r0)) {
        CHECK(false);
        return;
    }
    if (!make(text, &s1, &r1)) {
        CHECK(false);
        renderer_destroy(r0), scene_desc_free(&s0);
        return;
    }
    int w = renderer_width(r0), h = renderer_height(r0);
    Diag err = {0};
    CHECK(renderer_set_overscan(r1, margin, &err));
    CHECK(renderer_overscan_px(r1) == margin);
    CHECK(renderer_width(r1) == w + 2 * margin && renderer_height(r1) == h + 2 * margin);
    const Camera *c0 = renderer_camera(r0), *c1 = renderer_camera(r1);
    /* the film position's rounding, ulp(W + 2M + 1) pixels, as an angle on the screen:
     * screen units per pixel times tan(fov / 2) (directions are unit vectors) */
    float raster_ulp = 2.0f * FLT_EPSILON * (float)(w + 2 * margin + 1);
    float per_px = fmaxf((c0->screen_max[0] - c0->screen_min[0]) / (float)w, (c0->screen_max[1] - c0->screen_min[1]) / (float)h);
    /* plus the float arithmetic of a ray itself (a few ulps of unit-size quantities) */
    float tol_dir = 4.0f * raster_ulp * per_px * c0->tan_half_fov + 16.0f * FLT_EPSILON;
    float tol_org = 16.0f * FLT_EPSILON * 16.0f; /* |origin| < 16 world units here */
    unsigned seed = 12345u;
    float worst_dir = 0.0f, worst_org = 0.0f;
    for (int k = 0; k < 2000; ++k) {
        int x = (int)(next_u32(&seed) % (unsigned)w), y = (int)(next_u32(&seed) % (unsigned)h);
        /* the pixel corners too: the film sample's ends */
        float u = k < 4 ? (float)(k & 1) : unit01(&seed), v = k < 4 ? (float)(k >> 1) : unit01(&seed);
        vec2 lens = v2(2.0f * unit01(&seed) - 1.0f, 2.0f * unit01(&seed) - 1.0f);
        float t = unit01(&seed);
        CameraRay a = camera_generate_ray(c0, (float)x + u, (float)y + v, lens, t);
        CameraRay b = camera_generate_ray(c1, (float)(x + margin) + u, (float)(y + margin) + v, lens, t);
        worst_dir = fmaxf(worst_dir, vdist(a.d_world, b.d_world));
        worst_org = fmaxf(worst_org, vdist(a.o_world, b.o_world));
    }
    printf("margin %d, %dx%d: worst direction gap %.3g (tolerance %.3g), origin gap %.3g\n", margin, w, h,
           (double)worst_dir, (double)tol_dir, (double)worst_org);
    CHECK(worst_dir <= tol_dir);
    CHECK(worst_org <= tol_org);

    /* the enlarged raster renders, each sample inside its own (enlarged) pixel */
    Frame f;
    CHECK(frame_init(&f, renderer_width(r1), renderer_height(r1)));
    FilmCheck fc = {0};
    SampleSink sink = {film_add, &fc};
    CHECK(render_pass(r1, 0, NULL, 2, &f, &sink));
    CHECK(fc.samples == 2L * renderer_width(r1) * renderer_height(r1));
    CHECK(fc.outside == 0);
    CHECK(frame_spp_avg(&f) == 2.0);
    frame_free(&f);

    /* back to no band: the plain camera, bit for bit */
    CHECK(renderer_set_overscan(r1, 0, &err));
    CHECK(renderer_width(r1) == w && renderer_height(r1) == h && renderer_overscan_px(r1) == 0);
    c1 = renderer_camera(r1);
    CHECK(!memcmp(c0->screen_min, c1->screen_min, sizeof c0->screen_min));
    CHECK(!memcmp(c0->screen_max, c1->screen_max, sizeof c0->screen_max));
    CameraRay a = camera_generate_ray(c0, 3.25f, 2.5f, v2(0.3f, -0.2f), 0.7f);
    CameraRay b = camera_generate_ray(c1, 3.25f, 2.5f, v2(0.3f, -0.2f), 0.7f);
    CHECK(!memcmp(&a, &b, sizeof a));

    CHECK(!renderer_set_overscan(r1, -1, &err));
    CHECK_STR(err.message, "error: overscan must be >= 0 pixels, got -1");
    renderer_destroy(r0), renderer_destroy(r1);
    scene_desc_free(&s0), scene_desc_free(&s1);
}

int main(void)
{
    for (size_t i = 0; i < sizeof SCENES / sizeof SCENES[0]; ++i) {
        check_scene(SCENES[i], 8);
        check_scene(SCENES[i], 3);
    }
    CHECK_DONE();
}
