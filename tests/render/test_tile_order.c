/* tile_order_longest_first, the order a pass's later rounds hand their tiles out in (issue 22):
 *  - against a brute-force selection (repeatedly the largest cost left, the lowest tile on a
 *    tie) on pseudo-random costs with many ties, NaNs and zeros, for counts 0 to 300;
 *  - all-equal costs give row-major order (the first round's order);
 *  - the result is a permutation of 0 .. count-1.
 * Teeth: shortest first, the tie broken the other way, NaN taken as the largest, or a tile
 * lost in the copy each fail the brute-force comparison. */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "check.h"
#include "render/tile_order.h"

enum { MAX_TILES = 300 };

/* The longest tile not yet taken, NaN below every number, the lowest index on a tie. */
static void brute_force(const double *seconds, int count, int *order)
{
    bool taken[MAX_TILES] = {false};
    for (int k = 0; k < count; ++k) {
        int best = -1;
        for (int i = 0; i < count; ++i) {
            if (taken[i]) continue;
            if (best < 0) { best = i; continue; }
            bool i_nan = isnan(seconds[i]), b_nan = isnan(seconds[best]);
            if (i_nan) continue; /* a NaN never beats an earlier tile */
            if (b_nan || seconds[i] > seconds[best]) best = i;
        }
        taken[best] = true;
        order[k] = best;
    }
}

static unsigned next_random(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

int main(void)
{
    double seconds[MAX_TILES];
    int order[MAX_TILES], expect[MAX_TILES];
    TileCost scratch[MAX_TILES];
    unsigned state = 12345u;
    for (int count = 0; count <= MAX_TILES; count += (count < 20 ? 1 : 7)) {
        for (int trial = 0; trial < 4; ++trial) {
            for (int i = 0; i < count; ++i) {
                unsigned r = next_random(&state);
                /* few distinct values (ties), some NaN and zero costs */
                seconds[i] = r % 11 == 0 ? NAN : r % 13 == 0 ? 0.0 : (double)(r % 17) * 1e-3;
            }
            tile_order_longest_first(seconds, count, scratch, order);
            brute_force(seconds, count, expect);
            bool seen[MAX_TILES] = {false}, permutation = true, same = true;
            for (int k = 0; k < count; ++k) {
                if (order[k] < 0 || order[k] >= count || seen[order[k]]) permutation = false;
                else seen[order[k]] = true;
                if (order[k] != expect[k]) same = false;
            }
            CHECK(permutation);
            CHECK(same);
        }
    }
    /* equal costs: row-major */
    for (int i = 0; i < 256; ++i) seconds[i] = 2e-3;
    tile_order_longest_first(seconds, 256, scratch, order);
    bool row_major = true;
    for (int k = 0; k < 256; ++k) row_major = row_major && order[k] == k;
    CHECK(row_major);
    return check_failures ? 1 : 0;
}
