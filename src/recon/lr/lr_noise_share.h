/* How much of a frame's in-focus variation is noise: the still pixels' noise share
 * (docs/algorithms.md 8.37), which widens the still layers' pixel band of 8.36 where the light
 * is noisy and leaves it where the variation is texture. */
#ifndef WEDGE_RECON_LR_NOISE_SHARE_H
#define WEDGE_RECON_LR_NOISE_SHARE_H

#include "recon/lr/lr_partition.h"

/* Over the horizontally neighbouring pairs of still pixels (moving[] zero for both: no sample
 * moving or blurred by the lens, lr_method.c's flag), the mean variance of a pixel's mean
 * brightness estimated from its own samples (their sample variance / spp) over the mean half
 * squared difference of the two pixels' means, both relative to the pixel mean's square (plus
 * a floor for black): 1 where neighbouring still pixels differ by their noise alone, under 1
 * where they differ by texture. Returns -1 (unknown) with fewer than LR_NOISE_SHARE_MIN_PAIRS
 * pairs or spp < 2. */
enum { LR_NOISE_SHARE_MIN_PAIRS = 64 };
double lr_still_noise_share(const LrSamples *img, const unsigned char *moving);

/* The still band's widening for a noise share: (share / LR_NOISE_SHARE_REF)^(1/8), within
 * [1, LR_NOISE_WIDEN_MAX]; 1 for an unknown share. */
#define LR_NOISE_SHARE_REF 0.3
#define LR_NOISE_WIDEN_MAX 1.25
float lr_still_band_widening(double noise_share);

/* The still band band_px (lr_still_sigma_pixel_px's) widened for the noise share, at most
 * LR_NOISE_BAND_MAX_PX (a band already wider keeps its width). */
#define LR_NOISE_BAND_MAX_PX 0.5f
float lr_still_band_px(float band_px, double noise_share);

#endif
