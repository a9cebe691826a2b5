/* The blur probe (recon/blur_probe.h) against geometry on two scenes where the blur of every
 * visible point is known in closed form:
 *
 *   motion  pinhole camera at distance D from a wall parallel to the film that moves by dx
 *           (world) across it during the shutter: every point moves dx / (D * pixel_angle)
 *           pixels, with pixel_angle = 2 tan(fov/2) / W (the world size of a pixel at
 *           depth 1, square image);
 *   lens    a static wall at depth z seen through a thin lens of radius R focused at F: a
 *           point's lens rays meet the focal plane in a disk of diameter 2 R |1 - F/z|, which
 *           is 2 R |1 - F/z| / (F * pixel_angle) pixels seen from the lens centre.
 *
 * Every probe sample hits the wall, so the median is that one value; the only error is float
 * rounding in projecting and differencing the two poses (and in the camera's matrices), far
 * below 0.01 px for blurs of a few pixels: the tolerance is 1e-3 relative. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "../check.h"
#include "recon/blur_probe.h"
#include "recon_test_util.h"

enum { W = 64 };
static const double D_WORLD = 5.0, FOV_DEG = 40.0;

static const char *const MOVING =
    "LookAt 0 0 -5   0 0 0   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 64 ] \"string filename\" [ \"t.exr\" ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 4 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "LightSource \"distant\" \"rgb L\" [ 2 2 2 ] \"point3 from\" [ 0 0 -3 ] \"point3 to\" [ 0 0 0 ]\n"
    "AttributeBegin\n"
    "  Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "  ActiveTransform StartTime\n"
    "  Translate 0 0 0\n"
    "  ActiveTransform EndTime\n"
    "  Translate 0.5 0 0\n"
    "  ActiveTransform All\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -20 -20 0  20 -20 0  20 20 0  -20 20 0 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n";

static const char *const LENS =
    "LookAt 0 0 -5   0 0 0   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ] \"float lensradius\" [ 0.1 ] \"float focaldistance\" [ 2.5 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 64 ] \"string filename\" [ \"t.exr\" ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 4 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "LightSource \"distant\" \"rgb L\" [ 2 2 2 ] \"point3 from\" [ 0 0 -3 ] \"point3 to\" [ 0 0 0 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -20 -20 0  20 -20 0  20 20 0  -20 20 0 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n";

static BlurProbe probe(const char *text)
{
    SceneDesc scene;
    Renderer *r = NULL;
    BlurProbe b = {.median_blur_px = -1.0f};
    if (!recon_test_renderer(text, 1, 4, false, &scene, &r)) {
        CHECK(!"scene");
        return b;
    }
    CHECK(recon_blur_probe(r, &b));
    /* deterministic: a second probe gives the same value bit for bit */
    BlurProbe again;
    CHECK(recon_blur_probe(r, &again) && again.median_blur_px == b.median_blur_px);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return b;
}

/* A hit at (almost) the lens plane: its circle of confusion overflows a float; the blur
 * saturates at FLT_MAX instead of reading as 0 px (an unblurred sample), and a hit at an
 * ordinary depth keeps its finite value. */
static void test_unbounded(void)
{
    ReconCamera cam = {0};
    cam.lens_radius_world = 0.1f;
    cam.focal_distance_world = 2.5f;
    cam.pixel_angle = 1e-3f;
    SampleRecord rec = {0};
    rec.hit = true;
    rec.depth_cam = 1e-38f;
    CHECK(blur_extent_px(&cam, &rec) == FLT_MAX);
    rec.depth_cam = 5.0f;
    CHECK_NEAR(blur_extent_px(&cam, &rec), 2.0 * 100.0 * (1.0 / 2.5 - 1.0 / 5.0), 1e-3);
    rec.hit = false;
    CHECK(blur_extent_px(&cam, &rec) == 0.0f);
}

int main(void)
{
    test_unbounded();
    double pixel_angle = 2.0 * tan(FOV_DEG * M_PI / 360.0) / W;

    BlurProbe m = probe(MOVING);
    double motion_px = 0.5 / (D_WORLD * pixel_angle); /* 8.79 px */
    CHECK(m.samples == BLUR_PROBE_GRID * BLUR_PROBE_GRID * BLUR_PROBE_SPP && m.samples_hit == m.samples);
    CHECK_NEAR(m.median_blur_px, motion_px, 1e-3 * motion_px);

    BlurProbe l = probe(LENS);
    double R = 0.1, F = 2.5, z = D_WORLD;
    double coc_px = 2.0 * R * fabs(1.0 - F / z) / (F * pixel_angle); /* 3.52 px */
    CHECK(l.samples_hit == l.samples && l.samples > 0);
    CHECK(m.samples_unbounded == 0 && l.samples_unbounded == 0);
    CHECK_NEAR(l.median_blur_px, coc_px, 1e-3 * coc_px);
    printf("motion: probe %.4f px, geometry %.4f px; lens: probe %.4f px, geometry %.4f px\n", m.median_blur_px,
           motion_px, l.median_blur_px, coc_px);
    return check_failures ? 1 : 0;
}
