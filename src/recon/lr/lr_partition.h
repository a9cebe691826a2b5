/* LR partitions (section 7): a 16x16 tile's search window (32x32 pixels) of samples split into
 * depth layers, and per layer the mean motion direction psi, the circle-of-confusion and motion
 * slope ranges and the filter of lr_filter.h. Plain buffers, no OpenCL: the host computes the
 * partitions, the kernels (lr.cl) and the C reference (lr_reference.c) consume them. */
#ifndef WEDGE_RECON_LR_PARTITION_H
#define WEDGE_RECON_LR_PARTITION_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "recon/lr/lr_filter.h"

/* One camera sample as LR reads it (LR section 3: (x, y, u, v, t) -> (z, d, l)). */
typedef struct {
    float x_px, y_px;     /* film position, pixels (pixel (x, y) covers [x, x+1)) */
    float u, v;           /* lens position on the unit disk, oriented so that y = y0 + c v */
    float t;              /* shutter time in [0, 1] */
    float depth;          /* camera-space depth, world units; INFINITY for a miss */
    float coc_px;         /* c = dx/du = dy/dv, px per unit lens (signed, 0 in focus) */
    float motion_px[2];   /* screen velocity, px per unit shutter time */
    float L[3];           /* radiance */
} LrSample;

/* What the passes read of a sample, in two records and a sum, written once by the frame's
 * producer (lr_method.c's gather; lr_samples_split for an array of LrSample): the partition
 * statistics read only LrKey and bright, the reprojection only LrPlace. The statistics read
 * every sample of a window (four windows hold each) twice, and the reprojection's copy
 * (lr.cl: lr_pack_tile) gathers every window's samples in layer order: through one 48-byte record
 * each of them waited on memory for fields it did not use (docs/algorithms.md 8.31). */
typedef struct {
    float depth, coc_px, motion_px[2]; /* LrSample's; 16 bytes */
} LrKey;
typedef struct {
    float x_px, y_px, u, v, t, L[3]; /* LrSample's; 32 bytes */
} LrPlace;

/* The bright sum of a radiance: r + g + b, NaN when a channel is not finite (the sum of three
 * finite floats is never NaN, at worst +-infinity, so NaN alone marks a non-finite radiance;
 * the statistics count such a sample in its layer and leave its light out). */
static inline float lr_bright(const float L[3])
{
    return isfinite(L[0]) && isfinite(L[1]) && isfinite(L[2]) ? L[0] + L[1] + L[2] : NAN;
}

/* A fixed number of samples per pixel, pixel-major: sample k of pixel (px, py) is element
 * (py * width + px) * spp + k of each array. */
typedef struct {
    int width, height, spp;
    const LrKey *key;
    const LrPlace *place;
    const float *bright; /* lr_bright of each sample's L */
} LrSamples;

/* Sample i of s[] into the three arrays. */
static inline void lr_split_sample(const LrSample *s, size_t i, LrKey *key, LrPlace *place, float *bright)
{
    key[i] = (LrKey){s->depth, s->coc_px, {s->motion_px[0], s->motion_px[1]}};
    place[i] = (LrPlace){s->x_px, s->y_px, s->u, s->v, s->t, {s->L[0], s->L[1], s->L[2]}};
    bright[i] = lr_bright(s->L);
}

/* The arrays of width x height x spp samples s (pixel-major), allocated (NULL arrays when out
 * of memory); lr_samples_free releases them. */
LrSamples lr_samples_split(int width, int height, int spp, const LrSample *s);
void lr_samples_free(LrSamples *img);

/* 17 raw layer ids: 2 x 8 slabs and the misses where a window's moving and static samples
 * split (LR_MAX_SPLIT_SLABS), 16 slabs and the misses where nothing in the window moves
 * (LR_MAX_COC_BOUNDS + 1 slabs: lr_config_still_gap_slabs). */
enum { LR_MAX_LAYERS = 16, LR_MAX_DEPTH_BOUNDS = 15, LR_MAX_SPLIT_SLABS = 8, LR_MAX_COC_BOUNDS = 15 };

typedef struct {
    LrFilterConfig filter;
    int tile_px;              /* N: 16 */
    int window_px;            /* N_s: 32 (tile plus (N_s - N)/2 on each side) */
    int inset_px;             /* a band this wide along every border is read for its samples
                               * but not reconstructed (the overscan band, cropped by the
                               * pipeline): the tiles start at (inset_px, inset_px), the visible
                               * image's corner. 0: the whole image */
    int uniform_layers;       /* layers uniform in depth over the window's depth range */
    int focus_bounds;         /* extra boundaries at c = +-focus_step_px * k^2, k = 1..n/2 */
    float focus_step_px;
    int gap_slabs;            /* > 0: the CoC bounds are chosen per window in the gaps of its
                               * samples' CoC histogram (lr_gap_bounds), at most gap_slabs - 1
                               * of them, and focus_bounds / focus_step_px are not used; 0: the
                               * fixed focus bounds */
    int still_gap_slabs;      /* the same for a window that (hardly) moves: it splits no slab
                               * into moving and static layers once it has more than 8, so the
                               * 17 raw ids hold up to LR_MAX_COC_BOUNDS + 1 slabs, finer layers
                               * where static geometry crosses the focal plane (0, the
                               * default: gap_slabs; 12 measured with 24-px tiles).
                               * docs/algorithms.md 8.47 */
    int still_moving_permille; /* ...a window "hardly moves" when at most this share (per
                                * mille) of its hits is moving (LR_MOVING_PX; 0: none at all;
                                * default 150) */
    float motion_spread_max;  /* no motion filter when the directions' spread exceeds this
                               * share of the mean motion (and half a pixel), or when the
                               * range of speeds along the mean direction exceeds this share
                               * of it and motion_range_px */
    float motion_range_px;
    float motion_long_px;     /* ...but the range of speeds is no reason when the slowest
                               * speed along the mean direction is at least this (px per
                               * shutter; default the window's width, INFINITY: never) */
    /* A layer whose mean brightness is at least bright_contrast times the rest of its
     * window's (lr_layer_contrast: a light source out of focus over a dark background) takes
     * at most bright_clamp_px of screen sigma instead of filter.sigma_clamp_px: its blur stays
     * in the samples' own lens and shutter offsets, the lens disk's and the shutter box's
     * shape, rather than in a screen share whose shape is right only in variance (a bright
     * cone, with a halo past the disk's rim on the dark pixels around it). Defaults 8 and
     * 1 px; bright_contrast 0: off. docs/algorithms.md 8.24. For a moving layer and a still
     * one within the still band the clamp shrinks with the layer's smallest blur radius R
     * (lr_bright_clamp_px), down to bright_clamp_min_px (1 / sqrt(12) px, the pixel box's own
     * std: no Gaussian past what binning a sample into its pixel does), so that the
     * Gaussian's tails past a short blur (a light in focus, a light moving 3 px) do not
     * outshine the background (8.49). */
    float bright_contrast;
    float bright_clamp_px;
    float bright_clamp_min_px;
    /* Neighbouring layers whose filters agree (lr_layers_merge) are one partition, its
     * filter made from the union of their slope ranges. merge_shift_sigmas: the most a sample
     * may land elsewhere under the front layer's shear than under its own (|d eta| +
     * |d xi| / 2 + |d rho|), in the front layer's smaller screen sigma; merge_sigma_share: the
     * most the screen sigmas and shaped shares may differ, as a share of the front layer's.
     * merge_shift_sigmas 0: never merged. docs/algorithms.md 8.34. */
    float merge_shift_sigmas;
    float merge_sigma_share;
    /* A static layer's own samples shifted by the centroid shift of its surface's tilt
     * (LrLayer.ramp_x_px, lr_tilt_ramp; docs/algorithms.md 8.35); false: never. */
    bool tilt_ramp;
    const unsigned char *still_tiles; /* per tile (row-major, lr_tile_count's), non-zero: a
                                       * tile with nothing to move, left out (no layers, its
                                       * pixels 0 in the output); NULL: none */
    const unsigned char *band_class;  /* per pixel of the image (row-major), its still band's
                                       * class (lr_band_class.h: LR_BAND_*): the still layers'
                                       * screen filter at that pixel takes the class's band
                                       * (docs/algorithms.md 8.40); NULL: the frame's band */
    /* What the frame's producer measured while writing the samples (samples_scanned; else
     * lr_cl_run measures it in a pass of its own): the samples with a non-finite radiance,
     * and the farthest a film position lies from its pixel's centre along x or y, px. */
    bool samples_scanned;
    long samples_nonfinite;
    float film_dev_px;
} LrConfig;

LrConfig lr_config_default(void);

/* Sample p of pixel (px, py) into LrConfig's samples_nonfinite and film_dev_px: counts a
 * non-finite radiance, and keeps the larger of film_dev_px and its film position's distance
 * from the pixel's centre along x and along y (a NaN position is ignored). */
static inline void lr_scan_sample(const LrPlace *p, int px, int py, long *nonfinite, float *film_dev_px)
{
    if (!(isfinite(p->L[0]) && isfinite(p->L[1]) && isfinite(p->L[2]))) ++*nonfinite;
    float dx = fabsf(p->x_px - ((float)px + 0.5f)), dy = fabsf(p->y_px - ((float)py + 0.5f));
    if (dx > *film_dev_px) *film_dev_px = dx;
    if (dy > *film_dev_px) *film_dev_px = dy;
}

/* A layer's samples' CoC slope c against the position of the point each sees through the lens
 * centre (x, y: its film position less c (u, v), less the window's corner; px), for the slope's
 * gradient over the surface (lr_tilt_ramp): over the
 * samples of the tile's own pixels (a quarter of the window: the statistics' sweep sums each
 * sample four times, once per window that holds it, and these nine sums cost a quarter of it
 * over the whole window), the sums of x, y, c, x^2, y^2, x y, x c, y c and their count in
 * floats, sample by sample in window order (C and lr.cl: the same sums). */
enum { LR_TILT_SUMS = 9 };
typedef struct {
    float sum[LR_TILT_SUMS]; /* sum[8]: the count */
} LrTilt;

/* Sample (x, y, c) into a layer's sums (the order of the fields of LrTilt). */
static inline void lr_tilt_add(LrTilt *t, float x, float y, float c)
{
    float *m = t->sum;
    m[0] += x, m[1] += y, m[2] += c, m[3] += x * x, m[4] += y * y, m[5] += x * y, m[6] += x * c, m[7] += y * c, m[8] += 1.0f;
}

/* One layer of a tile (a partition). */
typedef struct {
    int count;                  /* samples of the window in the layer */
    float cos_psi, sin_psi;     /* mean motion direction (the rotated frame's x axis) */
    bool motion_filter;         /* false when the directions spread too much */
    float contrast;             /* the layer's mean brightness over the rest of the
                                 * window's (lr_layer_contrast) */
    LrSlopes slopes;
    LrFilter filter;
    LrTilt tilt;                /* its own samples' slope-against-position sums (merged
                                 * layers: added) */
    /* Where the layer's own samples land is moved by (ramp_x_px, ramp_y_px): the centroid
     * shift of a tilted surface's defocus splat that its screen disk lacks (lr_tilt_ramp,
     * docs/algorithms.md 8.35); 0 for a layer with motion or without a tilt. */
    float ramp_x_px, ramp_y_px;
} LrLayer;

/* The layers of one tile: a sample's layer is the number of depth bounds below its depth plus
 * the number of CoC bounds below its c (both orders agree: c grows with depth), compacted to
 * the non-empty layers; misses (depth INFINITY) are the last layer. */
typedef struct {
    int n_depth, n_coc;
    float depth_bound[LR_MAX_DEPTH_BOUNDS];
    float coc_bound_px[LR_MAX_COC_BOUNDS];
    int compact[LR_MAX_LAYERS + 1]; /* raw layer -> compact layer */
    int layer_count;                /* non-empty layers, front to back */
    LrLayer layer[LR_MAX_LAYERS + 1]; /* one per raw layer id at most (the misses' included) */
} LrTile;

/* The tiles covering the reconstructed image (the image less cfg->inset_px on every side). */
void lr_tile_count(const LrSamples *img, const LrConfig *cfg, int *ntx, int *nty);

/* Pixels of tile (tx, ty), clipped to the reconstructed image: [x0, x1) x [y0, y1). */
void lr_tile_pixels(const LrSamples *img, const LrConfig *cfg, int tx, int ty, int *x0, int *y0, int *x1, int *y1);

/* Window of tile (tx, ty) in pixels, clipped to the image (the band included): [x0, x1) x [y0, y1). */
void lr_tile_window(const LrSamples *img, const LrConfig *cfg, int tx, int ty, int *x0, int *y0, int *x1, int *y1);

/* Partitions the window of tile (tx, ty) (LR sections 5, 7): lr_tile_bounds from the window's
 * depth range, the per-layer statistics below, then lr_tile_finish. */
void lr_tile_partition(const LrSamples *img, const LrConfig *cfg, int tx, int ty, LrTile *tile);

/* What a partition needs from its samples, per raw layer (before compaction): the sample
 * count, the mean motion's direction, the CoC range, in that direction's frame the range
 * of motion along it and the largest motion across it, and the sum of its samples'
 * brightness (r + g + b; 0 for a non-finite radiance). OpenCL computes the same
 * (lr.cl: lr_tile_stats), the host finishes the partition from it. */
typedef struct {
    int count;
    float cos_psi, sin_psi;
    float c_min_px, c_max_px;
    float d_min_px, d_max_px;
    float across_px;
    float bright_sum;
    LrTilt tilt;
} LrLayerStats;

/* The shift of a static layer's own samples (psi = 0, no shutter shear) that gives its screen
 * disk the tilt's centroid shift (docs/algorithms.md 8.35): with g = (dc/dX, dc/dY) the
 * gradient of the samples' slope over their lens-centre points, fitted from `tilt`, the shift is (-eta g_x / 4, -rho g_y / 4) px. 0 when the fit is degenerate.
 * Measured since (8.48): inside a layer a normalised gather wants the opposite sign; the shift's
 * net gain comes from the layer bounds, where eq. 17 displaces the image the other way. */
void lr_tilt_ramp(const LrTilt *tilt, float eta_px, float rho_px, float *ramp_x_px, float *ramp_y_px);

/* cfg->uniform_layers within [1, 7], cfg->gap_slabs within [0, LR_MAX_SPLIT_SLABS] and
 * cfg->still_gap_slabs within [1, LR_MAX_COC_BOUNDS + 1] (0: the clamped gap_slabs; with
 * gap_slabs 0 it is 0 too): the counts the partition (C and lr.cl alike) works with. */
int lr_config_uniform_layers(const LrConfig *cfg);
int lr_config_gap_slabs(const LrConfig *cfg);
int lr_config_still_gap_slabs(const LrConfig *cfg);

/* Whether a window's moving hits can change its slab count (lr_config_still_gap_slabs differs
 * from lr_config_gap_slabs): when not, the statistics (C and lr.cl) do not count them. */
bool lr_config_counts_moving(const LrConfig *cfg);

/* The tile's layer bounds from its window's depth range (zmin > zmax: no hits); clears t. */
void lr_tile_bounds(const LrConfig *cfg, float zmin, float zmax, LrTile *t);

/* Histogram-gap bounds (docs/algorithms.md 8.22). The window's hit samples are counted in
 * LR_GAP_BINS bins of CoC slope whose edges are c = LR_GAP_C0_PX sinh(s), s uniform over
 * |c| <= LR_GAP_CMAX_PX (wider slopes fall in the end bins): linear (bins ~0.2 px wide) within
 * a pixel or so of focus, where the lens blur is below the pixel filter's, geometric (~1.22 a
 * bin) away from it, so that a bin's width is a bounded share of its slopes. c0 = 1 px
 * measured better than 0.5 px on every bench scene with LR (docs/benchmarks.md, 2026-11-28). */
enum { LR_GAP_BINS = 48 };
#define LR_GAP_C0_PX 1.0
#define LR_GAP_CMAX_PX 64.0

/* The LR_GAP_BINS - 1 ascending bin edges (px per unit lens). */
void lr_gap_edges(float *edges);

/* The bin of a CoC slope: the number of edges below it (the layers' "c > bound" rule). */
int lr_gap_bin(const float *edges, float coc_px);

/* At most max_bounds CoC bounds, ascending, written to bounds (returns how many): the split of
 * the histogram's occupied bins into contiguous groups that minimises the sum over groups of
 * (samples) x (bins from its first occupied bin to its last)^2, a group's width in bins being
 * the log of its c_max / c_min away from focus (the blur error of a layer grows with it,
 * 8.20). A bound sits at the upper edge of its group's last occupied bin, so every bound is
 * in a gap of the histogram when one is there to take. Integer costs, exact dynamic
 * programme: lr.cl's lr_gap_bounds gives the same bounds. */
int lr_gap_bounds(const int *hist, const float *edges, int max_bounds, float *bounds);

/* lr_tile_bounds with cfg->gap_slabs > 0: CoC bounds from the window's histogram hist (bins of
 * lr_gap_edges' edges), at most lr_config_gap_slabs slabs, or lr_config_still_gap_slabs when
 * moving_hits (the window's moving hits) is at most cfg->still_moving_permille per mille of
 * its hits (the histogram's count); clears t. */
void lr_tile_bounds_gaps(const LrConfig *cfg, float zmin, float zmax, const int *hist, const float *edges, long moving_hits,
                         LrTile *t);

/* Whether a layer keeps its motion filter (LR section 5, docs/algorithms.md 8.5 and 8.32): its
 * speeds along the mean direction psi span [d_min_px, d_max_px] (px over the shutter) and its
 * largest speed across psi is across_px. No clear direction (across above 0.5 px and above
 * motion_spread_max of the mean speed) or too wide a range of speeds (above motion_range_px and
 * that share, unless the slowest moves at least motion_long_px) gives none. auto's gain probe
 * asks the same of the probe's samples (probe_motion_rule.h). */
bool lr_motion_filter_kept(const LrConfig *cfg, float d_min_px, float d_max_px, float across_px);

/* Compaction, motion ranges widened by the spread across psi (Figure 4), the filters, then
 * neighbouring layers merged where lr_layers_merge allows (a merged layer's raw layers are
 * one run of the raw order: compact[] maps each of them, and any empty raw layer between
 * them has -1). */
void lr_tile_finish(const LrConfig *cfg, const LrLayerStats *raw_stats, LrTile *t);

/* A bright layer's screen sigma limit for slopes: sqrt(2 pi) R / (2 bright_contrast) for its
 * smallest blur radius R (px), between bright_clamp_min_px and bright_clamp_px, for a moving
 * layer or a still one whose lens blur is within the still band (lr_blur_within_band: the
 * band only smooths it); bright_clamp_px for a still layer blurred past the band (8.49). */
float lr_bright_clamp_px(const LrConfig *cfg, const LrSlopes *slopes);

/* A layer's filter from its slopes (lr_filter_make with cfg->filter), with the bright-layer
 * clamp (8.24, 8.49) where its contrast asks. */
LrFilter lr_layer_filter(const LrConfig *cfg, const LrSlopes *slopes, float contrast);

/* Whether layer `back`, right behind `front` in a tile, may be filtered as part of it: the
 * same rotation and sample weights, shears within cfg->merge_shift_sigmas, screen sigmas and
 * shaped shares within cfg->merge_sigma_share. Two layers with the same shear and screen
 * filter composite (eq. 17) exactly as their union does (docs/algorithms.md 8.34). */
bool lr_layers_merge(const LrConfig *cfg, const LrFilter *front, float front_cos, float front_sin, const LrFilter *back,
                     float back_cos, float back_sin);

/* The first raw layer after layer j's run (j < t->layer_count): its own samples are raw
 * layers [first, end) of j, those behind it the raw layers from end on. */
int lr_tile_layer_end(const LrTile *t, int raw_n, int j);

/* Raw layer i's mean brightness over the mean of the window's other samples (all raw layers,
 * misses included); INFINITY when the others are black and the layer is not; 1 when the layer
 * is the whole window or black. */
float lr_layer_contrast(const LrLayerStats *raw_stats, int raw_n, int i);

/* A sample moving at least this far over the shutter (screen pixels) is "moving": within one
 * depth/CoC slab the moving and the static samples are separate layers (lr_tile_raw_layer).
 * lr.cl has the same constant. */
#define LR_MOVING_PX 1.0f

/* Whether a sample is "moving" (LR_MOVING_PX or more over the shutter): the moving/static split
 * of a slab's raw layers, and (none among a window's hits) cfg->still_gap_slabs. */
static inline bool lr_key_moving(const float motion_px[2])
{
    return motion_px[0] * motion_px[0] + motion_px[1] * motion_px[1] >= LR_MOVING_PX * LR_MOVING_PX;
}

/* The raw layer (before compaction) of a sample in a tile. The depth and CoC bounds cut the
 * hits into slabs (k below); when the tile's 2 * slabs + 1 raw layers fit (always with the
 * default config), slab k becomes raw layer 2k for its moving samples and 2k + 1 for its
 * static ones, so that a moving object does not share a layer (and the motion range) with the
 * static floor or wall at its depth: a layer whose speeds range from 0 to the object's gets
 * no motion filter (lr_tile_finish), which left every moving object on a static background
 * unfiltered (docs/algorithms.md 8.14). Moving first: inside a slab the moving layer's
 * coverage, which its filter smooths over many pixels, sets how much of the static layer
 * shows through, rather than the static layer's per-pixel coverage. Misses are the last
 * raw layer. */
int lr_tile_raw_layer(const LrTile *tile, float depth, float coc_px, const float motion_px[2]);

/* The number of raw layers of a tile (lr_tile_raw_layer's values are below it). */
int lr_tile_raw_count(const LrTile *tile);

/* The compact layer of a sample in this tile. */
int lr_tile_layer_of(const LrTile *tile, const LrKey *s);

#endif
