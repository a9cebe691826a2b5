/* LR's samples of a window sorted by depth layer (Algorithm 1's visiting order).
 *
 * The reprojection of layer j reads the window's samples of layer j (opacity, weight and
 * irradiance) and of every layer behind it (weight only: they were seen through layer j).
 * Sorted by raw layer once per tile, both are contiguous ranges of one list, so a layer's
 * loop touches no sample in front of it (before this, 38% of the samples a layer visited on
 * the hard bench scene were in front and skipped one by one). The sort is a counting sort:
 * stable, so within a layer the samples keep the window's pixel-major order. lr.cl's
 * lr_tile_stats builds the same lists on the device; lr_reconstruct.c uses this one. */
#ifndef WEDGE_RECON_LR_BUCKET_H
#define WEDGE_RECON_LR_BUCKET_H

/* Flag on a raw layer id: the sample's radiance is not finite; it is left out of the lists
 * (counted once by the caller, never reprojected). lr.cl's LR_SKIP. */
enum { LR_LAYER_SKIP = 0x80 };

/* ids[i], i < n: the raw layer (< raw_n <= 127) of window sample i, possibly flagged
 * LR_LAYER_SKIP. Writes start[r], r = 0..raw_n: raw layer r's samples are
 * order[start[r] .. start[r + 1]), ascending window sample indices; start[raw_n] is the number
 * of listed (finite) samples, which is what order[] needs room for. */
void lr_bucket_by_layer(const unsigned char *ids, int n, int raw_n, int *start, int *order);

#endif
