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
/* Reads an 8/16-bit PNG as float rgb in [0,1] (no decoding of sRGB: callers decide), malloc'd.
 * Pixels are interleaved with *channels values each: 3 (RGB) or 4 (RGBA when the file has
 * alpha: grey+alpha, RGBA, or a palette with transparency). Grey is expanded to RGB and
 * palettes to their colours; values are code / (2^bits - 1). err exit 2. */
bool png_read(const char *path, int *width, int *height, int *channels, float **pixels, Diag *err);

/* True when the path ends in ".png" (case-insensitive). */
bool path_is_png(const char *path);

/* ---- Additions beyond the original contract (io engineer) ---- */

/* Compression numbering of the EXR file format (same values as the file's byte). */
typedef enum {
    EXRC_NONE = 0, EXRC_RLE = 1, EXRC_ZIPS = 2, EXRC_ZIP = 3, EXRC_PIZ = 4, EXRC_PXR24 = 5,
    EXRC_B44 = 6, EXRC_B44A = 7, EXRC_DWAA = 8, EXRC_DWAB = 9
} ExrCompression;
typedef enum { EXR_STORE_FLOAT, EXR_STORE_HALF, EXR_STORE_UINT } ExrStoreType;

/* Deflate level (libdeflate's, io/exr_zip.h; zlib's before) of ZIP and ZIPS chunks when
 * ExrWriteOptions.zip_level is 0: the fastest. zlib's level 1 on a 1080p render's RGBA
 * deflated ~1.5x faster than OpenEXR's default (zlib's 6) for a file ~1.4% larger
 * (docs/benchmarks.md, issue 22's low-count bundle); libdeflate's level 1 takes about half
 * of zlib's level 1 for a file ~1% smaller (wave39). Lossless either way, and not stored in
 * the file: readers never see it. */
enum { EXR_ZIP_LEVEL_DEFAULT = 1 };

/* Knobs for exr_write_with(); exr_write() is {EXR_STORE_FLOAT, EXRC_ZIP, scanline, level 0}. */
typedef struct {
    ExrStoreType store;       /* pixel type on disk (uint: values rounded, clamped at 0) */
    ExrCompression compression;
    int tile_size;            /* 0: scanline file; > 0: single-level tiled, square tiles */
    int zip_level;            /* deflate level 1-9 of ZIP/ZIPS; 0: EXR_ZIP_LEVEL_DEFAULT */
    long nonfinite_replaced;  /* out: how many NaN/Inf values were written as 0 */
} ExrWriteOptions;

bool exr_write_with(const char *path, int width, int height, const ExrChannel *channels,
                    int channel_count, const ExrAttr *attrs, int attr_count, ExrWriteOptions *opt,
                    Diag *err);

/* A whole EXR (first part) in memory: every channel as a float plane, plus the string,
 * float, double (stored in f) and int header attributes. Channel names are in file order
 * (alphabetical). The data window origin is dropped: pixel (0,0) is its top-left corner. */
typedef struct {
    int width, height;
    int channel_count;
    char **names;      /* channel_count names */
    float **planes;    /* planes[c][y * width + x] */
    int attr_count;
    ExrAttr *attrs;    /* names and strings owned by the image */
} ExrImage;

/* Reads every channel of any scanline or single-level tiled EXR (half/float/uint, any
 * compression; subsampled channels are refused). err exit 2. */
bool exr_read(const char *path, ExrImage *img, Diag *err);
void exr_image_free(ExrImage *img);
/* The plane of a channel, or NULL when the image has no channel of that name. */
const float *exr_image_channel(const ExrImage *img, const char *name);
const ExrAttr *exr_image_attr(const ExrImage *img, const char *name);
/* Reads one named channel ("Z", "albedo.R") as a malloc'd width*height float plane. A
 * missing channel is an error that lists the channels the file has. err exit 2. */
bool exr_read_channel(const char *path, const char *channel, int *width, int *height, float **data,
                      Diag *err);

/* Any of the two formats by extension: PNG is decoded from sRGB to linear (alpha dropped),
 * anything else is read as EXR with exr_read_rgb. Interleaved rgb, malloc'd. err exit 2. */
bool image_read_linear_rgb(const char *path, int *width, int *height, float **rgb, Diag *err);

#endif
