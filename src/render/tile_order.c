#include "render/tile_order.h"

#include <stdlib.h>

/* qsort's comparison: the longer tile first, the lower index on a tie. A NaN (no estimate)
 * compares as shorter than any number, so the order stays total. */
static int longest_first(const void *pa, const void *pb)
{
    const TileCost *a = pa, *b = pb;
    double sa = a->seconds == a->seconds ? a->seconds : -1.0 / 0.0;
    double sb = b->seconds == b->seconds ? b->seconds : -1.0 / 0.0;
    if (sa != sb) return sa > sb ? -1 : 1;
    return (a->tile > b->tile) - (a->tile < b->tile);
}

void tile_order_longest_first(const double *seconds, int count, TileCost *scratch, int *order)
{
    for (int i = 0; i < count; ++i) scratch[i] = (TileCost){seconds[i], i};
    qsort(scratch, (size_t)count, sizeof *scratch, longest_first);
    for (int i = 0; i < count; ++i) order[i] = scratch[i].tile;
}
