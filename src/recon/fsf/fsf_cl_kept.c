/* FSF's kept device buffers (fsf_cl_kept.h). */
#include "recon/fsf/fsf_cl_kept.h"

#include <stdlib.h>

#include "core/huge_pages.h"

cl_mem fsf_cl_kept_get(cl_context ctx, FsfClKept *k, size_t bytes, cl_int *err)
{
    if (k->mem && k->bytes >= bytes) return k->mem;
    fsf_cl_kept_free(k);
    if (!(k->host = huge_pages_alloc(bytes))) {
        *err = CL_OUT_OF_HOST_MEMORY;
        return NULL;
    }
    k->mem = clCreateBuffer(ctx, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, bytes, k->host, err);
    k->bytes = k->mem ? bytes : 0;
    return k->mem;
}

void fsf_cl_kept_free(FsfClKept *k)
{
    if (k->mem) clReleaseMemObject(k->mem);
    free(k->host);
    *k = (FsfClKept){0};
}
