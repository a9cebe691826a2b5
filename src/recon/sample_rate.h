/* Where a frame's samples go: the allocation that minimises the frame's relative error for a
 * given total (docs/algorithms.md 9.14; FSF's plan, section 10 "Under a budget").
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
 * window because nine samples give a noisy variance; A_i comes from the method's filters.
 * Nothing here knows a method: MAAF (maaf_method.c) and FSF (fsf_budget_plan.c) give the
 * areas of their own filters. */
#ifndef WEDGE_RECON_SAMPLE_RATE_H
#define WEDGE_RECON_SAMPLE_RATE_H

#include <stdbool.h>
#include <stddef.h>

/* Adds one sample's luminance to a pixel's moments (count, sum, sum of squares, unused);
 * non-finite values are left out. */
void sample_rate_add(float *moments4, float luminance);

/* Effective pixel count of a normalised 2D Gaussian whose variances along its two axes are
 * var_a_px2 and var_b_px2 (square pixel steps; separable along the axes, which need not be
 * orthogonal as long as a step reaches another pixel): 1 / sum w^2 = 4 pi sqrt(var_a var_b)
 * pixels (stds >~ 1 px). Two Gaussian blurs applied one after the other compose to one whose
 * variances add. At least 1 (the pixel itself); 0 along an axis: a filter that passes the
 * pixel through. */
float sample_rate_area_px(float var_a_px2, float var_b_px2);

/* Per pixel, the relative variance of one pass-1 sample, v / (mean^2 + 0.01), averaged over the
 * 3 x 3 window around it and divided by its mean over the frame (so 1 is a typical pixel; 0
 * where the whole window is constant). moments4 from sample_rate_add, rel_var w * h floats.
 * False when out of memory. */
bool sample_rate_rel_var(const float *moments4, int width, int height, float *rel_var);

/* The count factor of a pixel against a reference pixel of typical variance filtered over
 * ref_area (pixels): sqrt(rel_var ref_area / area), the Lagrange allocation's ratio. */
float sample_rate_factor(float rel_var, float area, float ref_area);

/* The two steps above for a frame, as both methods use them: area_factor holds each pixel's
 * filter area (pixels) and becomes its count factor against a typical pixel that no filter
 * covers (ref_area 1), in place. False when out of memory. */
bool sample_rate_factors(const float *moments4, int width, int height, float *area_factor);

/* Counts for a total when every pixel already has floor_spp samples (those traced) and may
 * have at most cap_spp: the optimum of sum v / (n A) under those bounds (its KKT conditions)
 * is n_i = clamp(lambda factor_i, floor_spp, cap_spp), lambda the one that spends
 * total_spp * n (found by bisection; the sum is monotone in lambda). spp_out[i] gets that
 * real count; where even lambda = infinity cannot spend the total (every pixel capped or of
 * factor 0) the rest is spread evenly over the pixels. spp_out may be factor itself. */
void sample_rate_counts(const float *factor, size_t n, float floor_spp, float cap_spp, double total_spp,
                        float *spp_out);

#endif
