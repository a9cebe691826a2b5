/* Image files: EXR through the OpenEXR C API (openexr.h), 8-bit PNG through libpng.
 * Every writer writes a temporary file in the destination folder and renames it into
 * place, so a reader never sees a half-written image. Non-finite values are never written
 * (writers replace them by 0 and count them). */
#ifndef WEDGE_IO_IMAGE_IO_H
#define WEDGE_IO_IMAGE_IO_H

#include <stdbool.h>

#include "core/diag.h"

/* One float32 channel of an EXR: pixel (x, y) is data[(y * width + x) * stride]. */
typedef struct {
    const char *name;  /* "R", "G", "B", "A", "albedo.R", "N.X", "Z", "spp", ... */
    const float *data;
    int stride;
} ExrChannel;

typedef enum { EXR_ATTR_STRING, EXR_ATTR_FLOAT, EXR_ATTR_INT } ExrAttrType;
typedef struct {
    const char *name;
    ExrAttrType type;
    const char *s;
    double f;
    int i;
} ExrAttr;

/* Writes a scanline float32 EXR (ZIP compression). Returns false with err (exit 3). */
bool exr_write(const char *path, int width, int height, const ExrChannel *channels, int channel_count,
               const ExrAttr *attrs, int attr_count, Diag *err);
/* Reads R, G, B (any pixel type, any compression) as interleaved float rgb (malloc'd).
 * Missing channels: error unless the file has a single Y channel (then grey). err exit 2. */
bool exr_read_rgb(const char *path, int *width, int *height, float **rgb, Diag *err);

/* Writes display-referred 8-bit RGB PNG from linear Rec.709 rgb using the plain sRGB
 * encode (the OpenColorIO path lives in io/ocio.h). err exit 3. */
bool png_write_srgb(const char *path, int width, int height, const float *rgb_linear, Diag *err);
/* Writes already display-encoded rgb in [0,1] as 8-bit PNG (used after an OCIO transform). */
bool png_write_display(const char *path, int width, int height, const float *rgb_display, Diag *err);
/* Reads an 8/16-bit PNG as float rgb in [0,1] (no decoding of sRGB: callers decide), malloc'd. */
bool png_read(const char *path, int *width, int *height, int *channels, float **pixels, Diag *err);

/* True when the path ends in ".png" (case-insensitive). */
bool path_is_png(const char *path);

#endif
