/* Rendering with axis-aligned filtering (AAF-shadow, AAF-GI, defocus AAF): the whole
 * sample -> parameters -> adaptive sample -> filter -> composite pipeline, as one call the
 * application makes for `wedge render --filter aaf [--mu X]` (and `--filter auto`).
 *
 *   pass 1   uniform sparse sampling (9 spp for shadows, 16 when indirect light or defocus
 *            is filtered), recording the ray geometry into per-pixel statistics
 *   params   per effect: filter width beta and samples per pixel n (aaf_pixel_params.h)
 *   pass 2   adaptive: max over effects of n minus the pass-1 count, per pixel, continuing
 *            each pixel's pass-1 sampler set (render_pass_more)
 *   filter   OpenCL, separately: direct irradiance (shadows), indirect irradiance, each with
 *            the albedo divided out, then the composite primary radiance (defocus)
 *   output   emission + albedo * filtered direct + albedo * filtered indirect, then defocus
 *
 * The Renderer must be created with RenderOptions.record_ray_geometry = true. */
#ifndef WEDGE_RECON_AAF_RENDER_H
#define WEDGE_RECON_AAF_RENDER_H

#include <stdbool.h>

#include "core/diag.h"
#include "render/frame.h"
#include "render/renderer.h"

enum { AAF_EFFECT_SHADOWS = 0, AAF_EFFECT_INDIRECT = 1, AAF_EFFECT_DEFOCUS = 2, AAF_EFFECT_COUNT = 3 };

/* "shadows", "indirect", "defocus": report keys and AOV layer suffixes (aaf.beta_px.<name>). */
const char *aaf_effect_name(int effect);

typedef struct {
    float mu;              /* > 0: used for every effect; <= 0: the defaults (shadows 2, indirect 2, defocus 1) */
    bool want[AAF_EFFECT_COUNT]; /* filter this effect if the scene has it (auto: all true) */
    const char *cl_device; /* --cl-device; NULL: $WEDGE_CL_DEVICE, else the first GPU/CPU */
} AafRenderOptions;

/* All true, mu default, no device choice. */
AafRenderOptions aaf_render_options_default(void);

typedef struct {
    int width, height;
    float *rgb;                          /* the image: 3 floats per pixel, finite */
    float *beta_px[AAF_EFFECT_COUNT];    /* filter width per pixel (pixels); NULL: not filtered */
    float *spp;                          /* samples taken per pixel (both passes) */
    const char *filters[AAF_EFFECT_COUNT]; /* "aaf" or "none" (effect absent or not wanted) */
    bool present[AAF_EFFECT_COUNT];      /* the scene has the effect */
    double spp_avg;
    double seconds_filter;               /* parameters + filtering + composite (wall) */
    double seconds_kernels;              /* OpenCL device time of the filter passes */
    int pass1_spp;
    long long guarded_events;            /* non-finite values replaced by 0 */
    bool cancelled;                      /* a pass was cancelled: rgb is the unfiltered mean */
    char device[600];                    /* OpenCL device used ("" when none was needed) */
} AafRenderResult;

/* Runs both passes into frame (which must be initialised to the renderer's size and is
 * left holding the sums of all samples), filters, and fills res. False with d set (exit 3)
 * on an OpenCL or memory failure. A cancelled render (RenderOptions.cancel) returns true
 * with res->cancelled set and res->rgb the unfiltered mean of the samples taken. */
bool aaf_render(Renderer *r, const AafRenderOptions *o, Frame *frame, AafRenderResult *res, Diag *d);
void aaf_render_result_free(AafRenderResult *res);

#endif
