/* One-sided versus two-sided area lights (pbrt-v4 rules): a diffuse area light emits only
 * on the side of its surface normal unless "twosided"; the triangle normal follows the
 * winding (counter-clockwise = right-handed cross product), ReverseOrientation flips it;
 * spheres emit outwards, disks along +z of their object space.
 * A plane under the light must see exactly 0 when the light faces away, and the closed-form
 * radiance rho E / pi (test_closed_forms.c) when it faces the plane.
 * A light sample the receiver or the light faces away from casts no shadow ray (the wave
 * decides this without a branch for a Lambert receiver of a triangle light: integrator.c,
 * light_prepare_lambert_triangle): counted with a light behind the plane. */
#include "check.h"
#include "render_test_util.h"

#define PI 3.14159265358979323846

static const char *HEADER =
    "LookAt 0 0.8 -3  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 0.02 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 1 ] \"integer yresolution\" [ 1 ]\n"
    "Sampler \"independent\" \"integer pixelsamples\" [ 8192 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    "  Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n";

/* Renders light's scene; the pixel's red value, and its shadow and camera ray counts. */
static double render_counted(const char *light, bool record, long long *shadow, long long *primary)
{
    char text[4096];
    snprintf(text, sizeof text, "%s%s", HEADER, light);
    TestRender t;
    RenderOptions o = {0};
    o.seed = 3;
    o.sampler_set = true;
    o.sampler = SAMPLER_STRATIFIED;
    o.record_ray_geometry = record; /* the first hit's area-light shadow rays go to the recorded batch */
    if (!test_render(text, &o, &t)) {
        CHECK(false);
        return -1.0;
    }
    double rgb[3];
    test_pixel(&t, 0, 0, rgb);
    CHECK(test_frame_finite(&t.frame));
    CHECK(t.stats.guarded_events == 0);
    *shadow = t.stats.rays_shadow, *primary = t.stats.rays_primary;
    test_render_free(&t);
    return rgb[0];
}

static double render(const char *light)
{
    long long shadow, primary;
    return render_counted(light, false, &shadow, &primary);
}

/* quad of half sides 0.5 at height 1: "down" winding has normal -y, "up" winding +y */
#define QUAD_DOWN "Shape \"trianglemesh\" \"point3 P\" [ -0.5 1 -0.5  0.5 1 -0.5  0.5 1 0.5  -0.5 1 0.5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
#define QUAD_UP "Shape \"trianglemesh\" \"point3 P\" [ -0.5 1 -0.5  0.5 1 -0.5  0.5 1 0.5  -0.5 1 0.5 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
#define LIGHT "AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
#define LIGHT2 "AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ] \"bool twosided\" true\n"

int main(void)
{
    double A = 0.5, L = 2.0;
    double E = 2.0 * L * 2.0 * (A / sqrt(1 + A * A) * atan(A / sqrt(1 + A * A)));
    double want = 0.5 * E / PI;

    double down = render("AttributeBegin\n" LIGHT QUAD_DOWN "AttributeEnd\n");
    double up = render("AttributeBegin\n" LIGHT QUAD_UP "AttributeEnd\n");
    double up_two = render("AttributeBegin\n" LIGHT2 QUAD_UP "AttributeEnd\n");
    double up_rev = render("AttributeBegin\nReverseOrientation\n" LIGHT QUAD_UP "AttributeEnd\n");
    double down_rev = render("AttributeBegin\nReverseOrientation\n" LIGHT QUAD_DOWN "AttributeEnd\n");
    /* a mirror transform flips handedness, which pbrt-v4 also counts as a flip for meshes */
    double down_mirror = render("AttributeBegin\nScale 1 1 -1\n" LIGHT QUAD_DOWN "AttributeEnd\n");
    fprintf(stderr, "down %.5f up %.5f up_two %.5f up_rev %.5f down_rev %.5f down_mirror %.5f want %.5f\n", down, up,
            up_two, up_rev, down_rev, down_mirror, want);
    CHECK_NEAR(down / want, 1.0, 0.01);
    CHECK(up == 0.0);
    CHECK_NEAR(up_two / want, 1.0, 0.01);
    CHECK_NEAR(up_rev / want, 1.0, 0.01);
    CHECK(down_rev == 0.0);
    CHECK_NEAR(down_mirror / want, 1.0, 0.01);

    /* Shadow rays: one per camera ray for the light facing the plane, none for a light
     * facing away or one below the plane (facing its underside: the receiver, lit from the
     * camera's side, faces away from it); beside each other the light below takes half the
     * picks (equal power) and none of the shadow rays, and the image keeps the closed form.
     * With the first hit's shadow rays recorded for the filters, the same. */
    const char *below = "AttributeBegin\nTranslate 0 -2 0\n" LIGHT QUAD_UP "AttributeEnd\n";
    char both[2048];
    snprintf(both, sizeof both, "AttributeBegin\n" LIGHT QUAD_DOWN "AttributeEnd\n%s", below);
    for (int record = 0; record < 2; ++record) {
        long long s_down, p_down, s_up, p_up, s_below, p_below, s_both, p_both;
        double v_down = render_counted("AttributeBegin\n" LIGHT QUAD_DOWN "AttributeEnd\n", record, &s_down, &p_down);
        double v_up = render_counted("AttributeBegin\n" LIGHT QUAD_UP "AttributeEnd\n", record, &s_up, &p_up);
        double v_below = render_counted(below, record, &s_below, &p_below);
        double v_both = render_counted(both, record, &s_both, &p_both);
        fprintf(stderr,
                "record %d: shadow rays / camera rays: facing %lld / %lld, facing away %lld / %lld, below %lld / %lld, "
                "both %lld / %lld (%.5f, want %.5f)\n",
                record, s_down, p_down, s_up, p_up, s_below, p_below, s_both, p_both, v_both, want);
        CHECK_NEAR(v_down / want, 1.0, 0.01);
        CHECK(p_down > 0 && s_down == p_down);
        CHECK(v_up == 0.0 && s_up == 0);
        CHECK(v_below == 0.0 && s_below == 0);
        CHECK_NEAR(v_both / want, 1.0, 0.02);
        CHECK(s_both > 0.45 * (double)p_both && s_both < 0.55 * (double)p_both);
    }

    /* disk at height 1 radius 0.6: +z normal rotated to -y (faces the plane), or to +y */
    double R = 0.6, h = 1.0;
    double want_disk = 0.5 * (PI * L * R * R / (h * h + R * R)) / PI;
    double disk_down = render("AttributeBegin\n" LIGHT "Translate 0 1 0\nRotate 90 1 0 0\nShape \"disk\" \"float radius\" [ 0.6 ]\nAttributeEnd\n");
    double disk_up = render("AttributeBegin\n" LIGHT "Translate 0 1 0\nRotate -90 1 0 0\nShape \"disk\" \"float radius\" [ 0.6 ]\nAttributeEnd\n");
    double disk_up2 = render("AttributeBegin\n" LIGHT2 "Translate 0 1 0\nRotate -90 1 0 0\nShape \"disk\" \"float radius\" [ 0.6 ]\nAttributeEnd\n");
    fprintf(stderr, "disk down %.5f up %.5f up two-sided %.5f want %.5f\n", disk_down, disk_up, disk_up2, want_disk);
    CHECK_NEAR(disk_down / want_disk, 1.0, 0.01);
    CHECK(disk_up == 0.0);
    CHECK_NEAR(disk_up2 / want_disk, 1.0, 0.01);

    /* sphere: outward by default; ReverseOrientation makes it emit inwards only */
    double want_sphere = 0.5 * L * 0.25 * 0.25;
    double sph = render("AttributeBegin\n" LIGHT "Translate 0 2 0\nShape \"sphere\" \"float radius\" [ 0.5 ]\nAttributeEnd\n");
    double sph_rev = render("AttributeBegin\nReverseOrientation\n" LIGHT "Translate 0 2 0\nShape \"sphere\" \"float radius\" [ 0.5 ]\nAttributeEnd\n");
    fprintf(stderr, "sphere %.5f reversed %.5f want %.5f\n", sph, sph_rev, want_sphere);
    CHECK_NEAR(sph / want_sphere, 1.0, 0.01);
    CHECK(sph_rev == 0.0);
    CHECK_DONE();
}
