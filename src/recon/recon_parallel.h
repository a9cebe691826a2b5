/* A two-way parallel for over an index range, for the reconstruction stage's per-pixel host
 * work (DESIGN.md section 7: two cores). Every caller writes only the entries of its own
 * range (and its own slot of any per-part reduction), so results do not depend on the split. */
#ifndef WEDGE_RECON_RECON_PARALLEL_H
#define WEDGE_RECON_RECON_PARALLEL_H

#include <stddef.h>

enum { RECON_PARTS = 2 };

/* fn(ctx, begin, end, part) for part = 0 .. RECON_PARTS-1 over consecutive ranges covering
 * [0, n); part 0 runs on the calling thread. Small ranges (or a failed thread start) run on
 * the calling thread, still one call per part. */
typedef void (*ReconRangeFn)(void *ctx, size_t begin, size_t end, int part);
void recon_parallel_for(size_t n, ReconRangeFn fn, void *ctx);
/* The same for a few heavy items (e.g. whole tables): work_items (the total of their sizes)
 * decides whether threads are worth starting. */
void recon_parallel_for_work(size_t n, size_t work_items, ReconRangeFn fn, void *ctx);

#endif
