/* LR (layered reconstruction, seeds/004) kernels: the partitions' statistics (lr_tile_stats;
 * the host turns them into filters, lr_partition.c: lr_tile_finish), Algorithm 1
 * (reprojection, eq. 16), Algorithm 2 (separable screen filter along / across the layer's
 * motion) and eq. 17 (front-to-back compositing). The plain C version of the same steps is
 * lr_reconstruct.c, which the tests compare against (bit for bit on PoCL).
 *
 * Buffers (host layout in lr_cl.c):
 *   samples       8 floats per sample (LrPlace: x, y, u, v, t, r, g, b), pixel-major, spp per
 *                 pixel: what the reprojection reads (lr_pack_tile, lr_reproject_layer)
 *   keys          a float4 per sample (LrKey: depth, CoC, motion x, y), the same order: what
 *                 the statistics read (lr_block_stats, lr_tile_stats); bright: r + g + b per
 *                 sample, NaN for a non-finite radiance (lr_partition.h: lr_bright)
 *   tile_bounds   LR_TB_STRIDE floats per tile: n_depth, n_coc, 15 depth bounds, 15 CoC bounds
 *   tile_layers   LR_TL_STRIDE ints per tile: layer_count, then raw layer -> compact layer
 *   params        LR_LP_STRIDE floats per (tile, layer): cos psi, sin psi, 1/sigma_x, eta, xi,
 *                 1/sigma_u, 1/sigma_t, 1/sigma_y, rho, 1/sigma_v, radius_x, radius_y, the shift of
 *                 the layer's own samples (ramp x, y: lr_partition.h, LrLayer), then the
 *                 screen filter's tap weights exp(-(k / sigma)^2 / 2), k = 0..32, along (x)
 *                 and across (y): computed once per partition on the host, not per tap; then
 *                 the round filter's flag (LR_ROUND: 1 for a layer filtered by one 2D table,
 *                 lr_taps.h: lr_screen_round) and its table over dx^2 + dy^2 (LR_ROUND_T);
 *                 then (LR_BAND) per band class, narrow and wide, the index of its record in
 *                 class_params, or -1 where the frame's filter serves the class's pixels
 *   class_params  LR_LP_STRIDE floats per record: a still layer's screen filter at a band
 *                 class's band (1/sigma_x, radii, taps, round flag and table at the offsets of params;
 *                 lr_band_class.h, docs/algorithms.md 8.40)
 *   band_class    a byte per pixel of the image: its band class (0 the frame's band, 1
 *                 narrow, 2 wide), read only for a layer with class records
 *   pass1_class   two grids per tile of the batch: the along pass of the narrow and of the
 *                 wide class's filter, for a layer with those records
 *   block_hist    LR_BH_STRIDE ints per 8x8 block of pixels (row-major, nbx per row): the CoC
 *                 histogram of its hits, then how many of them move (0 unless the moving hits
 *                 are counted: lr_config_counts_moving; lr_block_stats); block_z:
 *                 their depth range, 2 floats
 *   layer_ids     window_px^2 * spp bytes per tile: the raw layer of every window sample
 *                 (lr_tile_stats), with the flag LR_SKIP for a non-finite radiance
 *   order         window_px^2 * spp uints per tile: the window's finite samples (their index in
 *                 samples) sorted by raw layer, pixel-major within a layer (lr_bucket.h)
 *   layer_start   LR_LS_STRIDE ints per tile: raw layer r is order[start[r] .. start[r + 1])
 *   packed        per tile of the batch, 5 arrays of window_px^2 * spp floats: x, y, u, v, t of
 *                 the samples of order, in its order (lr_pack_tile)
 *   grid, pass1   window_px^2 cells of 5 floats (opacity, weight, rgb) per tile of the batch
 *                 being filtered (lr_tile_filter: a tile's layers reuse them one after the
 *                 other); the copy and the filter run on a few rows of tiles at a time (tile0
 *                 its first tile), so that these buffers stay small
 *
 * Launch shapes (lr_cl.c): all 2D in fixed 16x4 groups (cl_launch_2d), so that PoCL compiles
 * each kernel once whatever the image size or layer count; every kernel ignores the padding. */

#define LR_PLACE_STRIDE 8 /* LrPlace: x, y, u, v, t, then the radiance at LR_PLACE_L */
#define LR_PLACE_L 5
#define LR_TB_STRIDE 32
#define LR_TB_COC 17 /* tile_bounds: the CoC bounds' first float */
#define LR_TL_STRIDE 18
#define LR_LP_STRIDE 340
#define LR_ROUND 80
#define LR_ROUND_T 81
#define LR_BAND 338 /* two floats: the narrow and the wide class's record in class_params, or -1 */
#define LR_TAPS_X 14
#define LR_TAPS_Y 47
#define LR_SKIP 0x80 /* flag on a layer id: non-finite radiance, not reprojected */
#define LR_CH 5
#define LR_MOVING_PX 1.0f /* lr_partition.h: moving and static samples of a slab are separate layers */
#define LR_CHUNK 32 /* lr_reproject_layer: samples placed before they are summed */
#define LR_LS_STRIDE 18 /* raw layers 0..16, and the end */

typedef struct {
    int x0, y0, x1, y1;
} LrWindow;

/* inset: LrConfig.inset_px, the band read but not reconstructed; tiles start past it */
static LrWindow lr_window(int tx, int ty, int width, int height, int tile_px, int window_px, int inset)
{
    int margin = (window_px - tile_px) / 2;
    int ax = inset + tx * tile_px - margin, ay = inset + ty * tile_px - margin;
    LrWindow w;
    w.x0 = ax < 0 ? 0 : ax;
    w.y0 = ay < 0 ? 0 : ay;
    w.x1 = ax + window_px > width ? width : ax + window_px;
    w.y1 = ay + window_px > height ? height : ay + window_px;
    return w;
}

/* exp(-s / 2), operation for operation lr_reconstruct.h's lr_gauss (see there). */
#define LR_GAUSS_CUT 36.0f
static float lr_gauss(float s)
{
#pragma OPENCL FP_CONTRACT OFF
    if (!(s <= LR_GAUSS_CUT)) return 0.0f;
    float y = -0.72134752f * s;
    float n = floor(y + 0.5f), f = y - n;
    float p = 1.535336188319500e-4f;
    p = p * f + 1.339887440266574e-3f;
    p = p * f + 9.618437357674640e-3f;
    p = p * f + 5.550332471162809e-2f;
    p = p * f + 2.402264791363012e-1f;
    p = p * f + 6.931472028550421e-1f;
    return (1.0f + f * p) * as_float((((int)n + 127) << 23));
}

#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double lr_sum; /* as lr_partition.c sums the motion: the same psi, bit for bit */
#else
typedef float lr_sum; /* a device without doubles: psi may differ from the C version's in the last bits */
#endif

/* lr_partition.h: lr_key_moving */
static bool lr_moving(float mx, float my) { return mx * mx + my * my >= LR_MOVING_PX * LR_MOVING_PX; }

#define LR_ST_STRIDE 18 /* per raw layer: count, cos psi, sin psi, c_min, c_max, d_min, d_max, across, brightness sum,
                          * then the tilt's nine sums (lr_partition.h: LrTilt) */

/* lr_tile_raw_count: the raw layers of a tile with these bounds (the slabs split into moving
 * and static layers when 2 slabs + 1 ids fit in 17). */
static int lr_raw_count(int n_depth, int n_coc)
{
    int slabs = n_depth + n_coc + 1;
    return 2 * slabs + 1 <= 17 ? 2 * slabs + 1 : slabs + 1;
}

/* Same rule as lr_tile_raw_layer, on the tile's own bounds array: slab k's moving samples are
 * raw layer 2k, its static ones 2k + 1, when they split; misses last. */
static int lr_raw_layer(const float *tb, float depth, float coc, float mx, float my)
{
    int n_depth = (int)tb[0], n_coc = (int)tb[1];
    int raw_n = lr_raw_count(n_depth, n_coc);
    bool split = raw_n > n_depth + n_coc + 2;
    if (!(depth < INFINITY)) return raw_n - 1;
    int k = 0;
    for (int i = 0; i < n_depth; ++i) k += depth > tb[2 + i];
    for (int i = 0; i < n_coc; ++i) k += coc > tb[LR_TB_COC + i];
    if (!split) return k;
    return 2 * k + (lr_moving(mx, my) ? 0 : 1);
}

/* lr_partition.c: lr_gap_bin, lr_gap_bounds (the same integer dynamic programme, so the same
 * bounds): the histogram-gap CoC bounds of a window (docs/algorithms.md 8.22). */
#define LR_GAP_BINS 48
#define LR_COC_SLABS 16 /* lr_partition.h: LR_MAX_COC_BOUNDS + 1, a still window's most slabs */
#define LR_BH_STRIDE 49 /* block_hist: the histogram, then the block's moving hits */
/* The number of edges below c (edges ascending, padded with +infinity to 64 entries, which no
 * c exceeds), found by binary lifting: six compares whose results are added, no branch. The
 * binary search it replaces mispredicted about one branch in two on every window sample and
 * was half of lr_tile_stats' time (docs/benchmarks.md, "LR's reconstruction cost"); the
 * answer is the same (lr_partition.c: lr_gap_bin, written the same way), also for c = +-inf
 * (47, 0) and NaN (0). */
static int lr_gap_bin(const float *edges64, float c)
{
    int b = 0;
    b += (c > edges64[b + 31]) ? 32 : 0;
    b += (c > edges64[b + 15]) ? 16 : 0;
    b += (c > edges64[b + 7]) ? 8 : 0;
    b += (c > edges64[b + 3]) ? 4 : 0;
    b += (c > edges64[b + 1]) ? 2 : 0;
    b += (c > edges64[b]) ? 1 : 0;
    return b;
}

static int lr_gap_bounds(const int *hist, __global const float *edges, int max_bounds, float *bounds)
{
    int occ[LR_GAP_BINS], m = 0;
    long pre[LR_GAP_BINS + 1];
    pre[0] = 0;
    for (int b = 0; b < LR_GAP_BINS; ++b)
        if (hist[b] > 0) {
            occ[m] = b;
            pre[m + 1] = pre[m] + hist[b];
            ++m;
        }
    int groups = max_bounds + 1 < m ? max_bounds + 1 : m;
    if (groups <= 1) return 0;
    long best[LR_COC_SLABS][LR_GAP_BINS];
    int from[LR_COC_SLABS][LR_GAP_BINS];
    for (int j = 0; j < m; ++j) {
        long w = occ[j] - occ[0] + 1;
        best[0][j] = pre[j + 1] * w * w;
    }
    for (int g = 1; g < groups; ++g)
        for (int j = g; j < m; ++j) {
            best[g][j] = LONG_MAX;
            from[g][j] = g - 1;
            for (int i = g - 1; i < j; ++i) {
                long w = occ[j] - occ[i + 1] + 1, c = best[g - 1][i] + (pre[j + 1] - pre[i + 1]) * w * w;
                if (c < best[g][j]) {
                    best[g][j] = c;
                    from[g][j] = i;
                }
            }
        }
    for (int g = groups - 1, j = m - 1; g >= 1; --g) {
        j = from[g][j];
        bounds[g - 1] = edges[occ[j]];
    }
    return groups - 1;
}

/* The hits among the samples of pixels [x0, x1) x [y0, y1): their depth range into *zmin,
 * *zmax and, with gap_slabs > 0, their CoC bins counted into hist (edges: the histogram's
 * LR_GAP_BINS - 1 edges) and, with count_moving (lr_config_counts_moving), the moving ones into
 * *moving. Window order, as lr_partition.c. */
static void lr_bin_rect(__global const float4 *keys, int width, int spp, int x0, int y0, int x1, int y1, int gap_slabs,
                        int count_moving, __global const float *edges, int *hist, int *moving, float *zmin, float *zmax)
{
#pragma OPENCL FP_CONTRACT OFF
    float edges64[64]; /* the edges in private memory, padded for lr_gap_bin */
    for (int b = 0; b < 64; ++b) edges64[b] = gap_slabs > 0 && b < LR_GAP_BINS - 1 ? edges[b] : INFINITY;
    float lo = *zmin, hi = *zmax;
    int n_moving = *moving;
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int k = 0; k < spp; ++k) {
                float4 key = keys[(size_t)(py * width + px) * spp + k];
                float z = key.x;
                if (z < INFINITY) {
                    lo = z < lo ? z : lo;
                    hi = z > hi ? z : hi;
                    if (gap_slabs > 0) hist[lr_gap_bin(edges64, key.y)]++;
                    if (count_moving) n_moving += lr_moving(key.z, key.w);
                }
            }
    *zmin = lo, *zmax = hi;
    *moving = n_moving;
}

/* Per block of LR_BLOCK_PX x LR_BLOCK_PX pixels (clipped at the image's edges): the CoC
 * histogram (lr_gap_bin) and the depth range of its hits. Where every window is a union of
 * whole blocks (lr_cl.c checks the alignment), lr_tile_stats adds its 16 blocks' histograms
 * and ranges instead of binning its 8192 samples: each sample is binned once, not once per
 * window that holds it (four). Counts are integers and a range's ends are a minimum and a
 * maximum, so the bounds are the same as sample by sample. One work-item per block. */
#define LR_BLOCK_PX 8
__kernel void lr_block_stats(int width, int height, int spp, int nbx, int nby, int gap_slabs, int count_moving, __global const float *coc_edges,
                             __global const float4 *keys, __global int *block_hist, __global float *block_z)
{
#pragma OPENCL FP_CONTRACT OFF
    int bx = get_global_id(0), by = get_global_id(1);
    if (bx >= nbx || by >= nby) return;
    int x0 = bx * LR_BLOCK_PX, y0 = by * LR_BLOCK_PX, x1 = min(width, x0 + LR_BLOCK_PX), y1 = min(height, y0 + LR_BLOCK_PX);
    int hist[LR_GAP_BINS], moving = 0;
    for (int b = 0; b < LR_GAP_BINS; ++b) hist[b] = 0;
    float zmin = INFINITY, zmax = -INFINITY;
    lr_bin_rect(keys, width, spp, x0, y0, x1, y1, gap_slabs, count_moving, coc_edges, hist, &moving, &zmin, &zmax);
    int b0 = by * nbx + bx;
    for (int b = 0; b < LR_GAP_BINS; ++b) block_hist[b0 * LR_BH_STRIDE + b] = hist[b];
    block_hist[b0 * LR_BH_STRIDE + LR_GAP_BINS] = moving;
    block_z[2 * b0] = zmin;
    block_z[2 * b0 + 1] = zmax;
}

/* The partition statistics of one tile (lr_partition.c: tile_stats, the same sums in the same
 * order): depth range -> layer bounds (written to tile_bounds), then per raw layer the count,
 * motion sum, CoC range, and in the mean motion's frame the motion ranges. The host finishes
 * the partitions (lr_tile_finish) from these few numbers instead of sweeping the samples. The
 * raw layer of every window sample is kept for the reprojection (layer_ids).
 * uniform: the uniform depth layers (1..7). gap_slabs 0: coc_bounds holds n_coc fixed bounds,
 * the same for every tile; gap_slabs > 0: it holds the LR_GAP_BINS - 1 edges of the CoC
 * histogram, and each tile's bounds are chosen in its gaps (lr_gap_bounds), at most
 * gap_slabs slabs, or still_slabs in a window where at most still_permille per mille of the
 * hits move (lr_partition.c: lr_tile_bounds_gaps, the same integer test). */
__kernel void lr_tile_stats(int width, int height, int spp, int tile_px, int window_px, int ntx, int ntiles,
                            int uniform, int n_coc, int inset, int gap_slabs, __global const float *coc_bounds, __global const float4 *keys,
                            __global float *tile_bounds, __global float *stats, __global uchar *layer_ids,
                            __global uint *order, __global int *layer_start, __global const uchar *still_tiles,
                            int blocks, int nbx, __global const int *block_hist, __global const float *block_z,
                            __global const float *bright_in, __global const float *samples, int still_slabs, int still_permille)
{
#pragma OPENCL FP_CONTRACT OFF
    int tile = get_global_id(0);
    if (tile >= ntiles || get_global_id(1) != 0) return;
    LrWindow w = lr_window(tile % ntx, tile / ntx, width, height, tile_px, window_px, inset);
    if (still_tiles[tile]) w.x1 = w.x0, w.y1 = w.y0; /* nothing to partition: no layers (lr_partition.c) */
    float zmin = INFINITY, zmax = -INFINITY;
    int hist[LR_GAP_BINS], moving = 0;
    /* the moving hits only choose between gap_slabs and still_slabs (lr_config_counts_moving) */
    int count_moving = still_slabs != gap_slabs;
    for (int b = 0; b < LR_GAP_BINS; ++b) hist[b] = 0;
    if (blocks) { /* the window is whole blocks (lr_block_stats) */
        if (w.x1 > w.x0 && w.y1 > w.y0)
            for (int by = w.y0 / LR_BLOCK_PX; by < (w.y1 + LR_BLOCK_PX - 1) / LR_BLOCK_PX; ++by)
                for (int bx = w.x0 / LR_BLOCK_PX; bx < (w.x1 + LR_BLOCK_PX - 1) / LR_BLOCK_PX; ++bx) {
                    int b0 = by * nbx + bx;
                    float z0 = block_z[2 * b0], z1 = block_z[2 * b0 + 1];
                    zmin = z0 < zmin ? z0 : zmin;
                    zmax = z1 > zmax ? z1 : zmax;
                    if (gap_slabs > 0)
                        for (int b = 0; b < LR_GAP_BINS; ++b) hist[b] += block_hist[b0 * LR_BH_STRIDE + b];
                    if (count_moving) moving += block_hist[b0 * LR_BH_STRIDE + LR_GAP_BINS];
                }
    } else
        lr_bin_rect(keys, width, spp, w.x0, w.y0, w.x1, w.y1, gap_slabs, count_moving, coc_bounds, hist, &moving, &zmin, &zmax);
    float tb[LR_TB_STRIDE];
    for (int i = 0; i < LR_TB_STRIDE; ++i) tb[i] = 0.0f;
    int n_depth = 0;
    if (gap_slabs > 0) {
        /* lr_partition.c: lr_tile_bounds_gaps; coc_bounds holds the histogram's edges */
        long hits = 0;
        for (int b = 0; b < LR_GAP_BINS; ++b) hits += hist[b];
        int slabs = (long)moving * 1000 > (long)still_permille * hits ? gap_slabs : still_slabs;
        float gb[LR_COC_SLABS - 1];
        n_coc = lr_gap_bounds(hist, coc_bounds, slabs - 1, gb);
        for (int i = 0; i < n_coc; ++i) tb[LR_TB_COC + i] = gb[i];
        int n = uniform - 1 < slabs - 1 - n_coc ? uniform - 1 : slabs - 1 - n_coc;
        if (zmin < zmax)
            for (int i = 1; i <= n; ++i) tb[2 + n_depth++] = zmin + (zmax - zmin) * (float)i / (float)(n + 1);
    } else {
        if (zmin < zmax)
            for (int i = 1; i < uniform; ++i) tb[2 + n_depth++] = zmin + (zmax - zmin) * (float)i / (float)uniform;
        for (int i = 0; i < n_coc; ++i) tb[LR_TB_COC + i] = coc_bounds[i];
    }
    tb[0] = (float)n_depth;
    tb[1] = (float)n_coc;
    for (int i = 0; i < LR_TB_STRIDE; ++i) tile_bounds[tile * LR_TB_STRIDE + i] = tb[i];

    int raw_n = lr_raw_count(n_depth, n_coc);
    int count[17], skipped[17];
    lr_sum mx[17], my[17], bright[17];
    float cmin[17], cmax[17], cp[17], sp[17], dmin[17], dmax[17], perp[17];
    float tilt[17][9]; /* lr_partition.h: LrTilt, lr_tilt_add; over the tile's own pixels */
    int ix0 = inset + (tile % ntx) * tile_px, iy0 = inset + (tile / ntx) * tile_px;
    int ix1 = min(ix0 + tile_px, width - inset), iy1 = min(iy0 + tile_px, height - inset);
    for (int i = 0; i < raw_n; ++i) {
        for (int k = 0; k < 9; ++k) tilt[i][k] = 0.0f;
        count[i] = skipped[i] = 0;
        mx[i] = my[i] = bright[i] = 0;
        cmin[i] = dmin[i] = INFINITY;
        cmax[i] = dmax[i] = -INFINITY;
        perp[i] = 0.0f;
    }
    __global uchar *ids = layer_ids + (size_t)tile * window_px * window_px * spp;
    /* lr_raw_layer with the tile's bounds padded to 8 depth and 16 CoC bounds with +infinity,
     * which no depth or CoC exceeds: a fixed count of compares per sample, added without
     * branches (the same layer; the bounds loops of varying length were a fifth of this
     * loop's time) */
    float db[8], cb[LR_COC_SLABS];
    bool padded = n_depth <= 8, split = raw_n > n_depth + n_coc + 2, fine = n_coc > 8;
    for (int i = 0; i < 8; ++i) db[i] = i < n_depth ? tb[2 + i] : INFINITY;
    for (int i = 0; i < LR_COC_SLABS; ++i) cb[i] = i < n_coc ? tb[LR_TB_COC + i] : INFINITY;
    for (int py = w.y0, i = 0; py < w.y1; ++py)
        for (int px = w.x0; px < w.x1; ++px)
            for (int k = 0; k < spp; ++k, ++i) {
                size_t index = (size_t)(py * width + px) * spp + k;
                float4 key = keys[index]; /* depth, CoC, motion */
                float b = bright_in[index]; /* r + g + b, NaN for a non-finite radiance (lr_bright) */
                int r;
                if (!padded) r = lr_raw_layer(tb, key.x, key.y, key.z, key.w);
                else if (!(key.x < INFINITY)) r = raw_n - 1;
                else {
                    int slab = 0;
                    for (int j = 0; j < 8; ++j) slab += (key.x > db[j]) + (key.y > cb[j]);
                    if (fine) /* a still window's bounds past 8 (the same for every sample: predicted) */
                        for (int j = 8; j < LR_COC_SLABS; ++j) slab += key.y > cb[j];
                    r = split ? 2 * slab + (lr_moving(key.z, key.w) ? 0 : 1) : slab;
                }
                bool finite = !isnan(b);
                ids[i] = (uchar)(finite ? r : r | LR_SKIP); /* the reprojection skips non-finite radiance */
                count[r]++;
                if (px >= ix0 && px < ix1 && py >= iy0 && py < iy1) { /* the tile's own pixels (LrTilt) */
                    __global const float *pl = samples + index * LR_PLACE_STRIDE; /* x, y, u, v */
                    float c = key.y, x = (pl[0] - (float)w.x0) - c * pl[2], y = (pl[1] - (float)w.y0) - c * pl[3];
                    float *m = tilt[r];
                    m[0] += x, m[1] += y, m[2] += c, m[3] += x * x, m[4] += y * y, m[5] += x * y, m[6] += x * c, m[7] += y * c, m[8] += 1.0f;
                }
                if (!finite) skipped[r]++; /* rare: a branch, not a sum per sample */
                mx[r] += (lr_sum)key.z;
                my[r] += (lr_sum)key.w;
                bright[r] += (lr_sum)(isfinite(b) ? b : 0.0f); /* lr_partition.c: the layer's brightness, 8.24 */
                cmin[r] = key.y < cmin[r] ? key.y : cmin[r];
                cmax[r] = key.y > cmax[r] ? key.y : cmax[r];
            }
    for (int i = 0; i < raw_n; ++i) {
        cp[i] = 1.0f;
        sp[i] = 0.0f;
        if (!count[i]) continue;
        lr_sum ax = mx[i] / count[i], ay = my[i] / count[i], len = sqrt(ax * ax + ay * ay);
        if (len > 0) {
            cp[i] = (float)(ax / len);
            sp[i] = (float)(ay / len);
        }
    }
    /* The window sorted by raw layer (lr_bucket.c: lr_bucket_by_layer, a stable counting
     * sort), so that a layer's reprojection reads its own samples and those behind it as one
     * contiguous run of the list and none in front of it; written during the second sweep. */
    __global int *start = layer_start + tile * LR_LS_STRIDE;
    int next[17], total = 0;
    for (int r = 0; r < 17; ++r) {
        start[r] = next[r] = total;
        total += r < raw_n ? count[r] - skipped[r] : 0;
    }
    start[17] = total;
    __global uint *list = order + (size_t)tile * window_px * window_px * spp;
    for (int py = w.y0, i = 0; py < w.y1; ++py)
        for (int px = w.x0; px < w.x1; ++px)
            for (int k = 0; k < spp; ++k, ++i) {
                uint index = ((uint)py * (uint)width + (uint)px) * (uint)spp + (uint)k;
                float2 m = keys[index].zw; /* the motion */
                int id = ids[i], r = id & ~LR_SKIP;
                if (!(id & LR_SKIP)) list[next[r]++] = index;
                float along = cp[r] * m.x + sp[r] * m.y;
                float across = fabs(-sp[r] * m.x + cp[r] * m.y);
                dmin[r] = along < dmin[r] ? along : dmin[r];
                dmax[r] = along > dmax[r] ? along : dmax[r];
                perp[r] = across > perp[r] ? across : perp[r];
            }
    __global float *o = stats + (size_t)tile * 17 * LR_ST_STRIDE;
    for (int i = 0; i < 17; ++i) {
        bool used = i < raw_n;
        o[i * LR_ST_STRIDE + 0] = used ? (float)count[i] : 0.0f;
        o[i * LR_ST_STRIDE + 1] = used ? cp[i] : 1.0f;
        o[i * LR_ST_STRIDE + 2] = used ? sp[i] : 0.0f;
        o[i * LR_ST_STRIDE + 3] = used ? cmin[i] : INFINITY;
        o[i * LR_ST_STRIDE + 4] = used ? cmax[i] : -INFINITY;
        o[i * LR_ST_STRIDE + 5] = used ? dmin[i] : INFINITY;
        o[i * LR_ST_STRIDE + 6] = used ? dmax[i] : -INFINITY;
        o[i * LR_ST_STRIDE + 7] = used ? perp[i] : 0.0f;
        o[i * LR_ST_STRIDE + 8] = used ? (float)bright[i] : 0.0f;
        for (int k = 0; k < 9; ++k) o[i * LR_ST_STRIDE + 9 + k] = used ? tilt[i][k] : 0.0f;
    }
}

/* The first of list[lo .. hi) (ascending) that is >= key. */
static int lr_lower_bound(__global const uint *list, int lo, int hi, uint key)
{
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (list[mid] < key) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* A tile's window in list order (lr_tile_stats' order), as five arrays: x, y, u, v, t, what
 * lr_reproject_layer needs of every sample it places. It places each window sample once per
 * layer at or in front of the sample's own (4 to 5 times a sample at 7-8 layers a tile);
 * through the list every placement was a gather of sample records spread over the window,
 * about half of its time. Copied here once, the layers read them as contiguous runs (the same
 * floats: the sums are unchanged); the gather here reads 32-byte LrPlace records, two to a
 * cache line, which hold only what the reprojection reads (docs/algorithms.md 8.31). The
 * radiance is read once per sample (by its own layer), so it stays in samples: copying it too
 * cost more than it saved (docs/benchmarks.md, "LR's reconstruction cost"). Done by the tile's
 * own work-item (lr_tile_filter), just before its layers read the copy. */
#define LR_PACK_FIELDS 5
static void lr_pack_tile(size_t cap, int n, __global const float *samples, __global const uint *list, __global float *p)
{
    for (int e = 0; e < n; ++e) {
        __global const float *s = samples + (size_t)list[e] * LR_PLACE_STRIDE;
        p[e] = s[0];
        p[cap + e] = s[1];
        p[2 * cap + e] = s[2];
        p[3 * cap + e] = s[3];
        p[4 * cap + e] = s[4];
    }
}

/* One 1D Gaussian pass of Algorithm 2 on the cells [ix0, ix1) of window row iy: for each,
 * the cells at k (dx, dy), k in [-r, r], nearest pixel, weighted by taps[|k|] =
 * exp(-(k / sigma)^2 / 2), summed into acc[(ix - ix0) * LR_CH + c]. Tap by tap over the whole
 * row (a tap's offset is the same for every cell of the row, and the cells whose tap falls
 * outside the window are a range at either end), so that every cell gets its taps added in
 * the order k = -r..r, exactly as one cell at a time would. The offsets: lr_tap_offsets. */
#define LR_ROW_MAX 64 /* window_px <= 64 (lr_cl.c) */
#define LR_ROUND_MAX 16 /* lr_taps.h: LR_ROUND_MAX_PX */
#define LR_TAP_MAX (LR_TAPS_Y - LR_TAPS_X - 1) /* r <= 32: taps[0..r] in a layer's parameters */

/* The pass's tap offsets along (dx, dy), k in [-r, r]: ox[k] = floor(k dx + 0.5), oy[k] likewise,
 * at ox[k + LR_TAP_MAX]. They depend on the direction only, so a pass computes them once for all
 * its rows (lr_row_pass took two floors per tap per row, ~a fifth of its time); the same floats,
 * so the same offsets. */
static void lr_tap_offsets(float dx, float dy, int r, int *ox, int *oy)
{
#pragma OPENCL FP_CONTRACT OFF
    for (int k = -r; k <= r; ++k) {
        ox[k + LR_TAP_MAX] = (int)floor((float)k * dx + 0.5f);
        oy[k + LR_TAP_MAX] = (int)floor((float)k * dy + 0.5f);
    }
}

static void lr_row_pass(__global const float *g, int ww, int wh, int iy, int ix0, int ix1, const int *oxs, const int *oys, int r,
                        __global const float *taps, float *acc)
{
#pragma OPENCL FP_CONTRACT OFF
    for (int i = 0; i < (ix1 - ix0) * LR_CH; ++i) acc[i] = 0.0f;
    for (int k = -r; k <= r; ++k) {
        int ox = oxs[k + LR_TAP_MAX], jy = iy + oys[k + LR_TAP_MAX];
        if (jy < 0 || jy >= wh) continue;
        int a = max(ix0, -ox), b = min(ix1, ww - ox); /* 0 <= ix + ox < ww */
        float wk = taps[k < 0 ? -k : k];
        /* the cells' channels are contiguous in the row and in acc: one flat loop over
         * (b - a) * LR_CH floats, which the compiler runs 8 or 16 wide (the loop over cells
         * and then channels ran 4 + 1 wide); the same products and sums */
        __global const float *row = g + (jy * ww + ox + a) * LR_CH;
        float *dst = acc + (a - ix0) * LR_CH;
        for (int i = 0; i < (b - a) * LR_CH; ++i) dst[i] += wk * row[i];
    }
}

/* Where band class c's along pass (c = 1 narrow, 2 wide) begins in a tile's two class grids. */
static size_t lr_class_grid(int c, int window_px)
{
    return (size_t)(c - 1) * (size_t)window_px * (size_t)window_px * LR_CH;
}

/* A layer's shear and sample weights, as lr_reproject_layer reads them from its parameters. */
typedef struct {
    float cp, sp, eta, xi, rho, isu, isv, ist;
    float shift_x, shift_y; /* the ramp: added where the layer's own samples land (shifted) */
} LrShear;

/* Where samples e0 .. e0 + n - 1 of a packed list land (eq. 16) and their weight w_u w_v w_t
 * (eq. 14): cell[m] the first float of their grid cell, clamped into the box [bx0, bx1) x
 * [by0, by1) that the screen passes read, and wt[m] their weight, 0 where the sample lands
 * outside the box (nothing reads it there). So the sums add every sample without a branch:
 * adding 0 (or 0 L, L finite: a non-finite radiance is not in the list) leaves a cell's
 * value as it was (x + 0 = x; of a zero at most its sign changes, and -0 and +0 are the same
 * number to every later sum, product and quotient), and the test it replaces mispredicted
 * where a layer's samples straddle the box's edge.
 * Independent samples, no branches: the processor overlaps them. flat (8.15's flat weights,
 * all three inverse sigmas 0): every weight is lr_gauss(0), exactly 1, so the Gaussian is not
 * evaluated (docs/algorithms.md 8.30). own: the layer's own samples, whose landing cells of
 * nonzero weight widen the box obox (x0, y0, x1, y1; inclusive). */
/* (always_inline: left a call, the loops were not specialised and the reprojection took a fifth
 * more time) */
static inline __attribute__((always_inline)) void lr_place(__global const float *P, size_t cap, int e0, int n,
                                                           const LrShear *f, bool flat, bool shifted, bool own, int x0, int y0, int ww, int bx0,
                                                           int by0, int bx1, int by1, float *wt, int *cell, int *obox)
{
#pragma OPENCL FP_CONTRACT OFF
    /* in registers: the stores to wt and cell below could otherwise alias *f */
    float cp = f->cp, sp = f->sp, eta = f->eta, xi = f->xi, rho = f->rho, isu = f->isu, isv = f->isv, ist = f->ist;
    float shx = f->shift_x, shy = f->shift_y;
    int ox0 = obox[0], oy0 = obox[1], ox1 = obox[2], oy1 = obox[3];
    for (int m = 0; m < n; ++m) {
        int e = e0 + m;
        float su = P[2 * cap + e], sv = P[3 * cap + e];
        float ur = cp * su + sp * sv, vr = -sp * su + cp * sv;
        float tc = P[4 * cap + e] - 0.5f;
        float along = eta * ur + xi * tc, across = rho * vr;
        float p = P[e] + cp * along - sp * across; /* eq. 16 */
        float q = P[cap + e] + sp * along + cp * across;
        if (shifted) p += shx, q += shy; /* the layer's own samples (lr_partition.h: LrLayer's ramp) */
        int ix = (int)floor(p) - x0, iy = (int)floor(q) - y0;
        float weight = 1.0f;
        if (!flat) {
            float au = isu * ur, av = isv * vr, at = ist * tc;
            weight = lr_gauss(au * au + av * av + at * at); /* w_u w_v w_t of eq. 14 */
        }
        bool read = ix >= bx0 && iy >= by0 && ix < bx1 && iy < by1; /* else never read */
        wt[m] = read ? weight : 0.0f;
        cell[m] = (clamp(iy, by0, by1 - 1) * ww + clamp(ix, bx0, bx1 - 1)) * LR_CH;
        if (own) {
            bool lands = read && weight != 0.0f;
            ox0 = min(ox0, lands ? ix : INT_MAX), ox1 = max(ox1, lands ? ix : INT_MIN);
            oy0 = min(oy0, lands ? iy : INT_MAX), oy1 = max(oy1, lands ? iy : INT_MIN);
        }
    }
    obox[0] = ox0, obox[1] = oy0, obox[2] = ox1, obox[3] = oy1;
}

/* Algorithm 1 for one (tile, layer) of lr_tile_filter's tile, serial over the window's samples
 * (no float atomics in OpenCL 1.2). It reads the tile's sorted list (lr_tile_stats): the
 * layer's own samples (raw layers raw_j .. raw_e - 1: one, or a run of merged ones,
 * lr_layers_merge), then those behind it raw layer by raw layer; the C version visits them in
 * the same order, so every cell gets the same sums. Positions and lens/time coordinates come
 * from lr_pack_tile's copy of the list (P), the radiance of the layer's own samples from samples.
 * Then the along pass into p1 (or the band classes' into pcls). g, p1, pcls: the tile's own
 * grids, reused by each of its layers. box: the tile pixels the layer can change (window
 * coordinates, all 0 for none). */
static void lr_reproject_layer(int width, int height, int spp, int tile_px, int window_px, int ntx, int tile, int j,
                               int film_slack_px, int inset, __global const float *samples, __global const float *P,
                               __global const uint *order, __global const int *layer_start, __global const int *tile_layers,
                               __global const float *lp, __global float *g, __global float *p1, __global float *pcls,
                               __global const float *class_params, __global const uchar *band_class, int *box)
{
#pragma OPENCL FP_CONTRACT OFF
    __global const int *tl = tile_layers + tile * LR_TL_STRIDE;
    size_t cap = (size_t)window_px * window_px * spp;
    __global const uint *list = order + (size_t)tile * cap;
    __global const int *start = layer_start + tile * LR_LS_STRIDE;
    __global const int *compact = tl + 1;
    int raw_j = 0, raw_e = 0; /* the layer's own samples: raw layers [raw_j, raw_e) (lr_tile_layer_end) */
    while (compact[raw_j] != j) ++raw_j;
    for (int i = raw_j; i < 17; ++i)
        if (compact[i] == j) raw_e = i + 1;
    LrWindow w = lr_window(tile % ntx, tile / ntx, width, height, tile_px, window_px, inset);
    int ww = w.x1 - w.x0, wh = w.y1 - w.y0;
    float cp = lp[0], sp = lp[1], eta = lp[3], xi = lp[4], isu = lp[5], ist = lp[6], rho = lp[8], isv = lp[9];
    /* flat sample weights (docs/algorithms.md 8.15, the default): every w_u w_v w_t is
     * lr_gauss(0) = 1 exactly, so the placement skips the Gaussian (a fifth of this kernel) */
    bool flat = isu == 0.0f && isv == 0.0f && ist == 0.0f;
    float ramp_x = lp[12], ramp_y = lp[13];
    LrShear sh = {cp, sp, eta, xi, rho, isu, isv, ist, ramp_x, ramp_y};
    /* Only the grid cells the screen passes read matter: the along pass's box around the tile,
     * widened by the along radius. A sample moves at most |eta| + |xi|/2 + |rho| px (|u_r|,
     * |v_r| <= 1 on the unit lens, |t_c| <= 1/2), so source rows farther than that from
     * the box cannot land in it and are not visited (a layer's list is pixel-major: the rows
     * are one run of it, found by bisection): for a sharp layer that is the tile's rows and a
     * few more instead of the whole window. The cells read get exactly the C version's sums. */
    float rx = lp[10], ry = lp[11];
    /* a still layer with band classes (LR_BAND): the boxes cover the widest class's reach */
    int rec[3] = {-1, (int)lp[LR_BAND], (int)lp[LR_BAND + 1]};
    bool banded = rec[1] >= 0 || rec[2] >= 0;
    for (int c = 1; c < 3; ++c)
        if (rec[c] >= 0) {
            rx = fmax(rx, class_params[rec[c] * LR_LP_STRIDE + 10]);
            ry = fmax(ry, class_params[rec[c] * LR_LP_STRIDE + 11]);
        }
    int tx0 = inset + (tile % ntx) * tile_px - w.x0, ty0 = inset + (tile / ntx) * tile_px - w.y0;
    /* how far the along pass (ax, ay) and the across pass (cx, cy) reach in x and y: a tap's
     * offset is the nearest integer to k cos psi or k sin psi, |k| <= r, at most ceil(r |cos|)
     * (lr_row_pass rounds with floor(x + 0.5); r is an integer, so k x <= r x in floats, and
     * floor(ceil(r x) + 0.5) = ceil(r x)) */
    int ax = (int)ceil(rx * fabs(cp)), ay = (int)ceil(rx * fabs(sp));
    int cx = (int)ceil(ry * fabs(sp)), cy = (int)ceil(ry * fabs(cp));
    int mx = cx + ax, my = cy + ay;
    /* film_slack_px: how far (past its own half) a sample's film position lies from its pixel's
     * centre, at least 2 (the host measures it: a wide pixel filter, pbrt's sinc, places
     * samples up to its radius away) */
    int reach = (int)ceil(1.01f * (fabs(eta) + 0.5f * fabs(xi) + fabs(rho) + fabs(ramp_x) + fabs(ramp_y))) + film_slack_px;
    int cy0 = max(0, ty0 - my - reach), cy1 = min(wh, ty0 + tile_px + my + reach);
    int bx0 = max(0, tx0 - mx), bx1 = min(ww, tx0 + tile_px + mx), by0 = max(0, ty0 - my), by1 = min(wh, ty0 + tile_px + my);
    for (int iy = by0; iy < by1; ++iy) { /* a row's cells are one run of floats: cleared as one */
        __global float *row = g + (iy * ww + bx0) * LR_CH;
        for (int i = 0; i < (bx1 - bx0) * LR_CH; ++i) row[i] = 0.0f;
    }
    uint key0 = (uint)(w.y0 + cy0) * (uint)width * (uint)spp, key1 = (uint)(w.y0 + cy1) * (uint)width * (uint)spp;
    int obox[4] = {INT_MAX, INT_MAX, INT_MIN, INT_MIN}; /* the cells the own samples reach: x0, y0, x1, y1 */
    int p0x = 0, p0y = 0, p1x = 0, p1y = 0; /* box P */
    for (int r = raw_j; r <= 17; ++r) {
        bool own = r < raw_e;
        if (r == raw_e) {
            /* The layer's opacity and light come from its own samples only: a tile pixel whose
             * screen filter (along, then across) reaches no cell of theirs gets alpha = 0 and
             * no light from this layer, whatever the weights, and eq. 17 leaves it as it was.
             * So the passes need only the tile pixels within (ax + cx, ay + cy) of the own
             * cells (box P, for the along pass below and lr_across_row), the along pass only P
             * widened by (cx, cy), which reads the grid within P widened by (ax + cx, ay + cy)
             * (box G): the samples behind are placed only into G, and only source rows within
             * reach of G are visited. G's cells get the same sums in the same order as before;
             * the cells outside it are never read (docs/algorithms.md 8.25). */
            p0x = max(tx0, obox[0] - ax - cx), p1x = min(tx0 + tile_px, obox[2] + 1 + ax + cx);
            p0y = max(ty0, obox[1] - ay - cy), p1y = min(ty0 + tile_px, obox[3] + 1 + ay + cy);
            box[0] = p0x, box[1] = p0y, box[2] = p1x, box[3] = p1y;
            if (p0x >= p1x || p0y >= p1y) { /* the layer shows nowhere in the tile */
                box[0] = box[1] = box[2] = box[3] = 0;
                return;
            }
            bx0 = max(bx0, p0x - ax - cx), bx1 = min(bx1, p1x + ax + cx);
            by0 = max(by0, p0y - ay - cy), by1 = min(by1, p1y + ay + cy);
            cy0 = max(0, by0 - reach), cy1 = min(wh, by1 + reach);
            key0 = (uint)(w.y0 + cy0) * (uint)width * (uint)spp, key1 = (uint)(w.y0 + cy1) * (uint)width * (uint)spp;
        }
        if (r == 17) break; /* (the loop's last step only writes the box when the layer's run ends at the last raw layer) */
        int e1 = lr_lower_bound(list, start[r], start[r + 1], key1);
        /* In chunks: first where each sample lands and its weight (independent samples, no
         * branches: the processor overlaps them), then the sums in list order. */
        for (int e0 = lr_lower_bound(list, start[r], e1, key0); e0 < e1; e0 += LR_CHUNK) {
            int n = min(LR_CHUNK, e1 - e0), cell[LR_CHUNK];
            float wt[LR_CHUNK];
            if (own) /* the next chunk's radiance, which its sums read: fetched while this chunk is placed */
                for (int m = e0 + LR_CHUNK; m < min(e0 + 2 * LR_CHUNK, e1); ++m)
                    __builtin_prefetch(samples + (size_t)list[m] * LR_PLACE_STRIDE + LR_PLACE_L);
            /* written out six times by the compiler: flat, shifted and own are constants in each call */
            bool shifted = own && (ramp_x != 0.0f || ramp_y != 0.0f);
            if (!own) {
                if (flat) lr_place(P, cap, e0, n, &sh, true, false, false, w.x0, w.y0, ww, bx0, by0, bx1, by1, wt, cell, obox);
                else lr_place(P, cap, e0, n, &sh, false, false, false, w.x0, w.y0, ww, bx0, by0, bx1, by1, wt, cell, obox);
                for (int m = 0; m < n; ++m) g[cell[m] + 1] += wt[m]; /* behind: the weight only */
                continue;
            }
            if (flat && shifted) lr_place(P, cap, e0, n, &sh, true, true, true, w.x0, w.y0, ww, bx0, by0, bx1, by1, wt, cell, obox);
            else if (flat) lr_place(P, cap, e0, n, &sh, true, false, true, w.x0, w.y0, ww, bx0, by0, bx1, by1, wt, cell, obox);
            else if (shifted) lr_place(P, cap, e0, n, &sh, false, true, true, w.x0, w.y0, ww, bx0, by0, bx1, by1, wt, cell, obox);
            else lr_place(P, cap, e0, n, &sh, false, false, true, w.x0, w.y0, ww, bx0, by0, bx1, by1, wt, cell, obox);
            for (int m = 0; m < n; ++m) {
                __global float *c = g + cell[m];
                __global const float *L = samples + (size_t)list[e0 + m] * LR_PLACE_STRIDE + LR_PLACE_L;
                c[0] += wt[m];
                c[1] += wt[m];
                c[2] += wt[m] * L[0];
                c[3] += wt[m] * L[1];
                c[4] += wt[m] * L[2];
            }
        }
    }
    float acc[LR_ROW_MAX * LR_CH];
    if (!banded) {
        if (lp[LR_ROUND] != 0.0f) return; /* the round filter reads the grid itself (lr_across_row) */
        /* Algorithm 2, first pass, along the layer's motion, while the grid is still in this
         * processor's caches: at the window cells the second pass reads, box P widened by the
         * across pass's reach (cx, cy), not the whole window. */
        int ix0 = max(0, p0x - cx), ix1 = min(ww, p1x + cx);
        int ox[2 * LR_TAP_MAX + 1], oy[2 * LR_TAP_MAX + 1];
        lr_tap_offsets(cp, sp, (int)rx, ox, oy); /* along (cos psi, sin psi) */
        for (int iy = max(0, p0y - cy); iy < min(wh, p1y + cy); ++iy) {
            lr_row_pass(g, ww, wh, iy, ix0, ix1, ox, oy, (int)rx, lp + LR_TAPS_X, acc);
            __global float *o = p1 + (iy * ww + ix0) * LR_CH;
            for (int i = 0; i < (ix1 - ix0) * LR_CH; ++i) o[i] = acc[i];
        }
        return;
    }
    /* A still layer with band classes (8.40): per class its own along pass, on the rows its
     * pixels' across pass reads. need[c]: the tile rows (bit iy - ty0) with a pixel of box P
     * that takes class c's filter (a class without a record takes the frame's, c = 0). */
    ulong need[3] = {0, 0, 0};
    int pe = min(p1x, width - inset - w.x0), qe = min(p1y, height - inset - w.y0); /* the tile's pixels in the image */
    for (int iy = p0y; iy < qe; ++iy)
        for (int ix = p0x; ix < pe; ++ix) {
            int k = band_class[(size_t)(w.y0 + iy) * width + w.x0 + ix];
            need[k > 0 && k < 3 && rec[k] >= 0 ? k : 0] |= (ulong)1 << (iy - ty0);
        }
    for (int c = 0; c < 3; ++c) {
        __global const float *sc = c == 0 ? lp : class_params + rec[c] * LR_LP_STRIDE;
        if (!need[c] || sc[LR_ROUND] != 0.0f) continue;
        int rxc = (int)sc[10], ryc = (int)sc[11];
        int cxc = (int)ceil((float)ryc * fabs(sp)), cyc = (int)ceil((float)ryc * fabs(cp));
        int ix0 = max(0, p0x - cxc), ix1 = min(ww, p1x + cxc);
        __global float *pc = c == 0 ? p1 : pcls + lr_class_grid(c, window_px);
        int ox[2 * LR_TAP_MAX + 1], oy[2 * LR_TAP_MAX + 1];
        lr_tap_offsets(cp, sp, rxc, ox, oy);
        for (int iy = max(0, p0y - cyc); iy < min(wh, p1y + cyc); ++iy) {
            /* the tile rows within cyc of this one: does any read it? */
            int lo = max(0, iy - cyc - ty0), hi = min(tile_px - 1, iy + cyc - ty0);
            if (lo > hi) continue;
            ulong rows = (hi - lo == 63 ? ~(ulong)0 : (((ulong)1 << (hi - lo + 1)) - 1)) << lo;
            if (!(need[c] & rows)) continue;
            lr_row_pass(g, ww, wh, iy, ix0, ix1, ox, oy, rxc, sc + LR_TAPS_X, acc);
            __global float *o = pc + (iy * ww + ix0) * LR_CH;
            for (int i = 0; i < (ix1 - ix0) * LR_CH; ++i) o[i] = acc[i];
        }
    }
}

/* The round screen filter on the cells [ix0, ix1) of window row iy, summed into
 * acc[(ix - ix0) * LR_CH + c]: the grid's cells within r of each, weighted by
 * table[dx^2 + dy^2]. The four taps (+-dx, +-dy) share a weight, so they are added before
 * it multiplies them: per dy >= 0 the rows iy - dy and iy + dy summed once into a row of rs
 * (cells outside the window count 0), then per dx >= 0 the pair rs[ix + dx] + rs[ix - dx]
 * added to each cell. dy, then dx ascending, exactly as lr_reconstruct.c's lr_round_sum, so
 * every cell gets the same sums (docs/algorithms.md 8.30).
 * The row sums of every dy are made first; then acc is summed LR_ROUND_BLOCK floats at a time
 * in registers over all (dy, dx) and stored once, where the pair loop swept the whole row once
 * per (dy, dx) with a load and a store of acc each time (docs/algorithms.md 8.46). Row dy of
 * rs holds the columns [ix0 - w(dy), ix1 + w(dy)) at the place of [ix0 - r, ...) (one stride
 * for all rows), then zeros up to the last block's end: a block's lanes past the row's n
 * floats are summed from them and never stored. ix1 - ix0 <= LR_TILE_MAX (lr_across_row's
 * tile pixels). */
#define LR_TILE_MAX 32
#define LR_ROUND_BLOCK 40 /* five 8-float chains of additions (a 16-px tile row is two blocks) */
/* eight floats from any float's address as one load (vload8 of private memory was taken apart
 * into 8-byte loads) */
typedef float8 lr_float8_any __attribute__((aligned(4)));
static inline float8 lr_load8(const float *p) { return *(const lr_float8_any *)p; }
static void lr_round_row(__global const float *g, int ww, int wh, int iy, int ix0, int ix1, int r, __global const float *table,
                         float *acc)
{
#pragma OPENCL FP_CONTRACT OFF
    int n = (ix1 - ix0) * LR_CH, blocks = (n + LR_ROUND_BLOCK - 1) / LR_ROUND_BLOCK * LR_ROUND_BLOCK;
    int stride = 2 * r * LR_CH + blocks;
    float rs[(LR_ROUND_MAX + 1) * ((LR_TILE_MAX + 2 * LR_ROUND_MAX) * LR_CH + LR_ROUND_BLOCK)];
    int width[LR_ROUND_MAX + 1]; /* the row's taps dx <= width[dy]; -1: both rows outside the window */
    for (int dy = 0; dy <= r; ++dy) {
        int w = r;
        while (w * w + dy * dy > r * r) --w; /* the row's taps: dx^2 + dy^2 <= r^2 */
        int up = iy - dy, dn = iy + dy;
        bool has_up = up >= 0 && up < wh, has_dn = dy > 0 && dn >= 0 && dn < wh;
        width[dy] = has_up || has_dn ? w : -1;
        if (!has_up && !has_dn) continue;
        /* rs[dy * stride + (x - (ix0 - r)) * LR_CH + c] for x in [ix0 - w, ix1 + w): 0 + 0 for
         * the columns outside the window (and the tail), and within it one flat loop over the
         * window's columns [xa, xb) per case of the two rows; the same sums as cell by cell with
         * a test per column (row + 0 where the other row is outside) */
        float *o = rs + dy * stride;
        __global const float *row_up = g + (has_up ? up : 0) * ww * LR_CH, *row_dn = g + (has_dn ? dn : 0) * ww * LR_CH;
        int xa = max(ix0 - w, 0), xb = min(ix1 + w, ww), nc = (xb - xa) * LR_CH;
        for (int i = (r - w) * LR_CH; i < (xa - (ix0 - r)) * LR_CH; ++i) o[i] = 0.0f + 0.0f;
        for (int i = (xb - (ix0 - r)) * LR_CH; i < (r + w) * LR_CH + blocks; ++i) o[i] = 0.0f + 0.0f;
        o += (xa - (ix0 - r)) * LR_CH;
        __global const float *a = row_up + xa * LR_CH, *b = row_dn + xa * LR_CH;
        if (has_up && has_dn)
            for (int i = 0; i < nc; ++i) o[i] = a[i] + b[i];
        else if (has_up)
            for (int i = 0; i < nc; ++i) o[i] = a[i] + 0.0f;
        else
            for (int i = 0; i < nc; ++i) o[i] = 0.0f + b[i];
    }
    for (int b0 = 0; b0 < n; b0 += LR_ROUND_BLOCK) {
        float8 s0 = 0.0f, s1 = 0.0f, s2 = 0.0f, s3 = 0.0f, s4 = 0.0f;
        for (int dy = 0; dy <= r; ++dy) {
            int w = width[dy];
            if (w < 0) continue;
            const float *m = rs + dy * stride + b0 + r * LR_CH; /* column ix0 + b0 / LR_CH */
            float wk = table[dy * dy];
            s0 += wk * lr_load8(m), s1 += wk * lr_load8(m + 8), s2 += wk * lr_load8(m + 16), s3 += wk * lr_load8(m + 24);
            s4 += wk * lr_load8(m + 32);
            for (int dx = 1; dx <= w; ++dx) {
                float wd = table[dx * dx + dy * dy];
                const float *right = m + dx * LR_CH, *left = m - dx * LR_CH;
                s0 += wd * (lr_load8(right) + lr_load8(left));
                s1 += wd * (lr_load8(right + 8) + lr_load8(left + 8));
                s2 += wd * (lr_load8(right + 16) + lr_load8(left + 16));
                s3 += wd * (lr_load8(right + 24) + lr_load8(left + 24));
                s4 += wd * (lr_load8(right + 32) + lr_load8(left + 32));
            }
        }
        if (n - b0 >= LR_ROUND_BLOCK) {
            vstore8(s0, 0, acc + b0), vstore8(s1, 1, acc + b0), vstore8(s2, 2, acc + b0), vstore8(s3, 3, acc + b0);
            vstore8(s4, 4, acc + b0);
        } else { /* the row's last, partial block */
            float part[LR_ROUND_BLOCK];
            vstore8(s0, 0, part), vstore8(s1, 1, part), vstore8(s2, 2, part), vstore8(s3, 3, part), vstore8(s4, 4, part);
            for (int i = 0; i < n - b0; ++i) acc[b0 + i] = part[i];
        }
    }
}

/* Normalisation and eq. 17 for the row's pixels [i0, i1) of one layer, acc holding the across
 * pass from pixel i0 on: each adds its light under the transmittance so far and takes the
 * layer's opacity off it (the extent AOV: the first layer with opacity, 1 / inv_sigma_x).
 * use: per pixel its band class's record, only the pixels of record c; 0: every pixel. */
static inline __attribute__((always_inline)) void lr_composite(const float *acc, int i0, int i1, const uchar *use, int c,
                                                               float inv_sigma_x, float *trans, float *out, float *extent)
{
#pragma OPENCL FP_CONTRACT OFF
    for (int i = i0; i < i1; ++i) {
        if (use && use[i] != c) continue;
        const float *a = acc + (i - i0) * LR_CH;
        if (!(a[1] > 0.0f)) continue;
        float alpha = a[0] / a[1];
        for (int ch = 0; ch < 3; ++ch) out[3 * i + ch] += trans[i] * a[2 + ch] / a[1];
        if (alpha > 0.0f && extent[i] == 0.0f) extent[i] = 1.0f / inv_sigma_x;
        trans[i] *= 1.0f - alpha;
    }
}

/* Algorithm 2, second pass (across the motion), normalisation and eq. 17 for one layer on
 * tile row iy (window coordinates; image row py): the row's pixels [i0, i1) (of the tile's n,
 * from window column ix0 on) inside the layer's box, with the tile's grids g, p1 and pcls as
 * lr_reproject_layer left them. */
static void lr_across_row(int width, int ww, int wh, int window_px, int iy, int py, int px0, int ix0, int i0, int i1,
                          __global const float *lp, __global const float *g, __global const float *p1, __global const float *pcls,
                          __global const float *class_params, __global const uchar *band_class, const int *ox, const int *oy,
                          float *trans, float *out, float *extent)
{
#pragma OPENCL FP_CONTRACT OFF
    float acc[LR_ROW_MAX * LR_CH];
    int rec[3] = {-1, (int)lp[LR_BAND], (int)lp[LR_BAND + 1]};
    if (rec[1] < 0 && rec[2] < 0) { /* one filter for the whole row */
        if (lp[LR_ROUND] != 0.0f)
            lr_round_row(g, ww, wh, iy, ix0 + i0, ix0 + i1, (int)lp[11], lp + LR_ROUND_T, acc);
        else
            lr_row_pass(p1, ww, wh, iy, ix0 + i0, ix0 + i1, ox, oy, (int)lp[11], lp + LR_TAPS_Y, acc);
        lr_composite(acc, i0, i1, 0, 0, lp[2], trans, out, extent);
        return;
    }
    /* A still layer with band classes (8.40): per pixel the record of its class's filter
     * (0, the frame's, for a class without one), per record the span [lo, hi) of its
     * pixels, the across pass over that span, and the pixels of the record composited. */
    uchar use[LR_ROW_MAX];
    int lo[3] = {i1, i1, i1}, hi[3] = {i0, i0, i0};
    for (int i = i0; i < i1; ++i) {
        int k = band_class[(size_t)py * width + px0 + i];
        int u = k > 0 && k < 3 && rec[k] >= 0 ? k : 0;
        use[i] = (uchar)u, lo[u] = min(lo[u], i), hi[u] = max(hi[u], i + 1);
    }
    for (int c = 0; c < 3; ++c) {
        if (hi[c] <= lo[c]) continue;
        __global const float *sc = c == 0 ? lp : class_params + rec[c] * LR_LP_STRIDE;
        __global const float *pc = c == 0 ? p1 : pcls + lr_class_grid(c, window_px);
        if (sc[LR_ROUND] != 0.0f)
            lr_round_row(g, ww, wh, iy, ix0 + lo[c], ix0 + hi[c], (int)sc[11], sc + LR_ROUND_T, acc);
        else
            lr_row_pass(pc, ww, wh, iy, ix0 + lo[c], ix0 + hi[c], ox, oy, (int)sc[11], sc + LR_TAPS_Y, acc);
        lr_composite(acc, lo[c], hi[c], use, c, sc[2], trans, out, extent);
    }
}

/* One tile of the batch, all its layers, front to back, in one work-item (docs/algorithms.md
 * 8.42): the copy of its list (lr_pack_tile), then per layer Algorithm 1 and the along pass
 * (lr_reproject_layer) and the across pass and eq. 17 on the tile's rows (lr_across_row). Each
 * work-item has its own grids (grid, pass1 and, for still layers with band classes, two class
 * grids: 40-80 KB at 32-px windows), which every layer of the tile reuses while they are in
 * this core's caches, and reads its copy right after writing it; as three kernels (one
 * work-item per 16th of a tile's list, per (tile, layer), per tile row) the batch's copy and
 * grids (~6 MB at 256x192, 8 spp) went from one to the next through the shared cache
 * (docs/benchmarks.md, "A tile's layers in one work-item"). Each pixel gets the same
 * operations in the same order as before: the images are the same to the bit. The tile's
 * transmittance, light and extent stay in private arrays (tile_px <= LR_TILE_MAX, lr_cl.c
 * checks). */
__kernel void lr_tile_filter(int width, int height, int spp, int tile_px, int window_px, int ntx, int tile1, int max_layers,
                             int tile0, int film_slack_px, int inset, __global const float *samples, __global float *packed,
                             __global const uint *order, __global const int *layer_start, __global const int *tile_layers,
                             __global const float *params, __global float *grid, __global float *pass1, __global float *rgb,
                             __global float *layers_aov, __global float *extent_aov, __global const float *class_params,
                             __global const uchar *band_class, __global float *pass1_class)
{
#pragma OPENCL FP_CONTRACT OFF
    int tile = tile0 + get_global_id(0);
    if (tile >= tile1 || get_global_id(1) != 0) return; /* the batch is tiles [tile0, tile1) */
    int slot = tile - tile0, tx = tile % ntx, ty = tile / ntx;
    size_t cells = (size_t)window_px * window_px * LR_CH, cap = (size_t)window_px * window_px * spp;
    __global float *g = grid + (size_t)slot * cells, *p1 = pass1 + (size_t)slot * cells, *pcls = pass1_class + (size_t)slot * 2 * cells;
    __global float *P = packed + (size_t)slot * LR_PACK_FIELDS * cap; /* the tile's copy of its list */
    int count = tile_layers[tile * LR_TL_STRIDE];
    if (count > 0) lr_pack_tile(cap, layer_start[tile * LR_LS_STRIDE + 17], samples, order + (size_t)tile * cap, P);
    LrWindow w = lr_window(tx, ty, width, height, tile_px, window_px, inset);
    int ww = w.x1 - w.x0, wh = w.y1 - w.y0;
    int px0 = inset + tx * tile_px, py0 = inset + ty * tile_px;
    int n = min(tile_px, width - inset - px0), rows = min(tile_px, height - inset - py0);
    int ix0 = px0 - w.x0, iy0 = py0 - w.y0;
    float trans[LR_TILE_MAX * LR_TILE_MAX], out[LR_TILE_MAX * LR_TILE_MAX * 3], extent[LR_TILE_MAX * LR_TILE_MAX];
    for (int i = 0; i < rows * tile_px; ++i) {
        trans[i] = 1.0f;
        out[3 * i] = out[3 * i + 1] = out[3 * i + 2] = 0.0f;
        extent[i] = 0.0f;
    }
    for (int j = 0; j < count; ++j) {
        __global const float *lp = params + (size_t)(tile * max_layers + j) * LR_LP_STRIDE;
        int box[4], ox[2 * LR_TAP_MAX + 1], oy[2 * LR_TAP_MAX + 1];
        lr_tap_offsets(-lp[1], lp[0], LR_TAP_MAX, ox, oy); /* the across passes' (-sin psi, cos psi), any r */
        lr_reproject_layer(width, height, spp, tile_px, window_px, ntx, tile, j, film_slack_px, inset, samples, P, order, layer_start,
                           tile_layers, lp, g, p1, pcls, class_params, band_class, box);
        /* the pixels outside the layer's box P get no opacity and no light from it: eq. 17
         * would leave them as they are */
        int i0 = max(ix0, box[0]) - ix0, i1 = min(ix0 + n, box[2]) - ix0;
        if (i0 >= i1) continue;
        for (int r = max(0, box[1] - iy0); r < min(rows, box[3] - iy0); ++r) {
            int o = r * tile_px;
            lr_across_row(width, ww, wh, window_px, iy0 + r, py0 + r, px0, ix0, i0, i1, lp, g, p1, pcls, class_params, band_class, ox,
                          oy, trans + o, out + 3 * o, extent + o);
        }
    }
    for (int r = 0; r < rows; ++r)
        for (int i = 0; i < n; ++i) {
            size_t p = (size_t)(py0 + r) * width + px0 + i;
            int o = r * tile_px + i;
            for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = out[3 * o + c];
            layers_aov[p] = (float)count;
            extent_aov[p] = extent[o];
        }
}
