/* How far a pixel without an occluder near may reach with the soft-shadow filter (MAAF's far
 * pixels; docs/algorithms.md 9.27).
 *
 * Where no pixel of a window saw an occluder in pass 1 and none has an albedo that varies inside
 * it, each pixel's light divided by its mean albedo and the unoccluded irradiance r(x) (the value
 * the shadow filter averages) has expectation 1: its visibility. A filter that reaches only over
 * such pixels is unbiased whatever its width, and the widest one has the least variance. The
 * reach is the radius of the largest square window around the pixel, inside the image, that
 * holds no marked pixel (maaf_far_marks: those that break the premise). */
#ifndef WEDGE_RECON_MAAF_FAR_REACH_H
#define WEDGE_RECON_MAAF_FAR_REACH_H

#include <stdbool.h>
#include <stddef.h>

/* The pixels that break the premise, marks[j] = 1 for each of n pixels where pass 1 saw an
 * occluder (occluder[j]), where the albedo varies inside the pixel (albedo_varies[j]), or where
 * a surface was hit (hit[j]) but no shadow ray was cast (shadow_rays[j] == 0): there nothing
 * checked that the light is unoccluded. With N unoccluded rays and none occluded the occluded
 * fraction is below 3 / N at 95% (the rule of three); N = 0 bounds nothing (a face lit only at
 * grazing, whose light points all fell behind its horizon in pass 1; docs/algorithms.md 9.28).
 * marks may be occluder itself. */
void maaf_far_marks(size_t n, const unsigned char *occluder, const unsigned char *albedo_varies,
                    const unsigned char *hit, const int *shadow_rays, unsigned char *marks);

/* reach_px[i] = min(cap_px, d - 1), where d is the Chebyshev distance in pixels from pixel i to
 * the nearest pixel j with seen[j] != 0 (d = 0 where pixel i is marked itself, reach 0 then), or
 * cap_px where none lies within cap_px + 1. cap_px in [0, 254]. Separable: per row the distance
 * to the nearest such pixel within cap_px + 1, then per column the least max(|dy|, that).
 * False when out of memory (reach_px then undefined). */
bool maaf_far_reach(const unsigned char *seen, int width, int height, int cap_px, unsigned char *reach_px);

#endif
