/* imagemap texture: encodings, bilinear lookups of a 2x2 image at known points under each
 * wrap mode, the (u, v) mapping and its vertical flip, scale / invert, and loading PNG
 * (sRGB by default) and EXR (always linear) files. */
#include <stdlib.h>
#include <unistd.h>

#include "check.h"
#include "io/image_io.h"
#include "render/image_texture.h"

#define CHECK_V3(c, ex, ey, ez, tol)   \
    do {                               \
        vec3 cv_ = (c);                \
        CHECK_NEAR(cv_.x, (ex), (tol)); \
        CHECK_NEAR(cv_.y, (ey), (tol)); \
        CHECK_NEAR(cv_.z, (ez), (tol)); \
    } while (0)

static double srgb_to_linear_ref(double v) { return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4); }

int main(void)
{
    /* ---- encodings ---- */
    TexEncoding e;
    CHECK(tex_encoding_parse("sRGB", &e) && e.kind == TEX_ENCODING_SRGB);
    CHECK_NEAR(tex_encoding_to_linear(e, 0.5f), 0.2140, 1e-4); /* the standard value */
    CHECK_NEAR(tex_encoding_to_linear(e, 0.02f), 0.02 / 12.92, 1e-7); /* linear toe */
    CHECK_NEAR(tex_encoding_to_linear(e, 1.0f), 1.0, 1e-6);
    CHECK_NEAR(tex_encoding_to_linear(e, 0.0f), 0.0, 0);
    /* the two pieces meet (continuity at the threshold) */
    CHECK_NEAR(tex_encoding_to_linear(e, 0.04045f), tex_encoding_to_linear(e, 0.04046f), 1e-5);
    CHECK(tex_encoding_parse("linear", &e) && e.kind == TEX_ENCODING_LINEAR);
    CHECK(tex_encoding_to_linear(e, 0.37f) == 0.37f);
    CHECK(tex_encoding_parse("gamma 2.2", &e) && e.kind == TEX_ENCODING_GAMMA);
    CHECK_NEAR(tex_encoding_to_linear(e, 0.5f), pow(0.5, 2.2), 1e-6);
    CHECK(!tex_encoding_parse("gamma", &e));
    CHECK(!tex_encoding_parse("gamma -1", &e));
    CHECK(!tex_encoding_parse("gamma 2 x", &e));
    CHECK(!tex_encoding_parse("srgb", &e)); /* pbrt-v4 names are case-sensitive */
    TexWrap w;
    CHECK(tex_wrap_parse("clamp", &w) && w == TEX_WRAP_CLAMP);
    CHECK(tex_wrap_parse("black", &w) && w == TEX_WRAP_BLACK);
    CHECK(tex_wrap_parse("repeat", &w) && w == TEX_WRAP_REPEAT);
    CHECK(!tex_wrap_parse("octahedralsphere", &w));

    /* ---- 2x2 image: top row a b, bottom row c d (one channel, grey) ---- */
    const float a = 0.1f, b = 0.3f, c = 0.5f, d = 0.9f;
    float px[4] = {a, b, c, d};
    ImageTexture t;
    Diag err = {0};
    TexEncoding lin = {TEX_ENCODING_LINEAR, 1.0f};
    CHECK(image_texture_init(&t, 2, 2, 1, px, lin, &err));
    t.wrap = TEX_WRAP_CLAMP;
    /* texel centres are exact */
    CHECK_NEAR(image_texture_lookup(&t, v2(0.25f, 0.25f)).x, a, 1e-6);
    CHECK_NEAR(image_texture_lookup(&t, v2(0.75f, 0.25f)).y, b, 1e-6);
    CHECK_NEAR(image_texture_lookup(&t, v2(0.25f, 0.75f)).z, c, 1e-6);
    CHECK_NEAR(image_texture_lookup(&t, v2(0.75f, 0.75f)).x, d, 1e-6);
    /* bilinear weights */
    CHECK_NEAR(image_texture_lookup(&t, v2(0.5f, 0.5f)).x, (a + b + c + d) / 4, 1e-6);
    CHECK_NEAR(image_texture_lookup(&t, v2(0.375f, 0.25f)).x, 0.75 * a + 0.25 * b, 1e-6);
    CHECK_NEAR(image_texture_lookup(&t, v2(0.5f, 0.625f)).x, 0.25 * (a + b) / 2 + 0.75 * (c + d) / 2, 1e-6);
    /* wrap modes at the corner (0,0): half a texel outside in both axes */
    CHECK_NEAR(image_texture_lookup(&t, v2(0.0f, 0.0f)).x, a, 1e-6);
    t.wrap = TEX_WRAP_REPEAT;
    CHECK_NEAR(image_texture_lookup(&t, v2(0.0f, 0.0f)).x, (a + b + c + d) / 4, 1e-6);
    CHECK_NEAR(image_texture_lookup(&t, v2(1.25f, -0.75f)).x, a, 1e-6); /* periodic */
    t.wrap = TEX_WRAP_BLACK;
    CHECK_NEAR(image_texture_lookup(&t, v2(0.0f, 0.0f)).x, a / 4, 1e-6);
    CHECK_NEAR(image_texture_lookup(&t, v2(3.0f, 0.5f)).x, 0.0, 0);
    t.nearest = true;
    CHECK_NEAR(image_texture_lookup(&t, v2(0.49f, 0.51f)).x, c, 0);
    t.nearest = false;
    t.wrap = TEX_WRAP_CLAMP;

    /* ---- mapping: v = 0 is the bottom row of the image ---- */
    CHECK_NEAR(image_texture_eval(&t, v2(0.25f, 0.75f)).x, a, 1e-6);
    CHECK_NEAR(image_texture_eval(&t, v2(0.25f, 0.25f)).x, c, 1e-6);
    t.uscale = 2.0f, t.udelta = 0.25f; /* s = 2u + 0.25 */
    CHECK_NEAR(image_texture_eval(&t, v2(0.25f, 0.25f)).x, d, 1e-6); /* s = 0.75 */
    t.uscale = 1.0f, t.udelta = 0.0f;
    t.vscale = 0.5f, t.vdelta = 0.5f; /* t = 1 - (0.5 v + 0.5) */
    CHECK_NEAR(image_texture_eval(&t, v2(0.75f, 0.5f)).x, b, 1e-6); /* t = 0.25 */
    t.vscale = 1.0f, t.vdelta = 0.0f;
    t.scale = 2.0f;
    CHECK_NEAR(image_texture_eval(&t, v2(0.25f, 0.75f)).x, 2 * a, 1e-6);
    t.invert = true; /* 1 - scale * value, clamped at 0 */
    CHECK_NEAR(image_texture_eval(&t, v2(0.25f, 0.75f)).x, 1 - 2 * a, 1e-6);
    CHECK_NEAR(image_texture_eval(&t, v2(0.75f, 0.25f)).x, 0.0, 0); /* 1 - 1.8 < 0 */
    CHECK_NEAR(image_texture_eval_float(&t, v2(0.25f, 0.75f)), 1 - 2 * a, 1e-6);
    /* no NaN from non-finite uv */
    vec3 nan_uv = image_texture_eval(&t, v2(NAN, INFINITY));
    CHECK(isfinite(nan_uv.x) && isfinite(nan_uv.y) && isfinite(nan_uv.z));
    image_texture_free(&t);

    /* rgb with sRGB decoding at init; rgba ignores alpha */
    float rgba[8] = {0.5f, 0.0f, 1.0f, 0.2f, 0.25f, 0.75f, 0.04f, 1.0f};
    TexEncoding srgb = {TEX_ENCODING_SRGB, 1.0f};
    CHECK(image_texture_init(&t, 2, 1, 4, rgba, srgb, &err));
    t.wrap = TEX_WRAP_CLAMP;
    CHECK_V3(image_texture_lookup(&t, v2(0.25f, 0.5f)), srgb_to_linear_ref(0.5), 0.0, 1.0, 1e-6);
    CHECK_V3(image_texture_lookup(&t, v2(0.75f, 0.5f)), srgb_to_linear_ref(0.25), srgb_to_linear_ref(0.75),
             srgb_to_linear_ref(0.04), 1e-6);
    image_texture_free(&t);
    CHECK(!image_texture_init(&t, 0, 2, 3, rgba, lin, &err));
    CHECK(!image_texture_init(&t, 2, 2, 2, rgba, lin, &err));

    /* ---- files ---- */
    const char *dir = getenv("WEDGE_BUILD_DIR");
    char png_path[1024], exr_path[1024];
    snprintf(png_path, sizeof png_path, "%s/materials_tex_%d.png", dir ? dir : "/tmp", (int)getpid());
    snprintf(exr_path, sizeof exr_path, "%s/materials_tex_%d.exr", dir ? dir : "/tmp", (int)getpid());
    /* 8-bit codes that are exact: k / 255 */
    float disp[6] = {128 / 255.0f, 64 / 255.0f, 255 / 255.0f, 0.0f, 200 / 255.0f, 10 / 255.0f};
    CHECK(png_write_display(png_path, 2, 1, disp, &err));
    CHECK(image_texture_load(&t, png_path, NULL, &err)); /* default for PNG: sRGB */
    t.wrap = TEX_WRAP_CLAMP;
    CHECK_V3(image_texture_lookup(&t, v2(0.25f, 0.5f)), srgb_to_linear_ref(128 / 255.0), srgb_to_linear_ref(64 / 255.0),
             1.0, 1e-5);
    image_texture_free(&t);
    CHECK(image_texture_load(&t, png_path, "linear", &err));
    t.wrap = TEX_WRAP_CLAMP;
    CHECK_V3(image_texture_lookup(&t, v2(0.75f, 0.5f)), 0.0, 200 / 255.0, 10 / 255.0, 1e-6);
    image_texture_free(&t);
    CHECK(image_texture_load(&t, png_path, "gamma 2", &err));
    t.wrap = TEX_WRAP_CLAMP;
    CHECK_NEAR(image_texture_lookup(&t, v2(0.75f, 0.5f)).y, pow(200 / 255.0, 2.0), 1e-6);
    image_texture_free(&t);
    CHECK(!image_texture_load(&t, png_path, "gamma zero", &err));
    CHECK(strstr(err.message, "unknown texture encoding 'gamma zero'") != NULL);
    unlink(png_path);

    float hdr[6] = {0.5f, 2.0f, 7.25f, 0.0f, 0.125f, 1.0f};
    ExrChannel ch[3] = {{"R", hdr + 0, 3}, {"G", hdr + 1, 3}, {"B", hdr + 2, 3}};
    CHECK(exr_write(exr_path, 2, 1, ch, 3, NULL, 0, &err));
    CHECK(image_texture_load(&t, exr_path, "sRGB", &err)); /* EXR: encoding not applied */
    t.wrap = TEX_WRAP_CLAMP;
    CHECK_V3(image_texture_lookup(&t, v2(0.25f, 0.5f)), 0.5, 2.0, 7.25, 1e-6);
    CHECK_V3(image_texture_lookup(&t, v2(0.5f, 0.5f)), 0.25, 1.0625, 4.125, 1e-6);
    image_texture_free(&t);
    unlink(exr_path);

    CHECK(!image_texture_load(&t, "/nonexistent/wedge_no_such_texture.png", NULL, &err));
    CHECK(err.exit_code == WEDGE_EXIT_INPUT);
    CHECK_DONE();
}
