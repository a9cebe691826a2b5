/* pbrt-v4 imagemap texture; see image_texture.h. */
#include "render/image_texture.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io/image_io.h"

bool tex_encoding_parse(const char *s, TexEncoding *enc)
{
    if (!s) return false;
    if (!strcmp(s, "sRGB")) {
        *enc = (TexEncoding){TEX_ENCODING_SRGB, 1.0f};
        return true;
    }
    if (!strcmp(s, "linear")) {
        *enc = (TexEncoding){TEX_ENCODING_LINEAR, 1.0f};
        return true;
    }
    if (!strncmp(s, "gamma ", 6)) {
        char *end = NULL;
        float g = strtof(s + 6, &end);
        while (end && *end == ' ') ++end;
        if (end == s + 6 || (end && *end) || !(g > 0.0f) || !isfinite(g)) return false;
        *enc = (TexEncoding){TEX_ENCODING_GAMMA, g};
        return true;
    }
    return false;
}

float tex_encoding_to_linear(TexEncoding enc, float v)
{
    switch (enc.kind) {
    case TEX_ENCODING_LINEAR: return v;
    case TEX_ENCODING_SRGB:
        /* IEC 61966-2-1: linear toe below 0.04045, a 2.4 power curve above */
        if (v <= 0.04045f) return v / 12.92f;
        return powf((v + 0.055f) / 1.055f, 2.4f);
    case TEX_ENCODING_GAMMA: return v > 0.0f ? powf(v, enc.gamma) : 0.0f;
    }
    return v;
}

bool tex_wrap_parse(const char *s, TexWrap *wrap)
{
    if (!s) return false;
    if (!strcmp(s, "repeat")) *wrap = TEX_WRAP_REPEAT;
    else if (!strcmp(s, "clamp")) *wrap = TEX_WRAP_CLAMP;
    else if (!strcmp(s, "black")) *wrap = TEX_WRAP_BLACK;
    else return false;
    return true;
}

bool image_texture_init(ImageTexture *t, int width, int height, int channels, const float *pixels,
                        TexEncoding enc, Diag *err)
{
    *t = (ImageTexture){0};
    if (width <= 0 || height <= 0 || (channels != 1 && channels != 3 && channels != 4) || !pixels ||
        (size_t)width * (size_t)height > ((size_t)1 << 31)) {
        diag_set(err, WEDGE_EXIT_INPUT, (SrcLoc){0}, "image texture: unsupported size %dx%d with %d channels", width,
                 height, channels);
        return false;
    }
    size_t n = (size_t)width * (size_t)height;
    t->rgb = malloc(n * 3 * sizeof(float));
    if (!t->rgb) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for a %dx%d texture", width, height);
        return false;
    }
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            float v = pixels[i * (size_t)channels + (channels == 1 ? 0 : (size_t)c)];
            v = isfinite(v) ? tex_encoding_to_linear(enc, v) : 0.0f; /* no NaN/Inf downstream */
            t->rgb[i * 3 + (size_t)c] = isfinite(v) ? v : 0.0f;
        }
    t->width = width, t->height = height;
    t->wrap = TEX_WRAP_REPEAT;
    t->scale = 1.0f;
    t->uscale = t->vscale = 1.0f;
    return true;
}

static bool has_png_extension(const char *path)
{
    size_t n = strlen(path);
    return n >= 4 && !strcasecmp(path + n - 4, ".png");
}

bool image_texture_load(ImageTexture *t, const char *path, const char *encoding, Diag *err)
{
    *t = (ImageTexture){0};
    bool png = has_png_extension(path);
    TexEncoding enc = {png ? TEX_ENCODING_SRGB : TEX_ENCODING_LINEAR, 1.0f};
    if (encoding && !tex_encoding_parse(encoding, &enc)) {
        diag_set(err, WEDGE_EXIT_INPUT, (SrcLoc){0},
                 "%s: unknown texture encoding '%s' (expected \"sRGB\", \"linear\" or \"gamma G\")", path, encoding);
        return false;
    }
    int w = 0, h = 0, ch = 3;
    float *px = NULL;
    bool ok;
    if (png) {
        ok = png_read(path, &w, &h, &ch, &px, err);
    } else {
        ok = exr_read_rgb(path, &w, &h, &px, err);
        enc = (TexEncoding){TEX_ENCODING_LINEAR, 1.0f}; /* float data: encoding not applied */
    }
    if (!ok) return false;
    ok = image_texture_init(t, w, h, ch, px, enc, err);
    free(px);
    return ok;
}

void image_texture_free(ImageTexture *t)
{
    free(t->rgb);
    *t = (ImageTexture){0};
}

/* Texel (x, y) under the wrap mode; false for "black" outside the image. */
static bool texel(const ImageTexture *t, int x, int y, vec3 *c)
{
    switch (t->wrap) {
    case TEX_WRAP_REPEAT:
        x %= t->width, y %= t->height;
        if (x < 0) x += t->width;
        if (y < 0) y += t->height;
        break;
    case TEX_WRAP_CLAMP:
        x = x < 0 ? 0 : (x >= t->width ? t->width - 1 : x);
        y = y < 0 ? 0 : (y >= t->height ? t->height - 1 : y);
        break;
    case TEX_WRAP_BLACK:
        if (x < 0 || y < 0 || x >= t->width || y >= t->height) return false;
        break;
    }
    const float *p = t->rgb + 3 * ((size_t)y * (size_t)t->width + (size_t)x);
    *c = v3(p[0], p[1], p[2]);
    return true;
}

static vec3 texel_or_black(const ImageTexture *t, int x, int y)
{
    vec3 c;
    return texel(t, x, y, &c) ? c : v3s(0.0f);
}

/* Integer part that cannot overflow int for huge or non-finite coordinates. */
static int safe_floor(float x, float *frac)
{
    if (!isfinite(x)) x = 0.0f;
    x = fminf(fmaxf(x, -1.0e8f), 1.0e8f);
    float f = floorf(x);
    *frac = x - f;
    return (int)f;
}

vec3 image_texture_lookup(const ImageTexture *t, vec2 st)
{
    if (!t->rgb) return v3s(0.0f);
    float fx, fy;
    if (t->nearest) {
        int x = safe_floor(st.x * (float)t->width, &fx), y = safe_floor(st.y * (float)t->height, &fy);
        return texel_or_black(t, x, y);
    }
    /* texel centres sit at half-integers: shift by 0.5 so that (x0, y0) is the centre
     * up-left of st */
    int x0 = safe_floor(st.x * (float)t->width - 0.5f, &fx), y0 = safe_floor(st.y * (float)t->height - 0.5f, &fy);
    vec3 a = v3_lerp(texel_or_black(t, x0, y0), texel_or_black(t, x0 + 1, y0), fx);
    vec3 b = v3_lerp(texel_or_black(t, x0, y0 + 1), texel_or_black(t, x0 + 1, y0 + 1), fx);
    return v3_lerp(a, b, fy);
}

vec3 image_texture_eval(const ImageTexture *t, vec2 uv)
{
    vec2 st = v2(uv.x * t->uscale + t->udelta, uv.y * t->vscale + t->vdelta);
    st.y = 1.0f - st.y; /* texture space has (0,0) at the bottom left, images at the top left */
    vec3 c = v3_scale(image_texture_lookup(t, st), t->scale);
    if (t->invert) c = v3_sub(v3s(1.0f), c);
    return v3(fmaxf(c.x, 0.0f), fmaxf(c.y, 0.0f), fmaxf(c.z, 0.0f));
}

float image_texture_eval_float(const ImageTexture *t, vec2 uv) { return image_texture_eval(t, uv).x; }
