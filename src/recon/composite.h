/* The per-pixel work around the reconstruction filters (DESIGN.md section 2), host side:
 *
 *   prepare    the frame's means; the light a filter must not blur (SampleRecord.unfiltered)
 *              taken out; each shading effect's light divided by albedo (and by the method's
 *              factor for direct light, AAF-shadow's r(x)) where there is a filterable surface
 *   image      emission + albedo x filtered light + the unfiltered part, the composite
 *              radiance (and a copy as (r, g, b, 1) for a camera-effect filter)
 *   finish     the camera-effect filter's output into the image, nothing non-finite left
 *
 * Pixels are independent and split between the cores (recon_parallel.h), so results do not
 * depend on the split. Every non-finite value set to 0 is counted. */
#ifndef WEDGE_RECON_COMPOSITE_H
#define WEDGE_RECON_COMPOSITE_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/gbuffer.h"

typedef struct {
    long long guarded;     /* non-finite values set to 0 */
    long long bad_pixels;  /* pixels with at least one */
} CompositeCounts;

/* direct4 / indirect4 (4 floats per pixel, NULL: not filtered) get (r, g, b, usable): the
 * demodulated light, usable 0 where it is passed through as it is. factor: per-pixel divisor
 * of the direct light besides the albedo (NULL: 1); pixels at or below factor_min keep theirs. */
CompositeCounts composite_prepare(const GBuffer *g, const float *factor, float factor_min, float *direct4,
                                  float *indirect4);
/* The composite into rgb (3 floats per pixel) from the filtered lights (NULL: the means); a
 * copy into radiance4 (4 per pixel) when a camera-effect filter follows (NULL: none). */
void composite_image(const GBuffer *g, const float *factor, const float *direct4, const float *indirect4, float *rgb,
                     float *radiance4);
/* A split pixel's filterable direct (direct) or indirect light after its first surface was
 * filtered (gbuffer.h; value4: the filtered demodulated value, usable; factor: the direct
 * light's, 1 for indirect): share x albedo x factor x value4 + the other samples' light / spp,
 * which keeps the pixel's expectation (docs/algorithms.md, "Mixed pixels: the first surface
 * filtered"). */
void composite_split_light(const GBuffer *g, size_t i, bool direct, const float *value4, float factor, float out[3]);
/* rgb from radiance4 (when a camera-effect filter ran, else rgb itself), finite. */
CompositeCounts composite_finish(float *rgb, const float *radiance4, size_t pixels);

#endif
