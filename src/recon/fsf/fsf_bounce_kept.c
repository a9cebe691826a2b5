/* The plan's indirect-light parameters kept for the filter (fsf_bounce_kept.h). */
#include "recon/fsf/fsf_bounce_kept.h"

#include <stdlib.h>
#include <string.h>

void fsf_bounce_kept_free(FsfBounceKept *kept)
{
    free(kept->px), free(kept->k_lo), free(kept->k_hi), free(kept->count);
    memset(kept, 0, sizeof *kept);
}

void fsf_bounce_keep(FsfBounceKept *kept, const SampleStore *st, const FsfPixel *px, const float *k_lo,
                     const float *k_hi, size_t n)
{
    if (kept->n != n) fsf_bounce_kept_free(kept);
    if (!kept->px) {
        kept->px = malloc(n * sizeof *kept->px);
        kept->k_lo = malloc(n * sizeof(float)), kept->k_hi = malloc(n * sizeof(float));
        kept->count = malloc(n * sizeof(int));
        kept->n = n;
    }
    if (!kept->px || !kept->k_lo || !kept->k_hi || !kept->count) {
        fsf_bounce_kept_free(kept);
        return;
    }
    memcpy(kept->px, px, n * sizeof *px);
    memcpy(kept->k_lo, k_lo, n * sizeof(float)), memcpy(kept->k_hi, k_hi, n * sizeof(float));
    for (size_t i = 0; i < n; ++i) kept->count[i] = sample_store_count(st, i);
}

bool fsf_bounce_kept_take(const FsfBounceKept *kept, const SampleStore *st, FsfPixel *px, float *k_lo, float *k_hi,
                          size_t n)
{
    if (!kept->px || kept->n != n) return false;
    for (size_t i = 0; i < n; ++i)
        if (kept->count[i] != sample_store_count(st, i)) return false;
    memcpy(px, kept->px, n * sizeof *px);
    memcpy(k_lo, kept->k_lo, n * sizeof(float)), memcpy(k_hi, kept->k_hi, n * sizeof(float));
    return true;
}
