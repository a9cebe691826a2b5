/* Camera: a pinhole and a thin lens with lensradius 0 give identical images; image
 * orientation as pbrt-v4 (world +x to the right and +y up for LookAt along +z with up +y,
 * raster (0,0) at the top-left); fov spans the shorter image axis; generate_ray and
 * project are inverse maps (screen window and frame aspect included); the batched
 * camera_generate_rays gives camera_generate_ray's rays bit for bit (pinhole, thin lens,
 * moving camera; counts that are not a multiple of any vector width). */
#include "check.h"
#include "render/camera.h"
#include "render_test_util.h"

#define PI 3.14159265358979323846

static const char *SCENE =
    "LookAt 0 1 -4  0 0.5 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ] %s\n"
    "Film \"rgb\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 16 ]\n"
    "Sampler \"independent\" \"integer pixelsamples\" [ 4 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 2 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ]\n"
    " Shape \"trianglemesh\" \"point3 P\" [ -0.5 2 -0.5  0.5 2 -0.5  0.5 2 0.5  -0.5 2 0.5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeBegin\n Translate 0 0.5 0\n Shape \"sphere\" \"float radius\" [ 0.5 ]\nAttributeEnd\n";

static bool frames_equal(const Frame *a, const Frame *b)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    return a->width == b->width && a->height == b->height && !memcmp(a->color, b->color, 3 * n * sizeof(float)) &&
           !memcmp(a->direct, b->direct, 3 * n * sizeof(float)) && !memcmp(a->indirect, b->indirect, 3 * n * sizeof(float));
}

/* Which quadrant an emissive sphere lands in, for a camera at the origin looking down +z. */
static void brightest_pixel(const char *sphere_pos, int *bx, int *by)
{
    char text[2048];
    snprintf(text, sizeof text,
             "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" [ 60 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
             "Sampler \"independent\" \"integer pixelsamples\" [ 1 ]\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\n"
             "WorldBegin\nAttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n Translate %s\n"
             " Shape \"sphere\" \"float radius\" [ 0.2 ]\nAttributeEnd\n",
             sphere_pos);
    TestRender t;
    *bx = *by = -1;
    if (!test_render(text, NULL, &t)) return;
    double best = 0.0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            double rgb[3];
            test_pixel(&t, x, y, rgb);
            if (rgb[0] > best) best = rgb[0], *bx = x, *by = y;
        }
    test_render_free(&t);
}

static void check_roundtrip(const CameraDesc *cd, int w, int h)
{
    Camera cam;
    Diag err;
    CHECK(camera_init(&cam, cd, w, h, &err));
    const float pts[3][2] = {{0.5f, 0.5f}, {(float)w - 2.25f, 1.75f}, {3.0f, (float)h - 0.5f}};
    for (int i = 0; i < 3; ++i) {
        CameraRay r = camera_generate_ray(&cam, pts[i][0], pts[i][1], v2(0, 0), 0.0f);
        vec3 p = v3_madd(r.o_world, r.d_world, 7.0f);
        float px, py;
        CHECK(camera_project(&cam, p, 0.0f, &px, &py));
        CHECK_NEAR(px, pts[i][0], 1e-3);
        CHECK_NEAR(py, pts[i][1], 1e-3);
    }
}

/* camera_generate_rays against camera_generate_ray, ray by ray, every bit. */
static void check_batch(const CameraDesc *cd, int w, int h)
{
    enum { N = 61 };
    Camera cam;
    Diag err;
    CHECK(camera_init(&cam, cd, w, h, &err));
    float px[N], py[N], lu[N], lv[N], t[N], o[3][N], d[3][N];
    for (int k = 0; k < N; ++k) {
        /* film positions over the whole raster and a little beyond, lens points over the disk */
        px[k] = (float)(w + 2) * (float)((k * 37) % N) / N - 1.0f;
        py[k] = (float)(h + 2) * (float)((k * 17) % N) / N - 1.0f;
        lu[k] = (float)cos(0.7 * k) * (float)((k % 7) + 1) / 7.0f;
        lv[k] = (float)sin(0.7 * k) * (float)((k % 7) + 1) / 7.0f;
        t[k] = (float)k / (N - 1);
    }
    float *op[3] = {o[0], o[1], o[2]}, *dp[3] = {d[0], d[1], d[2]};
    for (int count = N; count >= N - 8; count -= 4) {
        camera_generate_rays(&cam, count, px, py, lu, lv, t, op, dp);
        int same = 0;
        for (int k = 0; k < count; ++k) {
            CameraRay r = camera_generate_ray(&cam, px[k], py[k], v2(lu[k], lv[k]), t[k]);
            float got[6] = {o[0][k], o[1][k], o[2][k], d[0][k], d[1][k], d[2][k]};
            float want[6] = {r.o_world.x, r.o_world.y, r.o_world.z, r.d_world.x, r.d_world.y, r.d_world.z};
            same += !memcmp(got, want, sizeof got);
        }
        CHECK(same == count);
    }
}

int main(void)
{
    /* pinhole vs lensradius 0 (with a focal distance that would matter for a lens) */
    char a[4096], b[4096];
    snprintf(a, sizeof a, SCENE, "");
    snprintf(b, sizeof b, SCENE, "\"float lensradius\" [ 0 ] \"float focaldistance\" [ 2.5 ]");
    TestRender ta, tb;
    RenderOptions o = {0};
    o.seed = 11;
    if (test_render(a, &o, &ta) && test_render(b, &o, &tb)) {
        CHECK(frames_equal(&ta.frame, &tb.frame));
        CHECK(test_mean(&ta) > 0.0);
        test_render_free(&ta);
        test_render_free(&tb);
    } else {
        CHECK(false);
    }

    /* orientation: +x right, +y up, raster (0,0) top-left */
    int bx, by;
    brightest_pixel("0.6 0.6 2", &bx, &by);
    CHECK(bx >= 16 && by < 16);
    brightest_pixel("-0.6 -0.6 2", &bx, &by);
    CHECK(bx < 16 && by >= 16 && bx >= 0);

    /* fov on the shorter axis: a point at fov/2 above the axis lands on the top edge of a
     * wide image; a point at fov/2 to the right lands on the right edge of a tall one */
    CameraDesc cd;
    memset(&cd, 0, sizeof cd);
    cd.fov_deg = 50.0f;
    cd.focal_distance = 1e6f;
    cd.shutter_close = 1.0f;
    cd.camera_from_world.m[0] = cd.camera_from_world.m[1] = mat4_identity();
    Camera cam;
    Diag err;
    float px, py, t = (float)tan(25.0 * PI / 180.0);
    CHECK(camera_init(&cam, &cd, 200, 100, &err));
    CHECK(camera_project(&cam, v3(0.0f, t, 1.0f), 0.0f, &px, &py));
    CHECK_NEAR(py, 0.0, 1e-3);
    CHECK_NEAR(px, 100.0, 1e-3);
    CHECK(camera_init(&cam, &cd, 100, 200, &err));
    CHECK(camera_project(&cam, v3(t, 0.0f, 1.0f), 0.0f, &px, &py));
    CHECK_NEAR(px, 100.0, 1e-3);
    CHECK_NEAR(py, 100.0, 1e-3);

    /* the batch: pinhole, thin lens, a turned camera, a moving one */
    check_batch(&cd, 100, 200);
    cd.lens_radius = 0.3f;
    cd.focal_distance = 2.5f;
    check_batch(&cd, 64, 48);
    const double eye[3] = {1.0, 2.0, -4.0}, look[3] = {0.2, 0.1, 0.3}, up[3] = {0.1, 1.0, 0.0};
    CHECK(mat4_lookat(eye, look, up, &cd.camera_from_world.m[0]));
    cd.camera_from_world.m[1] = cd.camera_from_world.m[0];
    check_batch(&cd, 64, 48);
    cd.lens_radius = 0.0f;
    check_batch(&cd, 64, 48);
    Mat4 shift = mat4_translate(0.5, 0.0, 0.2);
    cd.camera_from_world.m[1] = mat4_mul(&shift, &cd.camera_from_world.m[0]);
    check_batch(&cd, 64, 48);
    cd.camera_from_world.m[0] = cd.camera_from_world.m[1] = mat4_identity();
    cd.focal_distance = 1e6f;

    check_roundtrip(&cd, 100, 200);
    cd.frame_aspect = 1.5f;
    check_roundtrip(&cd, 64, 48);
    cd.has_screen_window = true;
    cd.screen_window[0] = -0.5f, cd.screen_window[1] = 1.0f, cd.screen_window[2] = -0.25f, cd.screen_window[3] = 0.75f;
    check_roundtrip(&cd, 30, 20);
    /* screen window (xmin, ymax) is raster (0, 0) */
    CHECK(camera_init(&cam, &cd, 30, 20, &err));
    CHECK(camera_project(&cam, v3(-0.5f * t, 0.75f * t, 1.0f), 0.0f, &px, &py));
    CHECK_NEAR(px, 0.0, 1e-3);
    CHECK_NEAR(py, 0.0, 1e-3);
    CHECK_DONE();
}
