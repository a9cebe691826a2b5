/* OpenColorIO bridge: known values through the built-in Standard view (the sRGB curve,
 * computed here independently from IEC 61966-2-1), the Filmic view's shape, $OCIO
 * honoured with a config written by this test, and the exact unknown-view error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "io/image_io.h"
#include "io/ocio.h"

/* sRGB encoding straight from the standard, in double precision. */
static double srgb_reference(double x)
{
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

static float through_view(const char *view, float grey)
{
    OcioView *v = NULL;
    Diag err = {0};
    if (!ocio_view_open(view, &v, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return NAN;
    }
    float rgb[3] = {grey, grey, grey};
    ocio_view_apply(v, rgb, 1);
    ocio_view_close(v);
    return rgb[1];
}

static void test_standard_view(void)
{
    /* The worked value from the brief: linear 0.18 -> 1.055 * 0.18^(1/2.4) - 0.055. */
    CHECK_NEAR(srgb_reference(0.18), 0.46135612950, 1e-10);
    CHECK_NEAR(through_view("Standard", 0.18f), 0.46135612950, 2e-6);
    CHECK_NEAR(through_view("Standard", 1.0f), 1.0, 2e-6);
    CHECK_NEAR(through_view("Standard", 0.0f), 0.0, 1e-7);
    /* Linear toe. OpenColorIO's curve (ExponentWithLinearTransform, gamma 2.4, offset
     * 0.055) joins the two pieces continuously: the power piece meets the line at
     * x_b = offset / (gamma - 1) in encoded value, so the slope is x_b / decode(x_b) =
     * 12.923..., where IEC 61966-2-1 rounds it to 12.92 (0.02% apart, far below one
     * 8-bit code). Check against the continuous slope, derived here. */
    double xb = 0.055 / (2.4 - 1.0), slope = xb / pow((xb + 0.055) / 1.055, 2.4);
    CHECK_NEAR(slope, 12.92, 0.01);
    CHECK_NEAR(through_view("Standard", 0.002f), slope * 0.002, 2e-7);
    const float xs[] = {0.0031308f, 0.01f, 0.05f, 0.5f, 0.75f};
    for (size_t i = 0; i < sizeof xs / sizeof xs[0]; ++i)
        CHECK_NEAR(through_view("Standard", xs[i]), srgb_reference(xs[i]), 2e-6);
    /* NULL and "" select the default view, which is Standard in the built-in config. */
    CHECK_NEAR(through_view(NULL, 0.18f), 0.46135612950, 2e-6);
    CHECK_NEAR(through_view("", 0.18f), 0.46135612950, 2e-6);
    CHECK_NEAR(through_view("Raw", 7.5f), 7.5, 0.0);

    /* Per channel, not just grey, and non-finite input never comes out. */
    OcioView *v = NULL;
    Diag err = {0};
    CHECK(ocio_view_open("Standard", &v, &err));
    if (v) {
        CHECK_STR(ocio_view_name(v), "Standard");
        CHECK_STR(ocio_view_display(v), "sRGB");
        CHECK_STR(ocio_view_config_source(v), "built-in");
        float px[6] = {0.25f, 0.5f, 1.0f, NAN, INFINITY, -INFINITY};
        ocio_view_apply(v, px, 2);
        CHECK_NEAR(px[0], srgb_reference(0.25), 2e-6);
        CHECK_NEAR(px[1], srgb_reference(0.5), 2e-6);
        CHECK_NEAR(px[2], 1.0, 2e-6);
        CHECK(px[3] == 0.0f && px[4] == 0.0f && px[5] == 0.0f);
        ocio_view_close(v);
    }
}

static void test_filmic_view(void)
{
    /* Monotonic (non-decreasing, and rising over the working range) on a grey ramp from
     * black to far above 1, and highlights that the Standard view clips stay below 1. */
    float prev = through_view("Filmic", 0.0f);
    CHECK(prev >= 0.0f && prev < 0.01f);
    int decreasing = 0;
    for (int k = -80; k <= 80; ++k) {
        float x = powf(2.0f, (float)k / 10.0f); /* 2^-8 .. 2^8 */
        float y = through_view("Filmic", x);
        decreasing += y < prev;
        if (k > -60 && k < 30) decreasing += !(y > prev); /* strictly rising mid-range */
        prev = y;
    }
    CHECK(decreasing == 0);
    float y4 = through_view("Filmic", 4.0f), y10 = through_view("Filmic", 10.0f);
    CHECK(y4 < 1.0f && y10 < 1.0f && y10 > y4);
    CHECK(through_view("Filmic", 1000.0f) <= 1.0f + 1e-6f);
    /* Mid-grey lands in the middle of the display range, not crushed or blown. */
    float mid = through_view("Filmic", 0.18f);
    CHECK(mid > 0.25f && mid < 0.6f);
}

static void test_unknown_view(void)
{
    OcioView *v = NULL;
    Diag err = {0};
    CHECK(!ocio_view_open("Nope", &v, &err));
    CHECK(v == NULL);
    CHECK_STR(err.message, "error: unknown view 'Nope' (display 'sRGB' has views: Standard, Filmic, Raw)");
    CHECK(err.exit_code == 1);
    char list[256];
    CHECK(ocio_list_views(list, sizeof list, &err));
    CHECK_STR(list, "Standard, Filmic, Raw");
}

static const char *test_config =
    "ocio_profile_version: 2\n"
    "roles:\n"
    "  default: linear\n"
    "  scene_linear: linear\n"
    "file_rules:\n"
    "  - !<Rule> {name: Default, colorspace: default}\n"
    "displays:\n"
    "  TestDisplay:\n"
    "    - !<View> {name: Half, colorspace: half}\n"
    "    - !<View> {name: Identity, colorspace: linear}\n"
    "colorspaces:\n"
    "  - !<ColorSpace>\n"
    "    name: linear\n"
    "  - !<ColorSpace>\n"
    "    name: half\n"
    "    from_scene_reference: !<MatrixTransform> {matrix: [0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 1]}\n";

static void test_env_config(void)
{
    char dir[] = "/tmp/wedge_test_ocio_XXXXXX";
    if (!mkdtemp(dir)) return;
    char path[256];
    snprintf(path, sizeof path, "%s/test.ocio", dir);
    FILE *f = fopen(path, "w");
    fputs(test_config, f);
    fclose(f);

    setenv("OCIO", path, 1);
    CHECK_NEAR(through_view("Half", 0.8f), 0.4, 1e-7);
    CHECK_NEAR(through_view(NULL, 0.8f), 0.4, 1e-7); /* first view is the default */
    OcioView *v = NULL;
    Diag err = {0};
    CHECK(!ocio_view_open("Filmic", &v, &err));
    CHECK_STR(err.message, "error: unknown view 'Filmic' (display 'TestDisplay' has views: Half, Identity)");
    CHECK(ocio_view_open("Identity", &v, &err));
    if (v) {
        CHECK_STR(ocio_view_config_source(v), path);
        ocio_view_close(v);
    }

    /* A $OCIO that does not exist: input error naming the file. */
    char missing[300];
    snprintf(missing, sizeof missing, "%s/absent.ocio", dir);
    setenv("OCIO", missing, 1);
    CHECK(!ocio_view_open(NULL, &v, &err));
    CHECK(err.exit_code == 2);
    CHECK(strncmp(err.message, missing, strlen(missing)) == 0);
    CHECK(strstr(err.message, "cannot load OpenColorIO config ($OCIO)") != NULL);

    /* The embedded text is a complete config on its own: through $OCIO it gives the same
     * numbers as the built-in path. */
    f = fopen(path, "w");
    fputs(ocio_embedded_config(), f);
    fclose(f);
    setenv("OCIO", path, 1);
    float via_file = through_view("Filmic", 2.0f), via_file_std = through_view("Standard", 0.18f);
    unsetenv("OCIO");
    CHECK(via_file == through_view("Filmic", 2.0f));
    CHECK(via_file_std == through_view("Standard", 0.18f));

    /* Empty $OCIO means unset. */
    setenv("OCIO", "", 1);
    CHECK_NEAR(through_view("Standard", 0.18f), 0.46135612950, 2e-6);
    unsetenv("OCIO");
    unlink(path);
    rmdir(dir);
}

static void test_write_png(void)
{
    char dir[] = "/tmp/wedge_test_ocio_png_XXXXXX";
    if (!mkdtemp(dir)) return;
    char path[256];
    snprintf(path, sizeof path, "%s/out.png", dir);
    float lin[6] = {0.18f, 0.18f, 0.18f, 5.0f, 5.0f, 5.0f};
    Diag err = {0};
    CHECK(ocio_write_png(path, 2, 1, lin, "Standard", &err));
    int w, h, c;
    float *px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    /* 0.46136 * 255 = 117.6 -> code 118; 5.0 clips to 255 in the Standard view. */
    CHECK(px && px[0] == 118.0f / 255.0f && px[3] == 1.0f);
    free(px);
    CHECK(ocio_write_png(path, 2, 1, lin, "Filmic", &err));
    px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    CHECK(px && px[3] < 1.0f); /* the filmic shoulder keeps 5.0 below white */
    free(px);
    CHECK(!ocio_write_png(path, 2, 1, lin, "Bogus", &err));
    CHECK(err.exit_code == 1);
    unlink(path);
    rmdir(dir);
}

int main(void)
{
    unsetenv("OCIO"); /* the built-in config unless a test sets one */
    test_standard_view();
    test_filmic_view();
    test_unknown_view();
    test_env_config();
    test_write_png();
    CHECK_DONE();
}
