/* Large arrays that FSF writes once per frame, backed by 2 MB pages where the system allows.
 *
 * A one-frame render touches FSF's arrays for the first time in that frame: the samples' light
 * coordinates and scaled values, the tap tables, P and G, about 50-60 MB at 256x256 and 16 spp.
 * At 4 KB a page that is 13,000-15,000 page faults, each 2-4 us of system time on the bench
 * machine (allocating, clearing and accounting one page; docs/benchmarks.md, "FSF's fresh
 * memory in 2 MB pages"). Where transparent huge pages are available on request
 * (/sys/kernel/mm/transparent_hugepage/enabled "madvise" or "always"), the whole 2 MB pages of
 * such an array are asked for as huge pages (madvise MADV_HUGEPAGE): one fault clears 2 MB, so
 * the per-page work is done 512 times less often. The tail beyond the last whole 2 MB page, and
 * every array below 2 MB, keeps ordinary pages (rounding up would clear memory that is never
 * used). Without the advice (another system, "never") these are ordinary page-aligned arrays.
 * The contents are undefined, as malloc's. */
#ifndef WEDGE_RECON_FSF_PAGES_H
#define WEDGE_RECON_FSF_PAGES_H

#include <stddef.h>

/* bytes (at least 1) aligned to 2 MB when at least 2 MB, else to 4 KB (page aligned either way,
 * so an OpenCL CPU device can use it in place); NULL when out of memory. Free with free(). */
void *fsf_pages_alloc(size_t bytes);

#endif
