/* Motion blur: (1) an emissive sphere moving from x0 to x1 during the shutter covers, on the
 * image row through its centre, exactly the pixels between the projections of its left
 * edge at shutter open and its right edge at shutter close; (2) a square rotating by 90
 * degrees about the view axis keeps its silhouette area at every instant (pbrt-v4 slerp of
 * the rotation, not a linear blend of matrices, which would shrink it to half at mid-
 * shutter), so its time-averaged image has the same total emission as the static square;
 * (3) a scene without motion samples no time (effects.motion false); (4) a camera that
 * moves during the shutter blurs a static sphere over its projected path; (5) a moving
 * sphere light lights a plane with the time average of the static closed form
 * E(t) = pi L r^2 h / D(t)^3 (D the distance to the centre, h its height), integrated
 * numerically over the shutter: light sampling and MIS follow the moving emitter; (6) a
 * rectangular light spinning about the vertical axis through the lit point keeps the
 * closed-form irradiance of test_closed_forms.c at every instant. */
#include "check.h"
#include "render/camera.h"
#include "render_test_util.h"

static const char *SPHERE_SCENE =
    "LookAt 0 0 -5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 30 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 96 ] \"integer yresolution\" [ 24 ]\n"
    "Sampler \"independent\" \"integer pixelsamples\" [ 64 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
    " ActiveTransform StartTime\n Translate %g 0 0\n ActiveTransform EndTime\n Translate %g 0 0\n ActiveTransform All\n"
    " Shape \"sphere\" \"float radius\" [ %g ]\nAttributeEnd\n";

static const char *SQUARE_SCENE =
    "LookAt 0 0 -5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 30 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 48 ]\n"
    "Sampler \"independent\" \"integer pixelsamples\" [ 64 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"bool twosided\" true\n"
    " Translate 0.1 -0.05 0\n"
    " ActiveTransform EndTime\n %s\n ActiveTransform All\n"
    " Shape \"trianglemesh\" \"point3 P\" [ -0.6 -0.6 0  0.6 -0.6 0  0.6 0.6 0  -0.6 0.6 0 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n";

/* The same square as an object instance whose instance transform rotates. */
static const char *INSTANCE_SCENE =
    "LookAt 0 0 -5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 30 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 48 ]\n"
    "Sampler \"independent\" \"integer pixelsamples\" [ 64 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
    "ObjectBegin \"sq\"\n"
    " Shape \"trianglemesh\" \"point3 P\" [ -0.6 -0.6 0  0.6 -0.6 0  0.6 0.6 0  -0.6 0.6 0 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "ObjectEnd\n"
    "AttributeBegin\n Translate 0 0 -0.5\n AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"bool twosided\" true\n"
    " Shape \"trianglemesh\" \"point3 P\" [ -9 -9 1  9 -9 1  9 9 1  -9 9 1 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n Translate 0.1 -0.05 0\n ActiveTransform EndTime\n %s\n ActiveTransform All\n"
    " ObjectInstance \"sq\"\nAttributeEnd\n";

static double total_emission(const TestRender *t)
{
    double s = 0.0;
    for (int y = 0; y < t->frame.height; ++y)
        for (int x = 0; x < t->frame.width; ++x) {
            double rgb[3];
            test_pixel(t, x, y, rgb);
            s += rgb[0];
        }
    return s;
}

int main(void)
{
    /* (1) blur extent */
    {
        double x0 = -1.0, x1 = 1.2, r = 0.3;
        char text[2048];
        snprintf(text, sizeof text, SPHERE_SCENE, x0, x1, r);
        TestRender t;
        RenderOptions o = {0};
        o.seed = 5;
        if (test_render(text, &o, &t)) {
            CHECK(effect_in(renderer_effects(t.r), EFFECT_MOTION));
            const Camera *cam = renderer_camera(t.r);
            float left_px, right_px, py;
            /* silhouette half-width of a sphere at distance D: r D / sqrt(D^2 - r^2) on the z = 0 plane */
            double D = 5.0, half = r * D / sqrt(D * D - r * r);
            CHECK(camera_project(cam, v3((float)(x0 - half), 0.0f, 0.0f), 0.0f, &left_px, &py));
            CHECK(camera_project(cam, v3((float)(x1 + half), 0.0f, 0.0f), 1.0f, &right_px, &py));
            int row = (int)py;
            int first = -1, last = -1;
            for (int x = 0; x < t.frame.width; ++x) {
                double rgb[3];
                test_pixel(&t, x, row, rgb);
                if (rgb[0] > 0.0) {
                    if (first < 0) first = x;
                    last = x;
                }
            }
            fprintf(stderr, "blur: covered pixels [%d, %d], projected extent [%.2f, %.2f]\n", first, last, left_px, right_px);
            /* a pixel is covered when any part of it is: floor(left) .. floor(right) */
            CHECK(abs(first - (int)floor(left_px)) <= 1);
            CHECK(abs(last - (int)floor(right_px)) <= 1);
            /* interior pixels are partially covered (the sphere passes by), not fully lit */
            double mid[3];
            test_pixel(&t, (int)(0.5 * (left_px + right_px)), row, mid);
            CHECK(mid[0] > 0.05 && mid[0] < 0.6);
            test_render_free(&t);
        } else {
            CHECK(false);
        }
    }
    /* (2) rotation keeps the silhouette area, for a moving shape and a moving instance */
    {
        const char *ends[] = {"Rotate 90 0 0 1", "Translate 0.3 0.2 0\n Rotate 120 0 0 1"};
        char text[4096];
        RenderOptions o = {0};
        o.seed = 9;
        for (int scene = 0; scene < 2; ++scene) {
            const char *fmt = scene == 0 ? SQUARE_SCENE : INSTANCE_SCENE;
            TestRender ts;
            snprintf(text, sizeof text, fmt, "");
            if (!test_render(text, &o, &ts)) {
                CHECK(false);
                continue;
            }
            CHECK(!effect_in(renderer_effects(ts.r), EFFECT_MOTION)); /* identical ends: no time dimension */
            double a_static = total_emission(&ts);
            if (scene == 1) a_static = ts.frame.width * ts.frame.height - a_static; /* dark square on a bright wall */
            for (int e = 0; e < 2; ++e) {
                TestRender tr;
                snprintf(text, sizeof text, fmt, ends[e]);
                if (!test_render(text, &o, &tr)) {
                    CHECK(false);
                    continue;
                }
                CHECK(effect_in(renderer_effects(tr.r), EFFECT_MOTION));
                double a_rot = total_emission(&tr);
                if (scene == 1) a_rot = tr.frame.width * tr.frame.height - a_rot;
                fprintf(stderr, "%s: static area %.3f px, moving (%s) %.3f px\n", scene ? "instance" : "shape", a_static,
                        ends[e], a_rot);
                CHECK_NEAR(a_rot / a_static, 1.0, 0.01);
                /* the blur is real: the moving square differs from the static one */
                int changed = 0;
                for (int i = 0; i < ts.frame.width * ts.frame.height; ++i)
                    changed += fabsf(ts.frame.color[3 * i] / ts.frame.spp[i] - tr.frame.color[3 * i] / tr.frame.spp[i]) > 0.2f;
                CHECK(changed > 50);
                test_render_free(&tr);
            }
            test_render_free(&ts);
        }
    }
    /* (4) moving camera: the camera slides right by 1.5, the static sphere slides left */
    {
        const char *text =
            "ActiveTransform StartTime\nLookAt 0 0 -5  0 0 0  0 1 0\n"
            "ActiveTransform EndTime\nLookAt 1.5 0 -5  1.5 0 0  0 1 0\nActiveTransform All\n"
            "Camera \"perspective\" \"float fov\" [ 30 ]\n"
            "Film \"rgb\" \"integer xresolution\" [ 96 ] \"integer yresolution\" [ 24 ]\n"
            "Sampler \"independent\" \"integer pixelsamples\" [ 64 ]\n"
            "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
            "WorldBegin\n"
            "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n Shape \"sphere\" \"float radius\" [ 0.3 ]\nAttributeEnd\n";
        TestRender t;
        RenderOptions o = {0};
        o.seed = 4;
        if (test_render(text, &o, &t)) {
            CHECK(effect_in(renderer_effects(t.r), EFFECT_MOTION));
            const Camera *cam = renderer_camera(t.r);
            double D = 5.0, r = 0.3, half = r * D / sqrt(D * D - r * r);
            float left_px, right_px, py;
            /* at shutter close the sphere is furthest left, at shutter open furthest right */
            CHECK(camera_project(cam, v3((float)-half, 0.0f, 0.0f), 1.0f, &left_px, &py));
            CHECK(camera_project(cam, v3((float)half, 0.0f, 0.0f), 0.0f, &right_px, &py));
            int row = (int)py, first = -1, last = -1;
            for (int x = 0; x < t.frame.width; ++x) {
                double rgb[3];
                test_pixel(&t, x, row, rgb);
                if (rgb[0] > 0.0) {
                    if (first < 0) first = x;
                    last = x;
                }
            }
            fprintf(stderr, "camera motion: covered [%d, %d], projected [%.2f, %.2f]\n", first, last, left_px, right_px);
            CHECK(abs(first - (int)floor(left_px)) <= 1);
            CHECK(abs(last - (int)floor(right_px)) <= 1);
            CHECK(last - first > 15); /* the blur is much wider than the sphere (about 6 pixels) */
            test_render_free(&t);
        } else {
            CHECK(false);
        }
    }
    /* (5) a moving sphere light */
    {
        double L = 3.0, r = 0.3, h = 1.5, x0 = -1.0, x1 = 1.6;
        char text[2048];
        snprintf(text, sizeof text,
                 "LookAt 0 0.8 -3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 0.02 ]\n"
                 "Film \"rgb\" \"integer xresolution\" [ 1 ] \"integer yresolution\" [ 1 ]\n"
                 "Sampler \"independent\" \"integer pixelsamples\" [ 16384 ]\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\n"
                 "WorldBegin\n"
                 "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
                 "Shape \"trianglemesh\" \"point3 P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                 "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ %g %g %g ]\n"
                 " ActiveTransform StartTime\n Translate %g %g 0\n ActiveTransform EndTime\n Translate %g %g 0\n"
                 " ActiveTransform All\n Shape \"sphere\" \"float radius\" [ %g ]\nAttributeEnd\n",
                 L, L, L, x0, h, x1, h, r);
        TestRender t;
        RenderOptions o = {0};
        o.seed = 8;
        o.sampler_set = true;
        o.sampler = SAMPLER_STRATIFIED;
        if (test_render(text, &o, &t)) {
            double rgb[3];
            test_pixel(&t, 0, 0, rgb);
            double E = 0.0;
            const int steps = 100000;
            for (int i = 0; i < steps; ++i) {
                double x = x0 + (x1 - x0) * (i + 0.5) / steps, D = sqrt(x * x + h * h);
                E += 3.14159265358979323846 * L * r * r * h / (D * D * D);
            }
            E /= steps;
            double want = 0.5 * E / 3.14159265358979323846;
            fprintf(stderr, "moving sphere light: got %.5f want %.5f\n", rgb[0], want);
            CHECK_NEAR(rgb[0] / want, 1.0, 0.01);
            test_render_free(&t);
        } else {
            CHECK(false);
        }
    }
    /* (6) a spinning rectangle light */
    {
        double L = 3.0, a = 0.6, b = 0.4, h = 1.0, A = a / h, B = b / h;
        double E = 2.0 * L * (A / sqrt(1 + A * A) * atan(B / sqrt(1 + A * A)) + B / sqrt(1 + B * B) * atan(A / sqrt(1 + B * B)));
        char text[2048];
        snprintf(text, sizeof text,
                 "LookAt 0 0.8 -3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 0.02 ]\n"
                 "Film \"rgb\" \"integer xresolution\" [ 1 ] \"integer yresolution\" [ 1 ]\n"
                 "Sampler \"independent\" \"integer pixelsamples\" [ 16384 ]\nIntegrator \"path\" \"integer maxdepth\" [ 1 ]\n"
                 "WorldBegin\n"
                 "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
                 "Shape \"trianglemesh\" \"point3 P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                 "AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [ %g %g %g ]\n"
                 " Translate 0 %g 0\n ActiveTransform EndTime\n Rotate 100 0 1 0\n ActiveTransform All\n"
                 " Shape \"trianglemesh\" \"point3 P\" [ %g 0 %g  %g 0 %g  %g 0 %g  %g 0 %g ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                 "AttributeEnd\n",
                 L, L, L, h, -a, -b, a, -b, a, b, -a, b);
        TestRender t;
        RenderOptions o = {0};
        o.seed = 8;
        o.sampler_set = true;
        o.sampler = SAMPLER_STRATIFIED;
        if (test_render(text, &o, &t)) {
            CHECK(effect_in(renderer_effects(t.r), EFFECT_MOTION));
            double rgb[3];
            test_pixel(&t, 0, 0, rgb);
            double want = 0.5 * E / 3.14159265358979323846;
            fprintf(stderr, "spinning rectangle light: got %.5f want %.5f\n", rgb[0], want);
            CHECK_NEAR(rgb[0] / want, 1.0, 0.01);
            test_render_free(&t);
        } else {
            CHECK(false);
        }
    }
    CHECK_DONE();
}
