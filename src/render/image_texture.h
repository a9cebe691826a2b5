/* pbrt-v4 "imagemap" texture: an EXR or PNG image looked up with bilinear filtering,
 * wrap modes repeat / clamp / black, pbrt-v4's "encoding" rules, "scale" and "invert", and
 * the (u, v) mapping with uscale / vscale / udelta / vdelta.
 *
 * pbrt-v4 semantics kept here (docs/materials.md):
 * - encoding: default "sRGB" for .png files, "linear" otherwise; "gamma G" raises the
 *   stored value to the power G. It applies to PNG (8 and 16 bit); EXR holds linear floats
 *   and ignores it (pbrt-v4 only decodes fixed-point images).
 * - mapping: s = u uscale + udelta, t = v vscale + vdelta, and then t is flipped (t = 1 - t)
 *   because texture (0,0) is the lower left corner and image row 0 is the top.
 * - filtering: the texel grid has centres at (i + 0.5) / width; bilinear between the four
 *   nearest centres (pbrt-v4's Image::Bilerp). "point" gives the nearest texel. pbrt-v4's
 *   default "bilinear" is what we do; its MIP-map filters (trilinear, ewa) fall back to
 *   bilinear (no ray differentials in wedge).
 * - value: scale * lookup, then 1 - value if invert, then clamped at 0. */
#ifndef WEDGE_RENDER_IMAGE_TEXTURE_H
#define WEDGE_RENDER_IMAGE_TEXTURE_H

#include <stdbool.h>

#include "core/diag.h"
#include "core/vec.h"

typedef enum { TEX_WRAP_REPEAT, TEX_WRAP_CLAMP, TEX_WRAP_BLACK } TexWrap;
typedef enum { TEX_ENCODING_LINEAR, TEX_ENCODING_SRGB, TEX_ENCODING_GAMMA } TexEncodingKind;

typedef struct {
    TexEncodingKind kind;
    float gamma;               /* TEX_ENCODING_GAMMA */
} TexEncoding;

typedef struct {
    int width, height;
    float *rgb;                /* linear rgb, row 0 = top of the image; owned */
    TexWrap wrap;
    bool nearest;              /* "filter" "point" */
    float scale;
    bool invert;
    float uscale, vscale, udelta, vdelta;
} ImageTexture;

/* "sRGB", "linear" or "gamma G" (G > 0). False for anything else. */
bool tex_encoding_parse(const char *s, TexEncoding *enc);
/* Decodes one stored value in [0,1] to linear (sRGB: IEC 61966-2-1 piecewise curve). */
float tex_encoding_to_linear(TexEncoding enc, float v);
/* "repeat", "clamp", "black" (pbrt-v4's "octahedralsphere" is for environment maps and
 * is refused here). False for anything else. */
bool tex_wrap_parse(const char *s, TexWrap *wrap);

/* A texture with default parameters (repeat, bilinear, scale 1, no invert, unit mapping)
 * from interleaved pixels with `channels` values each (1: grey, 3: rgb, 4: rgba with alpha
 * ignored), stored top row first, decoded with enc (pass linear for float images).
 * Copies the pixels. err: exit 3 (memory) or 2 (bad size). */
bool image_texture_init(ImageTexture *t, int width, int height, int channels, const float *pixels,
                        TexEncoding enc, Diag *err);
/* Loads an image file by extension: .png through png_read, anything else as EXR through
 * exr_read_rgb. encoding NULL applies pbrt-v4's default ("sRGB" for .png, else linear); an
 * unknown encoding string is an error. err exit 2. */
bool image_texture_load(ImageTexture *t, const char *path, const char *encoding, Diag *err);
void image_texture_free(ImageTexture *t);

/* Raw filtered lookup at image coordinates st in [0,1]^2 (t = 0 is the top row), with the
 * texture's wrap mode and filter; no scale / invert. */
vec3 image_texture_lookup(const ImageTexture *t, vec2 st);
/* The texture's value at surface (u, v): mapping, flip, lookup, scale, invert, clamp >= 0. */
vec3 image_texture_eval(const ImageTexture *t, vec2 uv);
/* Float imagemap: the first channel of the same pipeline (pbrt-v4 reads channel 0). */
float image_texture_eval_float(const ImageTexture *t, vec2 uv);

#endif
