/* FSF's per-frame arrays (fsf_scratch.h). */
#include "recon/fsf/fsf_scratch.h"

#include <stdlib.h>

#include "core/huge_pages.h"

/* Page aligned, in 2 MB pages where large (huge_pages.h); freed with free(). */
static void *alloc_device_input(size_t bytes) { return huge_pages_alloc(bytes); }

bool fsf_scratch_alloc(FsfScratch *s, size_t n, int capacity)
{
    size_t slots = n * (size_t)(capacity > 0 ? capacity : 0);
    s->usable = alloc_device_input(n);
    s->count = alloc_device_input(n * sizeof(int));
    /* at least one slot's floats: fsf_cl_run uploads one for an empty store */
    s->y = alloc_device_input((slots + 1) * 2 * sizeof(float)), s->v = NULL; /* fsf_scratch_values */
    s->k_lo = malloc(n * sizeof(float)), s->k_hi = malloc(n * sizeof(float)), s->out4 = malloc(n * 4 * sizeof(float));
    s->mean_g = alloc_device_input(n * sizeof(float));
    s->px = alloc_device_input(n * sizeof(FsfPixel));
    if (s->usable && s->count && s->y && s->k_lo && s->k_hi && s->out4 && s->mean_g && s->px) return true;
    fsf_scratch_free(s);
    return false;
}

void fsf_scratch_free(FsfScratch *s)
{
    free(s->usable), free(s->count), free(s->y), free(s->v), free(s->k_lo), free(s->k_hi), free(s->out4);
    free(s->mean_g), free(s->px);
    *s = (FsfScratch){0};
}

bool fsf_scratch_values(FsfScratch *s, size_t n, int capacity)
{
    size_t slots = n * (size_t)(capacity > 0 ? capacity : 0);
    if (!s->v) s->v = alloc_device_input((slots + 1) * 3 * sizeof(float)); /* one slot at least, as y */
    return s->v != NULL;
}
