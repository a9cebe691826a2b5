/* Zeroed, pre-faulted buffers (see zalloc.h). */
#include "core/zalloc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

void *zalloc(size_t count, size_t size)
{
    if (size != 0 && count > SIZE_MAX / size) return NULL;
    size_t bytes = count * size;
    /* calloc's memory reads as zero already (fresh pages from mmap, or a reused block it
     * clears); what is left is to back every page with a written one before the workers
     * start. MADV_POPULATE_WRITE (Linux 5.14) faults them in writable in one system call
     * instead of one fault per page from a memset. The range is widened to whole pages:
     * its first and last pages hold bytes of this block, so they lie in a mapping, and
     * populating a page never changes its contents. Without that flag (an older kernel:
     * EINVAL), zeros written by hand fault the pages in as before. */
    void *p = calloc(bytes ? bytes : 1, 1);
    if (!p || bytes == 0) return p;
#ifdef MADV_POPULATE_WRITE
    long page = sysconf(_SC_PAGESIZE);
    if (page > 0) {
        uintptr_t mask = (uintptr_t)page - 1;
        uintptr_t first = (uintptr_t)p & ~mask, end = ((uintptr_t)p + bytes + mask) & ~mask;
        if (madvise((void *)first, end - first, MADV_POPULATE_WRITE) == 0) return p;
    }
#endif
    memset(p, 0, bytes);
    return p;
}
