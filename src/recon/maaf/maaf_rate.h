/* How many samples each pixel of a frame with defocus gets under MAAF's plan: the allocation
 * that minimises the frame's relative error for a given total (docs/algorithms.md 9.14).
 *
 * A pixel i whose reconstruction averages its samples with those of A_i pixels (A_i the
 * filter's effective pixel count, 1 / sum of the squared normalised weights) has a variance
 * v_i / (n_i A_i), v_i the variance of one of its samples. Minimising sum_i v_i / (n_i A_i)
 * under sum_i n_i = N (a Lagrange multiplier) gives
 *
 *     n_i = N sqrt(v_i / A_i) / sum_k sqrt(v_k / A_k)
 *
 * (the error is then (sum_k sqrt(v_k / A_k))^2 / N). v_i is measured from pass 1's samples of
 * the pixel (their luminance, relative as relMSE weighs it: / (mean^2 + 0.01)), over a 3 x 3
 * window because nine samples give a noisy variance; A_i comes from the pixel's filters. This
 * is seeds/003's adaptive sampling ("more samples near the focal plane", where the lens
 * filter collapses: A = 1) made quantitative, and it also gives more to pixels whose shading
 * filters pass them through (silhouettes) and fewer to flat, well-filtered ones. */
#ifndef WEDGE_RECON_MAAF_MAAF_RATE_H
#define WEDGE_RECON_MAAF_MAAF_RATE_H

#include <stdbool.h>

/* Adds one sample's luminance to a pixel's moments (count, sum, sum of squares, unused);
 * non-finite values are left out. */
void maaf_rate_add(float *moments4, float luminance);

/* Effective pixel count of the filters a pixel's light goes through, in pixels: a normalised
 * 2D Gaussian of std s px averages 1 / sum w^2 = 4 pi s^2 pixels (s >~ 1 px); the lens filter
 * (std lens_px) blurs the shading filter's output (std shade_px), and the widths add in
 * quadrature. 0 for a filter that passes the pixel through; at least 1 (the pixel itself). */
float maaf_rate_area_px(float lens_px, float shade_px);

/* Per pixel, the relative variance of one pass-1 sample, v / (mean^2 + 0.01), averaged over the
 * 3 x 3 window around it and divided by its mean over the frame (so 1 is a typical pixel; 0
 * where the whole window is constant). moments4 from maaf_rate_add, rel_var w * h floats. False
 * when out of memory. */
bool maaf_rate_rel_var(const float *moments4, int width, int height, float *rel_var);

/* The count factor of a pixel against a reference pixel of typical variance filtered over
 * ref_area (pixels): sqrt(rel_var ref_area / area), the Lagrange allocation's ratio. */
float maaf_rate_factor(float rel_var, float area, float ref_area);

#endif
