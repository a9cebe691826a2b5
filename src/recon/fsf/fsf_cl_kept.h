/* A device buffer that FSF's OpenCL runs keep from one run to the next (fsf_cl.c's scratch,
 * fsf_flat_cl.c's): host memory from huge_pages_alloc, used in place by the device
 * (CL_MEM_USE_HOST_PTR), made anew only when a run needs more than it holds. A frame's later
 * runs then write pages touched before instead of fresh ones (docs/benchmarks.md, "FSF's time
 * outside its kernels"). */
#ifndef WEDGE_RECON_FSF_CL_KEPT_H
#define WEDGE_RECON_FSF_CL_KEPT_H

#include <stddef.h>

#include "recon/cl/cl_runtime_internal.h"

typedef struct {
    cl_mem mem;  /* NULL until the first fsf_cl_kept_get */
    void *host;  /* mem's memory */
    size_t bytes;
} FsfClKept;

/* k's buffer with at least `bytes`, owned by k (NULL with *err set when it cannot be made).
 * Replacing a smaller one releases it: no command may still use it (the runs end with
 * clFinish). */
cl_mem fsf_cl_kept_get(cl_context ctx, FsfClKept *k, size_t bytes, cl_int *err);
void fsf_cl_kept_free(FsfClKept *k);

#endif
