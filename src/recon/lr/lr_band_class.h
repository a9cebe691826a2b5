/* The still band per pixel (docs/algorithms.md 8.39, 8.40): a pixel's still layers take the
 * paper's narrow band where the light curves measurably across a line through the pixel (a
 * texture or shadow edge), a wide band where no curvature stands out of the pixels' own noise,
 * and the frame's band (8.36, 8.37) in between. Only the still layers' screen filter follows
 * the class; their reprojection keeps the frame's band (the cheap form of 8.39). */
#ifndef WEDGE_RECON_LR_BAND_CLASS_H
#define WEDGE_RECON_LR_BAND_CLASS_H

#include <stdbool.h>

#include "recon/lr/lr_partition.h"
#include "recon/lr/lr_taps.h"

enum { LR_BAND_FRAME = 0, LR_BAND_NARROW = 1, LR_BAND_WIDE = 2, LR_BAND_CLASSES = 3 };

/* The classes' bands (px): the paper's sigma_pixel, and the widest band lr21's per-pixel
 * oracle chose among (docs/benchmarks.md, lr21 and lr22). */
#define LR_BAND_NARROW_PX (1.0f / 3.0f)
#define LR_BAND_WIDE_PX 0.6f

/* The score's limits: above LR_BAND_Z_EDGE (the curvature two standard deviations out of its
 * noise) narrow, at most LR_BAND_Z_FLAT (within one) wide; chosen on seeds 1-5 of the two
 * bench scenes (8.39). */
#define LR_BAND_Z_EDGE 4.0
#define LR_BAND_Z_FLAT 1.0

/* The oriented curvature score of pixel (x, y) from the pixel means m[] and the variances of
 * those means v[] (w x h, row-major): the second difference across the rows summed over the
 * three pixels x - 1 .. x + 1, squared over its variance (the pixels independent), the same
 * across the columns over y - 1 .. y + 1, and the larger of the two. Each variance has a floor
 * of 1e-4 (m(x, y)^2 + 0.03). -1 on the image's outermost pixels or for a non-finite score. */
double lr_band_curvature_z(const float *m, const float *v, int w, int h, int x, int y);

/* The class (LR_BAND_*) of a score: LR_BAND_FRAME for an unknown one (negative). */
int lr_band_class_of(double z);

/* Per pixel of img its class, from lr_band_curvature_z of its samples' mean brightness
 * (LrSamples.bright, r + g + b) and that mean's variance (sample variance / spp). false (cls
 * untouched) when spp < 2 or out of memory. */
bool lr_band_classes(const LrSamples *img, unsigned char *cls);

/* The classes (bit 1 << LR_BAND_*) among tile (tx, ty)'s pixels; 0 without a class map. */
unsigned lr_band_tile_classes(const LrSamples *img, const LrConfig *cfg, int tx, int ty);

/* The screen filter of a layer at class cls's band: true, with it in *out and its filter in
 * *filter, when the layer is still (no motion range: lr_filter_make gives it the still band)
 * and the class's screen filter differs from the frame band's (frame, the layer's
 * lr_screen_make); false when the frame's serves the class's pixels as it is (cls
 * LR_BAND_FRAME, a moving layer, the same taps). */
bool lr_band_screen(const LrConfig *cfg, const LrLayer *layer, int cls, const LrScreen *frame, LrScreen *out, LrFilter *filter);

#endif
