/* FSF's extra samples for defocus straddlers (fsf_lens_plan.h). */
#include "recon/fsf/fsf_lens_plan.h"

#include <stdlib.h>

#include "recon/fsf/fsf_lens.h"

bool fsf_lens_straddlers(const GBuffer *g, const SampleStore *st, float mu, bool black_background, FsfPixel *px,
                         float *k_lo, float *k_hi, unsigned char *straddle)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    unsigned char *usable = malloc(n);
    bool ok = usable != NULL;
    for (size_t i = 0; ok && i < n; ++i) usable[i] = sample_store_count(st, i) > 0;
    FsfLensIn in = {g, st, usable, mu, black_background};
    ok = ok && fsf_lens_params(&in, px, k_lo, k_hi);
    for (size_t i = 0; ok && i < n; ++i) straddle[i] = fsf_lens_straddles(k_lo[i], k_hi[i]);
    free(usable);
    return ok;
}

void fsf_lens_plan(const unsigned char *straddle, size_t n, int pass1_spp, int extra_spp, const float *spp_now,
                   int *spp_total)
{
    for (size_t i = 0; i < n; ++i) {
        int now = (int)spp_now[i], want = straddle[i] ? pass1_spp + extra_spp : now;
        spp_total[i] = want > now ? want : now;
    }
}
