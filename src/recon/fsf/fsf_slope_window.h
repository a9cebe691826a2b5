/* FSF's slope ranges over growing windows, shared by the shadow (fsf_params.h) and lens
 * (fsf_lens.h) parameters.
 *
 * The filter reprojects every sample under a pixel's footprint with one shear, so the slope
 * range that bounds its width must hold the slopes of all those samples, not only the
 * pixel's own. Windows of radius 2 (5 x 5: FSF section 5's slope smoothing), 4, 8 and 16
 * (the tap cap) each give a width capped so that its taps (2 sigma) stay inside the window;
 * the widest wins, with its window's range. A window without slopes allows its full radius. */
#ifndef WEDGE_RECON_FSF_SLOPE_WINDOW_H
#define WEDGE_RECON_FSF_SLOPE_WINDOW_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/gbuffer.h"
#include "recon/sample_store.h"

enum { FSF_LEVELS = 4 };
extern const int FSF_LEVEL_RADIUS_PX[FSF_LEVELS];

typedef struct {
    float *lo[FSF_LEVELS], *hi[FSF_LEVELS]; /* per level and pixel (+inf, -inf: no slope) */
    const float *own_lo, *own_hi;           /* per pixel, over its own samples (the windows' input) */
    float *block;
} FsfSlopeWindows;

/* The ranges over the square windows of every level, from each pixel's own range over its
 * stored samples (slope(ctx, slot) per sample, slot = pixel * capacity + k, NaN for a sample
 * without one), counting only pixels whose obj equals the centre's (obj NULL: every pixel).
 * false when out of memory. */
bool fsf_slope_windows(const SampleStore *st, int width, int height, float (*slope)(const void *ctx, size_t slot),
                       const void *ctx, const float *obj, FsfSlopeWindows *out);
/* The same counting only the centre's object (the guides' object id, nrm4[3]): a filter that
 * takes light from no other surface needs no other surface's slopes. */
bool fsf_slope_windows_per_object(const SampleStore *st, const GBuffer *g, float (*slope)(const void *ctx, size_t slot),
                                  const void *ctx, FsfSlopeWindows *out);
void fsf_slope_windows_free(FsfSlopeWindows *w);

/* w (from fsf_slope_windows over the same store) after the object ids of some pixels in rows
 * y0 .. y1 changed to obj's: the rows whose windows can reach those pixels found again (the own
 * ranges depend on the store only and are kept), which gives the windows fsf_slope_windows would
 * give with obj, bit for bit. */
void fsf_slope_windows_update(FsfSlopeWindows *w, int width, int height, const float *obj, int y0, int y1);

/* The widest safe level of pixel i. sigma_of_spread(ctx, spread) is the width (pixel steps,
 * before any cap) that a slope spread allows, the narrowest over the axes. */
typedef struct {
    float lo, hi;        /* the chosen window's range (lo > hi: no slope in it) */
    float cap_px;        /* its radius / FSF_RADIUS_SIGMAS */
} FsfSlopePick;
FsfSlopePick fsf_slope_pick(const FsfSlopeWindows *w, size_t i, float (*sigma_of_spread)(const void *ctx, float spread),
                            const void *ctx);

#endif
