/* Texture reading with pbrt-v4's encoding rules: PNG codes decoded by sRGB / linear /
 * gamma, EXR linear whatever the encoding, alpha never decoded, bad encodings rejected. */
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "io/image_io.h"

static double srgb_to_linear(double v) /* IEC 61966-2-1 decoding */
{
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

int main(void)
{
    char dir[] = "/tmp/wedge_test_texture_XXXXXX";
    if (!mkdtemp(dir)) return 1;
    char png_path[256], exr_path[256];
    snprintf(png_path, sizeof png_path, "%s/t.png", dir);
    snprintf(exr_path, sizeof exr_path, "%s/t.exr", dir);

    /* RGBA PNG: one pixel with codes (128, 64, 255, 128). */
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    im.width = 1;
    im.height = 1;
    im.format = PNG_FORMAT_RGBA;
    png_byte codes[4] = {128, 64, 255, 128};
    CHECK(png_image_write_to_file(&im, png_path, 0, codes, 0, NULL));

    Diag err = {0};
    int w, h, c;
    float *px = NULL;
    CHECK(image_read_texture(png_path, NULL, &w, &h, &c, &px, &err)); /* default: sRGB */
    CHECK(w == 1 && h == 1 && c == 4);
    if (px) {
        CHECK_NEAR(px[0], srgb_to_linear(128 / 255.0), 1e-6);
        CHECK_NEAR(px[1], srgb_to_linear(64 / 255.0), 1e-6);
        CHECK_NEAR(px[2], 1.0, 1e-6);
        CHECK(px[3] == 128 / 255.0f); /* alpha untouched */
    }
    free(px);
    px = NULL;
    CHECK(image_read_texture(png_path, "linear", &w, &h, &c, &px, &err));
    CHECK(px && px[0] == 128 / 255.0f && px[1] == 64 / 255.0f && px[3] == 128 / 255.0f);
    free(px);
    px = NULL;
    CHECK(image_read_texture(png_path, "gamma 2.2", &w, &h, &c, &px, &err));
    CHECK(px && fabs(px[0] - pow(128 / 255.0, 2.2)) < 1e-6 && px[3] == 128 / 255.0f);
    free(px);

    px = NULL;
    CHECK(!image_read_texture(png_path, "gamma", &w, &h, &c, &px, &err));
    char expect[512];
    snprintf(expect, sizeof expect,
             "%s: error: unknown encoding 'gamma' (expected \"sRGB\", \"linear\" or \"gamma G\")", png_path);
    CHECK_STR(err.message, expect);
    CHECK(err.exit_code == 2);
    CHECK(!image_read_texture(png_path, "gamma -1", &w, &h, &c, &px, &err));
    CHECK(!image_read_texture(png_path, "srgb", &w, &h, &c, &px, &err)); /* pbrt spells it sRGB */

    /* EXR: linear values as stored, whatever the encoding says; alpha when present. */
    float rgb[6] = {0.25f, 2.0f, 0.5f, 0.125f, 0.0f, 7.0f}, alpha[2] = {1.0f, 0.5f};
    ExrChannel ch[] = {{"R", rgb, 3}, {"G", rgb + 1, 3}, {"B", rgb + 2, 3}, {"A", alpha, 1}};
    CHECK(exr_write(exr_path, 2, 1, ch, 4, NULL, 0, &err));
    px = NULL;
    CHECK(image_read_texture(exr_path, "sRGB", &w, &h, &c, &px, &err));
    CHECK(w == 2 && h == 1 && c == 4);
    if (px) {
        const float expect_px[8] = {0.25f, 2.0f, 0.5f, 1.0f, 0.125f, 0.0f, 7.0f, 0.5f};
        for (int i = 0; i < 8; ++i) CHECK(px[i] == expect_px[i]);
    }
    free(px);
    CHECK(exr_write(exr_path, 2, 1, ch, 3, NULL, 0, &err)); /* no alpha */
    px = NULL;
    CHECK(image_read_texture(exr_path, "gamma 2.2", &w, &h, &c, &px, &err));
    CHECK(c == 3 && px && px[1] == 2.0f && px[5] == 7.0f);
    free(px);

    unlink(png_path);
    unlink(exr_path);
    rmdir(dir);
    CHECK_DONE();
}
