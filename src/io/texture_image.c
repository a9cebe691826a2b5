/* Reading texture images with pbrt-v4's colour-encoding rules (see io/image_io.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/image_metrics.h"
#include "io/image_io.h"

typedef enum { ENC_SRGB, ENC_LINEAR, ENC_GAMMA } Encoding;

/* Parses "sRGB", "linear" or "gamma G" (G > 0) as pbrt-v4 spells them. */
static bool parse_encoding(const char *text, Encoding *enc, double *gamma)
{
    if (!text || !strcmp(text, "sRGB")) {
        *enc = ENC_SRGB;
        return true;
    }
    if (!strcmp(text, "linear")) {
        *enc = ENC_LINEAR;
        return true;
    }
    if (!strncmp(text, "gamma ", 6)) {
        char *end = NULL;
        double g = strtod(text + 6, &end);
        while (end && *end == ' ') ++end;
        if (end && end != text + 6 && *end == '\0' && isfinite(g) && g > 0.0) {
            *enc = ENC_GAMMA;
            *gamma = g;
            return true;
        }
    }
    return false;
}

static bool read_exr_texture(const char *path, int *width, int *height, int *channels, float **pixels, Diag *err)
{
    float *rgb = NULL;
    if (!exr_read_rgb(path, width, height, &rgb, err)) return false;
    /* Alpha is optional: read it only if the file has one. */
    ExrImage img;
    if (!exr_read(path, &img, err)) {
        free(rgb);
        return false;
    }
    const float *alpha = exr_image_channel(&img, "A");
    size_t n = (size_t)*width * (size_t)*height;
    if (!alpha) {
        exr_image_free(&img);
        *channels = 3;
        *pixels = rgb;
        return true;
    }
    float *rgba = malloc(n * 4 * sizeof *rgba);
    if (!rgba) {
        SrcLoc loc = {path, 0, 0};
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        free(rgb);
        exr_image_free(&img);
        return false;
    }
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) rgba[4 * i + (size_t)c] = rgb[3 * i + (size_t)c];
        rgba[4 * i + 3] = alpha[i];
    }
    free(rgb);
    exr_image_free(&img);
    *channels = 4;
    *pixels = rgba;
    return true;
}

bool image_read_texture(const char *path, const char *encoding, int *width, int *height, int *channels,
                        float **pixels, Diag *err)
{
    Encoding enc = ENC_SRGB;
    double gamma = 1.0;
    if (!parse_encoding(encoding, &enc, &gamma)) {
        SrcLoc loc = {path, 0, 0};
        diag_set(err, WEDGE_EXIT_INPUT, loc, "unknown encoding '%s' (expected \"sRGB\", \"linear\" or \"gamma G\")",
                 encoding);
        return false;
    }
    if (!path_is_png(path)) return read_exr_texture(path, width, height, channels, pixels, err);
    if (!png_read(path, width, height, channels, pixels, err)) return false;
    size_t n = (size_t)*width * (size_t)*height;
    int nc = *channels;
    float *px = *pixels;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            float *v = &px[(size_t)nc * i + (size_t)c];
            if (enc == ENC_SRGB)
                *v = srgb_decode(*v);
            else if (enc == ENC_GAMMA)
                *v = (float)pow((double)*v, gamma);
        }
    return true;
}
