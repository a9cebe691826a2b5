/* False colour for scalar maps (filter widths, sample counts) in docs and --visualize. */
#ifndef WEDGE_CORE_FALSE_COLOUR_H
#define WEDGE_CORE_FALSE_COLOUR_H

#include <stddef.h>

/* t in [0, 1] (clamped) to a display rgb ramp: black, blue, magenta, orange, pale yellow.
 * Perceptually ordered (lightness rises monotonically) so it reads in greyscale too. */
void false_colour(float t, float rgb[3]);

/* Maps values[0..n) to rgb (3 per pixel) scaled by the largest finite value, which is
 * returned (0 when there is none; non-finite values show as 0). */
float false_colour_image(const float *values, size_t n, float *rgb);

#endif
