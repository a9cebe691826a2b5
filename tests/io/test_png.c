/* PNG writer/reader: round trips within 8-bit quantisation, clamping, every layout the
 * reader must expand (grey, grey+alpha, palette with and without transparency, 16-bit,
 * RGBA), and errors. Input files of the odd layouts are made here with libpng's
 * simplified API, independently of the code under test. */
#include <dirent.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "core/image_metrics.h"
#include "io/image_io.h"

static char tmpdir[256];

static void tmp_path(char *buf, size_t size, const char *name)
{
    if (snprintf(buf, size, "%s/%s", tmpdir, name) >= (int)size) abort();
}

static bool write_raw_png(const char *path, int w, int h, png_uint_32 format, const void *data,
                          const void *colormap, int colormap_entries)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = (png_uint_32)w;
    img.height = (png_uint_32)h;
    img.format = format;
    img.colormap_entries = (png_uint_32)colormap_entries;
    /* convert_to_8_bit 0: 16-bit data is stored as 16-bit codes. */
    return png_image_write_to_file(&img, path, 0, data, 0, colormap) != 0;
}

static void test_srgb_round_trip(void)
{
    /* Linear values spread over [0, 1] plus out-of-range ones that must clamp. */
    enum { W = 7, H = 5 };
    float lin[W * H * 3];
    for (int i = 0; i < W * H * 3; ++i) lin[i] = (float)i / (float)(W * H * 3 - 1);
    lin[0] = -0.5f;     /* clamps to 0 */
    lin[1] = 7.0f;      /* clamps to 1 */
    lin[2] = NAN;       /* written as 0 */
    lin[3] = INFINITY;  /* non-finite: 0, not 1 */
    char path[512];
    tmp_path(path, sizeof path, "srgb.png");
    Diag err = {0};
    CHECK(png_write_srgb(path, W, H, lin, &err));
    int w = 0, h = 0, c = 0;
    float *px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    CHECK(w == W && h == H && c == 3);
    if (px) {
        CHECK(px[0] == 0.0f && px[1] == 1.0f && px[2] == 0.0f && px[3] == 0.0f);
        /* Within half a code of the exact sRGB encoding of the clamped value. */
        int bad = 0;
        for (int i = 4; i < W * H * 3; ++i) bad += fabs(px[i] - srgb_encode(lin[i])) > 0.5 / 255 + 1e-6;
        CHECK(bad == 0);
        /* Two known codes: linear 0.18 encodes to 0.46135 -> code 118 (117.64 rounds up). */
    }
    free(px);

    float grey18[3] = {0.18f, 0.18f, 0.18f};
    CHECK(png_write_srgb(path, 1, 1, grey18, &err));
    px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    CHECK(px && px[0] == 118.0f / 255.0f);
    free(px);

    /* png_write_display stores k/255 exactly. */
    float disp[256 * 3];
    for (int i = 0; i < 256 * 3; ++i) disp[i] = (float)(i / 3) / 255.0f;
    CHECK(png_write_display(path, 16, 16, disp, &err));
    px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    if (px)
        for (int i = 0; i < 256 * 3; ++i) CHECK(px[i] == disp[i]);
    free(px);

    /* And image_read_linear_rgb undoes the curve: within the quantisation step. */
    float *back = NULL;
    CHECK(png_write_srgb(path, 1, 1, grey18, &err));
    CHECK(image_read_linear_rgb(path, &w, &h, &back, &err));
    CHECK(back && fabs(back[0] - 0.18) < 0.002);
    free(back);
    unlink(path);
}

static void test_layouts(void)
{
    char path[512];
    tmp_path(path, sizeof path, "layout.png");
    Diag err = {0};
    int w, h, c;
    float *px = NULL;

    /* 8-bit grey: expanded to RGB. */
    png_byte grey[4] = {0, 51, 204, 255};
    CHECK(write_raw_png(path, 2, 2, PNG_FORMAT_GRAY, grey, NULL, 0));
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    CHECK(w == 2 && h == 2 && c == 3);
    if (px)
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 3; ++k) CHECK(px[3 * i + k] == grey[i] / 255.0f);
    free(px);

    /* Grey + alpha: RGBA. */
    png_byte ga[4] = {10, 20, 30, 40};
    CHECK(write_raw_png(path, 2, 1, PNG_FORMAT_GA, ga, NULL, 0));
    px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    CHECK(w == 2 && h == 1 && c == 4);
    if (px) {
        CHECK(px[0] == 10 / 255.0f && px[1] == 10 / 255.0f && px[2] == 10 / 255.0f && px[3] == 20 / 255.0f);
        CHECK(px[4] == 30 / 255.0f && px[7] == 40 / 255.0f);
    }
    free(px);

    /* 16-bit RGB: code / 65535, full precision kept (no sRGB/gamma interpretation). */
    png_uint_16 rgb16[6] = {0, 1, 32768, 65535, 12345, 54321};
    CHECK(write_raw_png(path, 2, 1, PNG_FORMAT_RGB | PNG_FORMAT_FLAG_LINEAR, rgb16, NULL, 0));
    px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    CHECK(c == 3);
    if (px)
        for (int i = 0; i < 6; ++i) CHECK(px[i] == rgb16[i] / 65535.0f);
    free(px);

    /* RGBA 8-bit. */
    png_byte rgba[8] = {1, 2, 3, 4, 250, 251, 252, 253};
    CHECK(write_raw_png(path, 2, 1, PNG_FORMAT_RGBA, rgba, NULL, 0));
    px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    CHECK(c == 4);
    if (px)
        for (int i = 0; i < 8; ++i) CHECK(px[i] == rgba[i] / 255.0f);
    free(px);

    /* Palette (opaque): indices expanded to their colours. */
    png_byte map[3 * 3] = {255, 0, 0, 0, 128, 0, 7, 8, 9};
    png_byte idx[4] = {2, 0, 1, 2};
    CHECK(write_raw_png(path, 4, 1, PNG_FORMAT_RGB | PNG_FORMAT_FLAG_COLORMAP, idx, map, 3));
    px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    CHECK(w == 4 && c == 3);
    if (px)
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 3; ++k) CHECK(px[3 * i + k] == map[3 * idx[i] + k] / 255.0f);
    free(px);

    /* Palette with transparency: RGBA. */
    png_byte map_a[2 * 4] = {255, 255, 255, 0, 10, 20, 30, 255};
    png_byte idx_a[2] = {1, 0};
    CHECK(write_raw_png(path, 2, 1, PNG_FORMAT_RGBA | PNG_FORMAT_FLAG_COLORMAP, idx_a, map_a, 2));
    px = NULL;
    CHECK(png_read(path, &w, &h, &c, &px, &err));
    CHECK(c == 4);
    if (px) {
        CHECK(px[0] == 10 / 255.0f && px[1] == 20 / 255.0f && px[2] == 30 / 255.0f && px[3] == 1.0f);
        CHECK(px[7] == 0.0f);
    }
    free(px);
    unlink(path);
}

static void test_errors(void)
{
    char path[512];
    Diag err = {0};
    int w, h, c;
    float *px = NULL;
    tmp_path(path, sizeof path, "absent.png");
    CHECK(!png_read(path, &w, &h, &c, &px, &err));
    char expect[1024];
    snprintf(expect, sizeof expect, "%s: error: cannot open: No such file or directory", path);
    CHECK_STR(err.message, expect);
    CHECK(err.exit_code == 2);

    tmp_path(path, sizeof path, "text.png");
    FILE *f = fopen(path, "w");
    fputs("definitely not a png file", f);
    fclose(f);
    CHECK(!png_read(path, &w, &h, &c, &px, &err));
    snprintf(expect, sizeof expect, "%s: error: not a PNG file", path);
    CHECK_STR(err.message, expect);

    /* Truncated: valid signature and header, data cut off. */
    float lin[64 * 64 * 3];
    for (int i = 0; i < 64 * 64 * 3; ++i) lin[i] = (float)((i * 7919) % 1000) / 1000.0f;
    tmp_path(path, sizeof path, "trunc.png");
    CHECK(png_write_srgb(path, 64, 64, lin, &err));
    CHECK(truncate(path, 100) == 0);
    CHECK(!png_read(path, &w, &h, &c, &px, &err));
    CHECK(err.exit_code == 2 && strstr(err.message, "cannot read PNG") != NULL);
    CHECK(px == NULL);
    unlink(path);
    tmp_path(path, sizeof path, "text.png");
    unlink(path);

    CHECK(path_is_png("a.png") && path_is_png("B.PNG") && !path_is_png("a.exr") && !path_is_png("png"));

    /* Missing folder: error, no file anywhere. */
    tmp_path(path, sizeof path, "nope/out.png");
    CHECK(!png_write_srgb(path, 1, 1, lin, &err));
    CHECK(err.exit_code == 3);
    DIR *d = opendir(tmpdir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d))) n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    if (d) closedir(d);
    CHECK(n == 0);
}

int main(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/wedge_test_png_XXXXXX");
    if (!mkdtemp(tmpdir)) return 1;
    test_srgb_round_trip();
    test_layouts();
    test_errors();
    rmdir(tmpdir);
    CHECK_DONE();
}
