/* Counting sort of a window's samples by raw layer (see lr_bucket.h). */
#include "recon/lr/lr_bucket.h"

void lr_bucket_by_layer(const unsigned char *ids, int n, int raw_n, int *start, int *order)
{
    for (int r = 0; r <= raw_n; ++r) start[r] = 0;
    for (int i = 0; i < n; ++i)
        if (!(ids[i] & LR_LAYER_SKIP)) start[ids[i] + 1]++;
    for (int r = 0; r < raw_n; ++r) start[r + 1] += start[r]; /* counts -> first slots */
    int next[128];
    for (int r = 0; r < raw_n; ++r) next[r] = start[r];
    for (int i = 0; i < n; ++i)
        if (!(ids[i] & LR_LAYER_SKIP)) order[next[ids[i]]++] = i;
}
