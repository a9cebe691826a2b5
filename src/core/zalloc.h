/* Zeroed buffers that render threads will accumulate into.
 *
 * calloc hands out fresh pages that the kernel maps to its shared zero page on first read;
 * the first write after that is a copy-on-write fault, and in a multi-threaded process each
 * one also flushes the page from every core's TLB (an inter-processor interrupt). Per-pixel
 * sums (`sum[i] += x`) read before they write, so every page of every such buffer took that
 * path inside the render threads: measured 8-10% of an AAF frame's CPU time in the kernel.
 * zalloc backs every page with a written one on the calling thread, before any worker
 * starts: calloc's zeros, then madvise(MADV_POPULATE_WRITE) over its pages (one system call;
 * a memset of the zeros where the kernel lacks it, before Linux 5.14). */
#ifndef WEDGE_CORE_ZALLOC_H
#define WEDGE_CORE_ZALLOC_H

#include <stddef.h>

/* count * size zero bytes, already backed by written pages; NULL when out of memory (or on
 * overflow). Free with free(). */
void *zalloc(size_t count, size_t size);

#endif
