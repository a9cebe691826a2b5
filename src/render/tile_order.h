/* The order in which a round of a pass hands its tiles to the render threads (issue 22).
 * Every round ends when its last tile does, so a thread that takes a long tile late leaves
 * the others idle at the round's barrier. Handing out the longest tiles first (Graham's
 * "longest processing time first" list schedule, SIAM J. Appl. Math. 17(2), 1969) leaves
 * short tiles for the end. A tile's cost is unknown before it runs, but a pixel's samples
 * cost about the same from one round of a pass to the next (same scene, same pixels), so the
 * round before is the estimate. Only the order changes: each tile is the same work whichever
 * thread runs it, so images and counters are bit for bit those of row-major order. */
#ifndef WEDGE_RENDER_TILE_ORDER_H
#define WEDGE_RENDER_TILE_ORDER_H

/* order[0 .. count) := the tiles 0 .. count-1 sorted by seconds[tile], largest first; equal
 * seconds keep the lower tile first (so all-equal costs give row-major order). NaN counts as
 * the smallest. scratch holds count entries. */
typedef struct {
    double seconds;
    int tile;
} TileCost;

void tile_order_longest_first(const double *seconds, int count, TileCost *scratch, int *order);

#endif
