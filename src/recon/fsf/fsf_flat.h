/* FSF's indirect-light filter without the shear: its two spatial passes over the pixels'
 * sample sums (docs/algorithms.md section 10, "Indirect light", "The bounce filter as two
 * spatial passes").
 *
 * Why. On the v-plane every sample lies inside the rim's square (|v_a| <= FSF_BOUNCE_V_RIM)
 * and the parallax bound keeps a tap's shift below 1.3 v, so the box profile keeps every
 * sample at every tap, and the density rho is each filter's plain tap sum: the four passes
 * (fsf_filter.h) then average whole pixels. The shear enters only through pass 1b's and 2b's
 * interpolation between shift nodes 2.5 v apart, whose box counts differ by the samples beyond
 * 2.5 v; with eta = 0 the passes are exactly (up to rounding) the two below:
 *
 *   A  for each pixel q:  G(q) = sum_t1 w_q(t1) S(q + t1 dir1_q) / sum_{|t1| <= r1} w_q(t1)
 *   B  for each pixel p:  out(p) = sum_t2 w_p(t2) G(p + t2 dir2_p)
 *
 * S = (sum of the pixel's stored samples' values, their count): the samples are scaled so
 * that they average to the pixel's value (fsf_match_pixel), so S = (count value, count); w_x(t) = exp(-t^2 / (2 sigma_x^2)) along the
 * pixel's own axis (pass A: q's first, pass B: p's second, as passes 1b and 2b gather), t over
 * fsf_tap_radius, taps rounded to the nearest pixel (fsf_step_pixel) and kept where t = 0 or
 * fsf_accept(centre, neighbour); pass A divides by the sum of all 2 r1 + 1 weights (pass 1a's
 * density times pass 1b's mean density: the taps a guide rejects still count), pass B's
 * divisor is one per pixel and cancels in out.rgb / out.w. The transfer weight that would make
 * the shear count (fsf_transfer.h) lost on every scene measured, so the shear is left out and
 * with it the per-sample work: the passes read 4 floats a pixel, not a pixel's samples at 9
 * shift nodes. fsf_flat_cl.h runs the same passes as OpenCL kernels (fsf_flat.cl), used
 * whenever FSF has a device; this C version, on the host threads, is their reference and the
 * path without one. */
#ifndef WEDGE_RECON_FSF_FLAT_H
#define WEDGE_RECON_FSF_FLAT_H

#include <stdbool.h>

#include "recon/fsf/fsf_filter.h"

/* The filter on a width x height frame: S from each usable pixel's value (value4, 4 floats a
 * pixel, rgb) and stored count: S = (count value, count), a non-finite channel 0 (what the
 * samples scaled to that value sum to: fsf_match_pixel, fsf_fill_dark_channels; the samples'
 * light itself is not read). out4: (rgb, weight) per pixel as fsf_filter_factored's (0 where
 * not usable; a pixel with both widths 0 its own S). px's eta is not read. false when out of
 * memory. */
bool fsf_filter_flat(const float *value4, const int *count, int width, int height, const FsfGrid *g,
                     const FsfPixel *px, const FsfGuides *gd, float *out4);

/* How many of the n pixels' rgb channels the filter (C or kernel) takes as 0 because they are
 * NaN or infinite: the usable pixels' (usable non-zero) non-finite value4 channels, for the
 * caller to report. */
long long fsf_flat_nonfinite_inputs(const float *value4, const unsigned char *usable, size_t n);

#endif
