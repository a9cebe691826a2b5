/* FSF under a --spp budget: a reduced pass 1 and the rest of the budget at the pixels the
 * filter leaves unfiltered (docs/algorithms.md section 10, "Under a budget").
 *
 * FSF's store keeps pass 1's samples only, so extra samples reach the image through the
 * pixel's own mean (the value its stored samples are scaled to, fsf_match_pixel). That is all
 * a pixel needs where the filter has collapsed: a width under FSF_COLLAPSED_SIGMA_PX along
 * either axis (near a contact line the slope range explodes, FSF eq. 4 goes to 0), a defocus
 * range straddling the focal plane (fsf_lens_straddles), a mixed pixel (several surfaces:
 * passed through), or a pixel the light-share test leaves out (FSF_MIN_LIGHT_SHARE); with
 * defocus filtered too, only where the lens filter leaves the pixel out as well. Such a pixel
 * is Monte Carlo: its variance is sigma^2 / n.
 *
 * The allocation (derived in docs/algorithms.md): minimising the frame's summed variance
 * c sigma^2 / n_c + (1 - c) sigma^2 / (F n_1) under (1 - c) n_1 + c n_c = budget (c the
 * collapsed share, F the filtered pixels' effective footprint, in Monte Carlo samples per
 * sample) gives n_c / n_1 = sqrt(F): FSF_BUDGET_COLLAPSED_RATIO. c is known only after pass 1,
 * so pass 1 takes a fixed share of the budget (FSF_BUDGET_PASS1_SHARE, or _LENS with defocus)
 * and the collapsed pixels get up to ratio * pass 1; what they cannot take is spread over the
 * others. */
#ifndef WEDGE_RECON_FSF_BUDGET_PLAN_H
#define WEDGE_RECON_FSF_BUDGET_PLAN_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/fsf/fsf_filter.h"
#include "recon/fsf/fsf_light.h"
#include "recon/gbuffer.h"
#include "recon/sample_store.h"

/* Below this width (pixel steps) the first taps weigh at most exp(-2) of the centre. Along
 * either axis, not both: on soft_shadows and thin_occluders at 16 spp the two tests gave the
 * same error within 1.5% (2 seeds), and either is what the AOV fsf.sigma_px shows. */
#define FSF_COLLAPSED_SIGMA_PX 0.5f
/* sqrt(F), F the effective footprint of a filtered pixel at the width cap (sigma = 8 px on
 * both axes): a 2D Gaussian of sigma px averages about 4 pi sigma^2 pixels' samples, so
 * sqrt(F) = 2 sqrt(pi) sigma = 28. It binds only where few pixels collapse (c < 1.3% at
 * 16 spp); a ratio of 4 (F = 16) was measured and lost 8-25% (docs/benchmarks.md). */
#define FSF_BUDGET_COLLAPSED_RATIO (2.0f * 1.7724539f * (float)FSF_RADIUS_CAP_PX / FSF_RADIUS_SIGMAS)
/* FSF's light's share of the scene's power (fsf_light_power_share) below FSF_MIN_LIGHT_SHARE:
 * the shadow filter leaves the pixels another light dominates to Monte Carlo, often most of
 * the frame (c near 1), and a pixel's samples in two stratified sets (pass 1's and pass 2's
 * are drawn apart, docs/sampling.md) are worth fewer than one set of as many: on
 * test_filter_assumptions' two lights, 12 + 4 had 1.78x the error of 16 in one pass. There
 * pass 1 takes the whole budget (fsf_method.c's budget_pass1_share). */

/* Pass 1's share of the budget. The variance model's own optimum, n_1 = budget / (1 - c +
 * c sqrt(F)), would be 0.35 of it at c = 7%, but a filtered pixel's error is not only its
 * variance (the slope windows and the widths come from pass 1's samples too): measured over
 * 0.5 to 0.875 on soft_shadows and thin_occluders at 8, 16 and 32 spp, 0.75 was the best
 * but once, within 2% (docs/benchmarks.md). Pass 1 counts with a balanced rows x cols grid
 * (6 = 2 x 3, 12 = 3 x 4, 24 = 4 x 6) stratify the light better than primes (11, 13). */
#define FSF_BUDGET_PASS1_SHARE 0.75f
/* ... and where FSF filters defocus: the lens filter, after the shading filters, filters
 * nearly every pixel from its stored samples (its collapsed share, the straddlers, is 5-8%
 * and holds 15-22% of the error, against 57% on soft_shadows), so pass 1 keeps more. On
 * defocus and combined at 8, 16 and 32 spp, 0.875 was up to 12% better than 0.75, at worst
 * 0.5% worse (combined at 16: 8.6e-4 with 0.75, 8.0e-4 with 0.875, fixed count 8.4e-4). */
#define FSF_BUDGET_PASS1_SHARE_LENS 0.875f

/* Whether a pixel's filter (FsfPixel) has collapsed. */
bool fsf_pixel_collapsed(const FsfPixel *px);

/* collapsed[i] |= 1 where the soft-shadow filter leaves pixel i unfiltered, from the store's
 * pass-1 samples and the guides as the filter will see them (usable: samples, a surface, not
 * mixed; share: FSF's light's share of the pixel's light, NULL: all). false when out of
 * memory. */
bool fsf_shadow_collapsed(const GBuffer *g, const SampleStore *st, const FsfLight *light, const float *share, float mu,
                          unsigned char *collapsed);
/* The same for the indirect light's filter. false when out of memory or the store lacks the
 * bounce or indirect field. */
bool fsf_bounce_collapsed(const GBuffer *g, const SampleStore *st, float mu, unsigned char *collapsed);

/* The totals: spp_now[i] plus an even share of the room (budget * n minus the samples so far)
 * at the collapsed pixels, at most (ratio - 1) * pass1_spp each, the rest spread evenly over
 * the others; integers by error diffusion in scan order (per class), within a sample of the
 * room in all (the pipeline scales the extras to the budget exactly). No room: spp_total =
 * spp_now. */
void fsf_budget_plan(const unsigned char *collapsed, size_t n, int pass1_spp, int budget_spp, float ratio,
                     const float *spp_now, int *spp_total);

#endif
