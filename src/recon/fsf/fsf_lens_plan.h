/* FSF's extra samples for defocus (FSF section 5, "Adaptive Sampling for Depth of Field"):
 * a pixel whose lens-slope range straddles the focal plane (fsf_lens_straddles) cannot be
 * sheared, is filtered axis-aligned and narrowly (often not at all: it keeps its mean), so
 * it gets a fixed number of samples more in a second pass; every other pixel keeps pass 1's.
 *
 * The decision is fsf_lens_params' own: the plan computes the lens parameters from the store,
 * which keeps pass 1's samples only, and the filter reuses them (fsf_method.c), so the pixels
 * given samples are the pixels filtered axis-aligned. The extra samples
 * reach the image through the pixel's mean (the composite value4 its stored samples are
 * scaled to, fsf_match_pixel); the store does not keep them (sample_store.h counts them as
 * dropped): a neighbour's taps see pass 1's samples as before. */
#ifndef WEDGE_RECON_FSF_LENS_PLAN_H
#define WEDGE_RECON_FSF_LENS_PLAN_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/fsf/fsf_filter.h"
#include "recon/gbuffer.h"
#include "recon/sample_store.h"

/* FSF section 5 adds 36 samples to such pixels (about 2.2 more per pixel on average in the
 * paper's scene). Measured here over 0/16/36/64 (docs/benchmarks.md, "FSF: extra samples where
 * defocus straddles the focal plane"). */
#define FSF_LENS_STRADDLE_EXTRA_SPP 36

/* fsf_lens_params over the store's samples with every pixel that has one usable (as
 * fsf_lens_samples has it for the composite radiance, whose weight is 1), and straddle[i] = 1
 * where pixel i's range straddles the focal plane, else 0 (black_background: FsfLensIn's). false
 * when out of memory or the store lacks the depth field. */
bool fsf_lens_straddlers(const GBuffer *g, const SampleStore *st, float mu, bool black_background, FsfPixel *px,
                         float *k_lo, float *k_hi, unsigned char *straddle);

/* The plan: spp_total[i] = max(spp_now[i], pass1_spp + extra_spp) at straddling pixels,
 * spp_now[i] elsewhere. */
void fsf_lens_plan(const unsigned char *straddle, size_t n, int pass1_spp, int extra_spp, const float *spp_now,
                   int *spp_total);

#endif
