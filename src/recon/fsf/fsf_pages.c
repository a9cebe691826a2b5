/* FSF's large arrays in 2 MB pages (fsf_pages.h). */
#include "recon/fsf/fsf_pages.h"

#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>

enum { FSF_SMALL_PAGE = 4096 };
#define FSF_HUGE_PAGE ((size_t)2 << 20)

void *fsf_pages_alloc(size_t bytes)
{
    if (bytes == 0) bytes = 1;
    size_t align = bytes >= FSF_HUGE_PAGE ? FSF_HUGE_PAGE : FSF_SMALL_PAGE;
    if (bytes > SIZE_MAX - align) return NULL;
    /* aligned_alloc wants a multiple of the alignment: the rounding is address space only, the
     * tail past `bytes` is never touched */
    void *p = aligned_alloc(align, (bytes + align - 1) / align * align);
#ifdef MADV_HUGEPAGE
    /* the whole 2 MB pages inside [p, p + bytes): p is 2 MB aligned here. A refusal (EINVAL
     * where the kernel has no transparent huge pages) leaves ordinary pages: nothing to undo */
    size_t whole = bytes / FSF_HUGE_PAGE * FSF_HUGE_PAGE;
    if (p && whole > 0) (void)madvise(p, whole, MADV_HUGEPAGE);
#endif
    return p;
}
