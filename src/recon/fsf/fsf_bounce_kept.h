/* The plan's indirect-light parameters kept for the filter (fsf_method.c).
 *
 * Under a budget the plan finds each pixel's indirect-light widths (fsf_bounce_params) from pass
 * 1's stored samples, and the store keeps no later sample (the pipeline fills it in pass 1), so
 * the filter can take them rather than find them again from the same samples: the slope windows,
 * the coordinates and the widths were the indirect frame's largest CPU after the trace (fsf12,
 * docs/benchmarks.md). What the filter does not see then is pass 2's change to the guides of the
 * pixels it gave extras (their mean normals and positions): measured, relMSE within 0.15% on the
 * bench scenes. The parameters are taken only while the store's counts equal those they were
 * found from. */
#ifndef WEDGE_RECON_FSF_BOUNCE_KEPT_H
#define WEDGE_RECON_FSF_BOUNCE_KEPT_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/fsf/fsf_filter.h"
#include "recon/sample_store.h"

typedef struct {
    FsfPixel *px;          /* NULL: nothing kept */
    float *k_lo, *k_hi;
    int *count;            /* the store's counts they were found from */
    size_t n;
} FsfBounceKept;

/* Keeps n pixels' px, k_lo, k_hi with st's counts; on out of memory nothing is kept. */
void fsf_bounce_keep(FsfBounceKept *kept, const SampleStore *st, const FsfPixel *px, const float *k_lo,
                     const float *k_hi, size_t n);
/* The kept parameters into px, k_lo, k_hi when some are kept for n pixels and st's counts equal
 * theirs: true; else false and nothing written. */
bool fsf_bounce_kept_take(const FsfBounceKept *kept, const SampleStore *st, FsfPixel *px, float *k_lo, float *k_hi,
                          size_t n);
void fsf_bounce_kept_free(FsfBounceKept *kept);

#endif
