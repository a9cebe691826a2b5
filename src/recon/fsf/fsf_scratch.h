/* The per-pixel and per-slot arrays of an FSF filtering (its samples, parameters and output),
 * allocated once per frame and written anew by each user in turn: the plan's areas
 * (fsf_budget_plan.h), then the filterings of the frame's effects (shadows, indirect light,
 * defocus). Pages the plan or an earlier filtering touched cost no page fault in a later one
 * (a fault took about 2-4 us on the bench machine, thousands of them a filtering at 256x256:
 * docs/benchmarks.md, "FSF's time outside its kernels"). No user may read what it did not
 * write: each array holds the last writer's values. */
#ifndef WEDGE_RECON_FSF_SCRATCH_H
#define WEDGE_RECON_FSF_SCRATCH_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/fsf/fsf_filter.h"

typedef struct {
    unsigned char *usable; /* n */
    int *count;            /* n */
    float *y;              /* 2 floats per slot (at least one slot) */
    float *v;              /* 3 floats per slot: allocated only by fsf_scratch_values (NULL until
                            * then): the filters that read a sample's light (shadows, defocus) ask
                            * for it, the indirect light's (fsf_flat.h: a pixel's value) does not */
    float *k_lo, *k_hi;    /* n */
    float *out4;           /* 4 n */
    float *mean_g;         /* n (form 4's per-pixel means, fsf_geo_term.h) */
    FsfPixel *px;          /* n */
} FsfScratch;

/* For n pixels of `capacity` slots each. The arrays the OpenCL passes read in place
 * (fsf_cl_run's CL_MEM_USE_HOST_PTR: usable, count, y, v, mean_g, px) are page aligned, else a
 * CPU device would copy them (PoCL's base address alignment is 128 bytes on this machine; a page
 * is safe for any device). false (nothing left allocated) when out of memory. */
bool fsf_scratch_alloc(FsfScratch *s, size_t n, int capacity);
/* s->v for the same n and capacity, allocated (page aligned) at the first call; false (s->v
 * NULL, the rest kept) when out of memory. */
bool fsf_scratch_values(FsfScratch *s, size_t n, int capacity);
void fsf_scratch_free(FsfScratch *s);

#endif
