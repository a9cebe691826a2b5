/* Large arrays written once per frame, backed by 2 MB pages where the system has them free.
 *
 * A one-frame render touches its large per-frame arrays for the first time in that frame: FSF's
 * samples, tap tables, P and G and slope windows (50-60 MB at 256x256 and 16 spp), the
 * pipeline's per-sample store (tens of MB under FSF and LR). At 4 KB a page that is tens of
 * thousands of page faults a frame, each 2-4 us of system time on the bench machine beyond the
 * zeroing itself (docs/benchmarks.md, "FSF's filter share, third round"). Where transparent huge
 * pages are available on request (/sys/kernel/mm/transparent_hugepage/enabled "madvise" or
 * "always"), the whole 2 MB pages of such an array are asked for as huge pages (madvise
 * MADV_HUGEPAGE): one fault per 2 MB.
 *
 * The guard: with `defrag` "madvise" a huge-page fault that finds no free 2 MB block compacts
 * memory synchronously, and on a machine whose memory other jobs had fragmented that cost more
 * than the faults it saved (LR's huge pages, docs/benchmarks.md "lrcost8": system time 2x at
 * 512x384). So the advice is given only while /proc/buddyinfo lists at least HUGE_PAGES_SPARE
 * free 2 MB blocks beyond twice the array's own: then the faults take free blocks and never
 * compact. Otherwise (and where the file or the advice is missing) the array keeps 4 KB pages.
 * The tail past the last whole 2 MB page, and every array below 2 MB, keeps 4 KB pages
 * (rounding up would clear memory that is never used). The contents are undefined, as malloc's. */
#ifndef WEDGE_CORE_HUGE_PAGES_H
#define WEDGE_CORE_HUGE_PAGES_H

#include <stddef.h>

/* Free 2 MB blocks the guard wants beyond twice an array's own (512 MB) */
#define HUGE_PAGES_SPARE 256

/* bytes (at least 1) aligned to 2 MB when at least 2 MB, else to 4 KB (page aligned either way,
 * so an OpenCL CPU device can use it in place); NULL when out of memory. Free with free(). */
void *huge_pages_alloc(size_t bytes);

/* bytes (at least 1) from malloc, its start where malloc puts it, with the whole 2 MB pages inside
 * advised as huge pages under the same guard; NULL when out of memory. Free with free(). For
 * arrays read in step with others at the same index: a start on a 2 MB boundary made LR's
 * gather over the per-sample store's fields 10-15% slower (docs/benchmarks.md, "The per-sample
 * store in 2 MB pages"), malloc's start did not. */
void *huge_pages_malloc(size_t bytes);

/* The free 2 MB blocks in a /proc/buddyinfo text (each zone's free blocks of order 9 and above,
 * an order-k block counting 2^(k - 9)); -1 when the text has no zone line. */
long huge_pages_free_blocks(const char *buddyinfo);

#endif
