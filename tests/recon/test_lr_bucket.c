/* LR's window samples sorted by layer (src/recon/lr/lr_bucket.c) against a brute-force
 * listing: every finite sample lands in exactly one bucket, its own layer's; within a bucket
 * the window's order is kept (ascending indices, the pixel-major order the reprojection
 * summed in before the sort); flagged (non-finite) samples are in none; empty layers give
 * empty ranges. Random layer ids, several sizes and layer counts, and the edge cases of an
 * empty window and a window whose samples are all flagged. */
#include <stdlib.h>

#include "../check.h"
#include "recon/lr/lr_bucket.h"

static unsigned next_u32(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

static void check_buckets(const unsigned char *ids, int n, int raw_n)
{
    int start[128 + 1];
    int *order = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    lr_bucket_by_layer(ids, n, raw_n, start, order);
    int finite = 0;
    for (int i = 0; i < n; ++i) finite += !(ids[i] & LR_LAYER_SKIP);
    CHECK(start[0] == 0 && start[raw_n] == finite);
    int bad_range = 0, bad_list = 0;
    for (int r = 0; r < raw_n; ++r) {
        bad_range += start[r + 1] < start[r];
        /* brute force: the samples of layer r, in window order */
        int e = start[r];
        for (int i = 0; i < n; ++i)
            if (ids[i] == r) bad_list += e >= start[r + 1] || order[e++] != i;
        bad_list += e != start[r + 1]; /* nothing else in the bucket */
    }
    CHECK(bad_range == 0);
    CHECK(bad_list == 0);
    /* exactly once over all buckets */
    int *seen = calloc((size_t)(n > 0 ? n : 1), sizeof(int)), twice = 0, flagged = 0;
    for (int e = 0; e < start[raw_n]; ++e) {
        twice += seen[order[e]]++ != 0;
        flagged += (ids[order[e]] & LR_LAYER_SKIP) != 0;
    }
    CHECK(twice == 0 && flagged == 0);
    free(seen);
    free(order);
}

int main(void)
{
    unsigned state = 17;
    int sizes[4] = {1, 7, 32 * 32 * 8, 20 * 13 * 3};
    int layers[4] = {1, 3, 17, 9};
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            int n = sizes[a], raw_n = layers[b];
            unsigned char *ids = malloc((size_t)n);
            for (int i = 0; i < n; ++i) {
                int r = (int)(next_u32(&state) % (unsigned)raw_n);
                if (raw_n > 2 && r == 1) r = 0; /* keep layer 1 empty */
                ids[i] = (unsigned char)(r | (next_u32(&state) % 10 == 0 ? LR_LAYER_SKIP : 0));
            }
            check_buckets(ids, n, raw_n);
            free(ids);
        }
    unsigned char all_flagged[5] = {LR_LAYER_SKIP, LR_LAYER_SKIP | 2, LR_LAYER_SKIP | 1, LR_LAYER_SKIP, LR_LAYER_SKIP | 2};
    check_buckets(all_flagged, 5, 3);
    check_buckets(NULL, 0, 4);
    CHECK_DONE();
}
