/* 8-bit PNG output and 8/16-bit PNG input through libpng.
 *
 * Writing uses libpng's simplified API into memory, then one atomic write (temporary file
 * + rename, io/atomic_file.h). Reading uses the classic API because it can hand us raw
 * code values: the simplified API would reinterpret 16-bit data as linear light. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <png.h>

#include "core/image_metrics.h"
#include "io/atomic_file.h"
#include "io/image_io.h"

bool path_is_png(const char *path)
{
    size_t n = path ? strlen(path) : 0;
    return n >= 4 && !strcasecmp(path + n - 4, ".png");
}

/* Display value in [0,1] to an 8-bit code; non-finite values become 0 (black). */
static png_byte to_code8(float v)
{
    if (!isfinite(v) || v <= 0.0f) return 0;
    if (v >= 1.0f) return 255;
    return (png_byte)lrintf(v * 255.0f);
}

static bool write_codes(const char *path, int width, int height, const png_byte *codes, Diag *err)
{
    SrcLoc loc = {path, 0, 0};
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = (png_uint_32)width;
    image.height = (png_uint_32)height;
    image.format = PNG_FORMAT_RGB;
    /* First call sizes the buffer, second fills it. */
    png_alloc_size_t size = 0;
    if (!png_image_write_to_memory(&image, NULL, &size, 0, codes, 0, NULL)) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot encode PNG: %s", image.message);
        png_image_free(&image);
        return false;
    }
    void *buffer = malloc(size);
    if (!buffer) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        return false;
    }
    if (!png_image_write_to_memory(&image, buffer, &size, 0, codes, 0, NULL)) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot encode PNG: %s", image.message);
        png_image_free(&image);
        free(buffer);
        return false;
    }
    AtomicFile af;
    if (!atomic_file_open(&af, path, err)) {
        free(buffer);
        return false;
    }
    if (!atomic_file_pwrite(&af, buffer, size, 0)) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "write failed: %s", strerror(errno));
        atomic_file_abort(&af);
        free(buffer);
        return false;
    }
    free(buffer);
    return atomic_file_commit(&af, err);
}

static bool write_mapped(const char *path, int width, int height, const float *rgb, bool encode, Diag *err)
{
    SrcLoc loc = {path, 0, 0};
    if (width <= 0 || height <= 0 || (long long)width * height > (1LL << 28)) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot write a %dx%d image", width, height);
        return false;
    }
    size_t n = (size_t)width * (size_t)height * 3;
    png_byte *codes = malloc(n);
    if (!codes) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        return false;
    }
    for (size_t i = 0; i < n; ++i) {
        float v = rgb[i];
        if (!isfinite(v)) v = 0.0f;
        v = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v; /* clamp before the curve */
        codes[i] = to_code8(encode ? srgb_encode(v) : v);
    }
    bool ok = write_codes(path, width, height, codes, err);
    free(codes);
    return ok;
}

bool png_write_srgb(const char *path, int width, int height, const float *rgb_linear, Diag *err)
{
    return write_mapped(path, width, height, rgb_linear, true, err);
}

bool png_write_display(const char *path, int width, int height, const float *rgb_display, Diag *err)
{
    return write_mapped(path, width, height, rgb_display, false, err);
}

/* ------------------------------------------------------------------ reading */

typedef struct {
    char message[256];
} PngErrorState;

static void on_png_error(png_structp png, png_const_charp msg)
{
    PngErrorState *st = png_get_error_ptr(png);
    snprintf(st->message, sizeof st->message, "%s", msg);
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* warnings (e.g. a bad iCCP chunk) do not stop the read */
}

/* The setjmp below may clobber locals: keep everything that must survive in here. */
typedef struct {
    FILE *file;
    png_structp png;
    png_infop info;
    png_bytep raw;
    png_bytepp rows;
    float *pixels;
} PngReadState;

static void release_read(PngReadState *s)
{
    if (s->png) png_destroy_read_struct(&s->png, s->info ? &s->info : NULL, NULL);
    if (s->file) fclose(s->file);
    free(s->raw);
    free(s->rows);
    free(s->pixels);
}

bool png_read(const char *path, int *width, int *height, int *channels, float **pixels, Diag *err)
{
    SrcLoc loc = {path, 0, 0};
    PngErrorState est = {{0}};
    PngReadState *s = calloc(1, sizeof *s);
    if (!s) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        return false;
    }
    s->file = fopen(path, "rb");
    if (!s->file) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "cannot open: %s", strerror(errno));
        free(s);
        return false;
    }
    png_byte sig[8];
    if (fread(sig, 1, 8, s->file) != 8 || png_sig_cmp(sig, 0, 8) != 0) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "not a PNG file");
        release_read(s);
        free(s);
        return false;
    }
    s->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &est, on_png_error, on_png_warning);
    if (s->png) s->info = png_create_info_struct(s->png);
    if (!s->png || !s->info) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        release_read(s);
        free(s);
        return false;
    }
    if (setjmp(png_jmpbuf(s->png))) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "cannot read PNG: %s", est.message);
        release_read(s);
        free(s);
        return false;
    }
    png_init_io(s->png, s->file);
    png_set_sig_bytes(s->png, 8);
    png_set_user_limits(s->png, 1u << 16, 1u << 16);
    png_read_info(s->png, s->info);
    png_uint_32 w = png_get_image_width(s->png, s->info), h = png_get_image_height(s->png, s->info);
    int color = png_get_color_type(s->png, s->info);
    int depth = png_get_bit_depth(s->png, s->info);
    bool has_alpha = (color & PNG_COLOR_MASK_ALPHA) || png_get_valid(s->png, s->info, PNG_INFO_tRNS);
    if ((unsigned long long)w * h > (1ULL << 28)) png_error(s->png, "image too large");

    /* Normalise every layout to 8- or 16-bit RGB(A) code values, no gamma handling. */
    if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(s->png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(s->png);
    if (png_get_valid(s->png, s->info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(s->png);
    if (color == PNG_COLOR_TYPE_GRAY || color == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(s->png);
    if (depth == 16) png_set_swap(s->png); /* file is big-endian; read host order */
    png_set_interlace_handling(s->png);
    png_read_update_info(s->png, s->info);

    int out_channels = png_get_channels(s->png, s->info);
    int out_depth = png_get_bit_depth(s->png, s->info);
    size_t rowbytes = png_get_rowbytes(s->png, s->info);
    if ((out_channels != 3 && out_channels != 4) || (out_depth != 8 && out_depth != 16) ||
        rowbytes != (size_t)w * (size_t)out_channels * (size_t)(out_depth / 8) ||
        (out_channels == 4) != has_alpha)
        png_error(s->png, "unexpected pixel layout after expansion");
    s->raw = malloc(rowbytes * h);
    s->rows = malloc(sizeof *s->rows * h);
    s->pixels = malloc(sizeof *s->pixels * (size_t)w * h * (size_t)out_channels);
    if (!s->raw || !s->rows || !s->pixels) png_error(s->png, "out of memory");
    for (png_uint_32 y = 0; y < h; ++y) s->rows[y] = s->raw + rowbytes * y;
    png_read_image(s->png, s->rows);
    png_read_end(s->png, NULL);

    size_t n = (size_t)w * h * (size_t)out_channels;
    if (out_depth == 8) {
        for (size_t i = 0; i < n; ++i) s->pixels[i] = (float)s->raw[i] / 255.0f;
    } else {
        const png_uint_16 *v = (const png_uint_16 *)(void *)s->raw;
        for (size_t i = 0; i < n; ++i) s->pixels[i] = (float)v[i] / 65535.0f;
    }
    *width = (int)w;
    *height = (int)h;
    *channels = out_channels;
    *pixels = s->pixels;
    s->pixels = NULL;
    release_read(s);
    free(s);
    return true;
}

/* ------------------------------------------------------------------ either format */

bool image_read_linear_rgb(const char *path, int *width, int *height, float **rgb, Diag *err)
{
    if (!path_is_png(path)) return exr_read_rgb(path, width, height, rgb, err);
    int channels = 0;
    float *px = NULL;
    if (!png_read(path, width, height, &channels, &px, err)) return false;
    size_t n = (size_t)*width * (size_t)*height;
    float *out = malloc(n * 3 * sizeof *out);
    if (!out) {
        free(px);
        SrcLoc loc = {path, 0, 0};
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        return false;
    }
    /* A PNG holds display-encoded values: undo the sRGB curve to compare in linear light. */
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) out[3 * i + (size_t)c] = srgb_decode(px[(size_t)channels * i + (size_t)c]);
    free(px);
    *rgb = out;
    return true;
}
