/* Pixel reconstruction filters as pbrt-v4 defines them (box, gaussian, triangle, mitchell,
 * sinc), applied by filter importance sampling: each camera sample is placed at an offset
 * from its pixel's centre drawn from the filter's shape and carries a weight, and it is
 * added to that one pixel only. The per-pixel mean of weight x radiance then estimates the
 * filtered image, and per-pixel statistics (and the reconstruction filters built on them)
 * keep working unchanged. All five filters are separable, f(x, y) = f_x(x) f_y(y), so each
 * axis is sampled on its own. */
#ifndef WEDGE_RENDER_PIXEL_FILTER_H
#define WEDGE_RENDER_PIXEL_FILTER_H

#include <stdbool.h>

#include "core/diag.h"
#include "core/vec.h"
#include "render/sample_record.h"
#include "scene/scene_desc.h"

typedef enum {
    PIXEL_FILTER_BOX,
    PIXEL_FILTER_GAUSSIAN,
    PIXEL_FILTER_TRIANGLE,
    PIXEL_FILTER_MITCHELL,
    PIXEL_FILTER_SINC
} PixelFilterKind;

/* One axis of a tabulated filter (gaussian, mitchell, sinc): like pbrt-v4's FilterSampler,
 * 32 cells per unit of radius over [-r, r], |f| at the cell centres as a piecewise-constant
 * density; a sample's weight is the sign of f in its cell times sum|f| / sum f, so that the
 * weights average to 1 and positive filters give weight 1 exactly. */
typedef struct {
    int cells;
    float *cdf;        /* cells + 1 entries, cdf[0] = 0, cdf[cells] = 1 */
    signed char *sign; /* sign of f per cell */
    float abs_over_sum; /* sum |f| / sum f over the cells */
} PixelFilterAxis;

typedef struct {
    PixelFilterKind kind;
    float radius[2];     /* pixels, per axis */
    float sigma;         /* gaussian */
    float b, c;          /* mitchell */
    float tau;           /* sinc: lobes of the Lanczos window */
    bool unit_box;       /* box of radius 0.5: the film sample is used as is (bit for bit) */
    PixelFilterAxis axis[2];
} PixelFilter;

/* Names, as in pbrt-v4's PixelFilter statement and --pixel-filter. */
bool pixel_filter_kind_from_name(const char *name, PixelFilterKind *kind);

/* Builds a filter of the given type from pbrt-v4 parameters (xradius, yradius, sigma, B, C,
 * tau; pbrt-v4's defaults; params may be NULL). Errors (exit 2): unknown type, radius not
 * positive or over 16 pixels, sigma not positive, a filter whose integral is not positive. */
bool pixel_filter_init(PixelFilter *pf, const char *type, const ParamSet *params, SrcLoc loc, Diag *err);
void pixel_filter_free(PixelFilter *pf);

/* pbrt-v4's Evaluate: the unnormalised filter at offset (x, y) from the pixel centre. */
float pixel_filter_eval(const PixelFilter *pf, float x, float y);

/* The tabulated and wider filters' part of pixel_filter_sample (pixel_filter.c). */
vec2 pixel_filter_sample_shaped(const PixelFilter *pf, vec2 u, float *weight);

/* Maps a film sample u in [0, 1)^2 to a position relative to the pixel's corner (the pixel
 * covers [0, 1)^2; the position lies in [0.5 - r, 0.5 + r]) and the sample's weight. The
 * unit box (and no filter, NULL) returns u itself and weight 1. Inline: every camera sample
 * asks, and the bench scenes' box needs no call. */
static inline vec2 pixel_filter_sample(const PixelFilter *pf, vec2 u, float *weight)
{
    if (!pf || pf->unit_box) {
        *weight = 1.0f;
        return u;
    }
    return pixel_filter_sample_shaped(pf, u, weight);
}

/* Multiplies a sample's radiance (L, emission, direct, indirect) by the filter weight w (w
 * != 1: the callers skip the weight 1). */
static inline void pixel_filter_weigh_radiance(SampleRadiance *R, float w)
{
    R->L = v3_scale(R->L, w);
    R->emission = v3_scale(R->emission, w);
    R->direct = v3_scale(R->direct, w);
    R->indirect = v3_scale(R->indirect, w);
}

/* Multiplies the radiance fields of a complete record (L, emission, direct, indirect,
 * unfiltered) by its filter_weight; nothing to do when the weight is 1. Inline: the
 * renderer calls it for every record. */
static inline void pixel_filter_weigh_record(SampleRecord *rec)
{
    float w = rec->filter_weight;
    if (w == 1.0f) return;
    pixel_filter_weigh_radiance(&rec->radiance, w);
    rec->unfiltered = v3_scale(rec->unfiltered, w);
    rec->unfiltered_direct = v3_scale(rec->unfiltered_direct, w);
}

#endif
