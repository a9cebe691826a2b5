/* LR partitions: tiles, depth layers and per-layer slopes (LR sections 5 and 7, Figure 4). */
#include "recon/lr/lr_partition.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Whether a tile's slabs split into moving and static layers (they fit in the raw ids). */
static bool splits_motion(const LrTile *t) { return 2 * (t->n_depth + t->n_coc + 1) + 1 <= LR_MAX_LAYERS + 1; }

int lr_tile_raw_count(const LrTile *t)
{
    int slabs = t->n_depth + t->n_coc + 1;
    return splits_motion(t) ? 2 * slabs + 1 : slabs + 1;
}

LrConfig lr_config_default(void)
{
    LrConfig c;
    c.filter = lr_filter_config_default();
    c.tile_px = 16;
    c.window_px = 32;
    c.inset_px = 0;
    c.uniform_layers = 4;
    c.focus_bounds = 4;
    c.focus_step_px = 1.0f;
    c.gap_slabs = 8; /* 2 x 8 slabs + misses: the 17 raw layer ids */
    /* Off: at 16/32 px it changes the error by 0.2% or less. With 24-px tiles in 40-px
     * windows, 12 slabs for windows whose hits move at most 15% win back those tiles' error
     * (docs/algorithms.md 8.47), but test_lr_tilted's near-focus plane keeps them out: with
     * them the tilt shift's harm inside layers outweighs its gain at their bounds (8.48). */
    c.still_gap_slabs = 0;
    c.still_moving_permille = 150;
    c.motion_spread_max = 0.5f;
    c.motion_range_px = 4.0f;
    c.motion_long_px = (float)c.window_px;
    c.bright_contrast = 8.0f; /* docs/algorithms.md 8.24 */
    c.bright_clamp_px = 1.0f;
    c.bright_clamp_min_px = 0.28867513f; /* 1 / sqrt(12): docs/algorithms.md 8.49 */
    c.merge_shift_sigmas = 0.3f; /* docs/benchmarks.md, lr16: 0.5 raised motion_defocus's error, 0.6 hard's */
    c.merge_sigma_share = 0.3f;
    c.tilt_ramp = true; /* docs/algorithms.md 8.35 */
    c.still_tiles = NULL;
    c.band_class = NULL; /* the frame's band everywhere (lr_method.c sets it below 16 spp) */
    c.samples_scanned = false; /* lr_cl_run measures the samples itself */
    c.samples_nonfinite = 0;
    c.film_dev_px = 0.0f;
    c.filter.sigma_clamp_px = (float)(c.window_px - c.tile_px) / 4.0f; /* Appendix C */
    return c;
}

void lr_tile_count(const LrSamples *img, const LrConfig *cfg, int *ntx, int *nty)
{
    int w = img->width - 2 * cfg->inset_px, h = img->height - 2 * cfg->inset_px;
    *ntx = w > 0 ? (w + cfg->tile_px - 1) / cfg->tile_px : 0;
    *nty = h > 0 ? (h + cfg->tile_px - 1) / cfg->tile_px : 0;
}

void lr_tile_pixels(const LrSamples *img, const LrConfig *cfg, int tx, int ty, int *x0, int *y0, int *x1, int *y1)
{
    int xe = img->width - cfg->inset_px, ye = img->height - cfg->inset_px;
    *x0 = cfg->inset_px + tx * cfg->tile_px;
    *y0 = cfg->inset_px + ty * cfg->tile_px;
    *x1 = *x0 + cfg->tile_px > xe ? xe : *x0 + cfg->tile_px;
    *y1 = *y0 + cfg->tile_px > ye ? ye : *y0 + cfg->tile_px;
}

void lr_tile_window(const LrSamples *img, const LrConfig *cfg, int tx, int ty, int *x0, int *y0, int *x1, int *y1)
{
    int margin = (cfg->window_px - cfg->tile_px) / 2;
    int ax = cfg->inset_px + tx * cfg->tile_px - margin, ay = cfg->inset_px + ty * cfg->tile_px - margin;
    *x0 = ax < 0 ? 0 : ax;
    *y0 = ay < 0 ? 0 : ay;
    *x1 = ax + cfg->window_px > img->width ? img->width : ax + cfg->window_px;
    *y1 = ay + cfg->window_px > img->height ? img->height : ay + cfg->window_px;
}

int lr_tile_raw_layer(const LrTile *t, float depth, float coc_px, const float motion_px[2])
{
    bool split = splits_motion(t);
    if (!(depth < INFINITY)) return lr_tile_raw_count(t) - 1; /* misses: behind everything */
    int k = 0;
    for (int i = 0; i < t->n_depth; ++i) k += depth > t->depth_bound[i];
    for (int i = 0; i < t->n_coc; ++i) k += coc_px > t->coc_bound_px[i];
    if (!split) return k;
    return 2 * k + (lr_key_moving(motion_px) ? 0 : 1);
}

int lr_tile_layer_of(const LrTile *tile, const LrKey *s) { return tile->compact[lr_tile_raw_layer(tile, s->depth, s->coc_px, s->motion_px)]; }

/* fminf / fmaxf without a libm call: the operands are finite or +-INFINITY (coc_px is made
 * finite by the caller, depth is a distance or INFINITY) */
static inline float min_f(float a, float b) { return b < a ? b : a; }
static inline float max_f(float a, float b) { return b > a ? b : a; }

int lr_config_uniform_layers(const LrConfig *cfg)
{
    return cfg->uniform_layers < 1 ? 1 : cfg->uniform_layers > 7 ? 7 : cfg->uniform_layers;
}

int lr_config_gap_slabs(const LrConfig *cfg)
{
    return cfg->gap_slabs > LR_MAX_SPLIT_SLABS ? LR_MAX_SPLIT_SLABS : cfg->gap_slabs;
}

int lr_config_still_gap_slabs(const LrConfig *cfg)
{
    int gap = lr_config_gap_slabs(cfg);
    if (gap <= 0 || cfg->still_gap_slabs <= 0) return gap;
    return cfg->still_gap_slabs > LR_MAX_COC_BOUNDS + 1 ? LR_MAX_COC_BOUNDS + 1 : cfg->still_gap_slabs;
}

bool lr_config_counts_moving(const LrConfig *cfg) { return lr_config_still_gap_slabs(cfg) != lr_config_gap_slabs(cfg); }

void lr_tile_bounds(const LrConfig *cfg, float zmin, float zmax, LrTile *t)
{
    memset(t, 0, sizeof *t);
    /* Uniform depth layers, plus boundaries symmetric about the focal plane (c = 0) at
     * c = +-step, +-4 step, ... so that the slopes near focus, where the filter is most
     * sensitive to the slope range (1/c), share a layer only with similar slopes. */
    int uniform = lr_config_uniform_layers(cfg);
    if (zmin < zmax)
        for (int i = 1; i < uniform; ++i) t->depth_bound[t->n_depth++] = zmin + (zmax - zmin) * (float)i / (float)uniform;
    int half = cfg->focus_bounds / 2 > LR_MAX_SPLIT_SLABS / 2 ? LR_MAX_SPLIT_SLABS / 2 : cfg->focus_bounds / 2;
    for (int k = half; k >= 1; --k) t->coc_bound_px[t->n_coc++] = -cfg->focus_step_px * (float)(k * k);
    for (int k = 1; k <= half; ++k) t->coc_bound_px[t->n_coc++] = cfg->focus_step_px * (float)(k * k);
}

void lr_gap_edges(float *edges)
{
    double s_max = asinh(LR_GAP_CMAX_PX / LR_GAP_C0_PX);
    for (int i = 0; i < LR_GAP_BINS - 1; ++i) edges[i] = (float)(LR_GAP_C0_PX * sinh(s_max * (2.0 * (i + 1) / LR_GAP_BINS - 1.0)));
}

int lr_gap_bin(const float *edges, float coc_px)
{
    /* Binary lifting, as lr.cl does without the bounds test (its edges are padded with
     * +infinity): "c > edge" holds for a prefix of the ascending edges, and b grows to that
     * prefix's length by steps of 32, 16, ..., 1 (none of c = NaN, 0; all of +inf, 47). */
    int b = 0;
    for (int step = 32; step >= 1; step /= 2)
        if (b + step <= LR_GAP_BINS - 1 && coc_px > edges[b + step - 1]) b += step;
    return b;
}

int lr_gap_bounds(const int *hist, const float *edges, int max_bounds, float *bounds)
{
    int occ[LR_GAP_BINS], m = 0;
    int64_t pre[LR_GAP_BINS + 1];
    pre[0] = 0;
    for (int b = 0; b < LR_GAP_BINS; ++b)
        if (hist[b] > 0) occ[m] = b, pre[m + 1] = pre[m] + hist[b], ++m;
    if (max_bounds > LR_MAX_COC_BOUNDS) max_bounds = LR_MAX_COC_BOUNDS;
    int groups = max_bounds + 1 < m ? max_bounds + 1 : m;
    if (groups <= 1) return 0;
    /* best[g][j]: least cost of occupied bins 0..j in g + 1 groups; from[g][j]: the last bin
     * of the previous group (ties: the smallest) */
    int64_t best[LR_MAX_COC_BOUNDS + 1][LR_GAP_BINS];
    int from[LR_MAX_COC_BOUNDS + 1][LR_GAP_BINS];
    for (int j = 0; j < m; ++j) {
        int64_t w = occ[j] - occ[0] + 1;
        best[0][j] = pre[j + 1] * w * w;
    }
    for (int g = 1; g < groups; ++g)
        for (int j = g; j < m; ++j) {
            best[g][j] = INT64_MAX;
            from[g][j] = g - 1;
            for (int i = g - 1; i < j; ++i) {
                int64_t w = occ[j] - occ[i + 1] + 1, c = best[g - 1][i] + (pre[j + 1] - pre[i + 1]) * w * w;
                if (c < best[g][j]) best[g][j] = c, from[g][j] = i;
            }
        }
    for (int g = groups - 1, j = m - 1; g >= 1; --g) {
        j = from[g][j];
        bounds[g - 1] = edges[occ[j]];
    }
    return groups - 1;
}

void lr_tile_bounds_gaps(const LrConfig *cfg, float zmin, float zmax, const int *hist, const float *edges, long moving_hits,
                         LrTile *t)
{
    memset(t, 0, sizeof *t);
    /* A window whose hits (almost) all stay put need not split its slabs into moving and
     * static layers (splits_motion is false past 8 slabs), so its raw ids go to finer CoC
     * slabs; its few moving samples then share their slab's layer with the static ones
     * (integer arithmetic, as lr.cl: the same choice). docs/algorithms.md 8.47 */
    long hits = 0;
    for (int b = 0; b < LR_GAP_BINS; ++b) hits += hist[b];
    int slabs = moving_hits * 1000 > (long)cfg->still_moving_permille * hits ? lr_config_gap_slabs(cfg) : lr_config_still_gap_slabs(cfg);
    t->n_coc = lr_gap_bounds(hist, edges, slabs - 1, t->coc_bound_px);
    /* a window with fewer occupied CoC bins than slabs (a pinhole: every c = 0) spends the
     * rest on uniform depth layers, as without the histogram */
    int uniform = lr_config_uniform_layers(cfg);
    int n = uniform - 1 < slabs - 1 - t->n_coc ? uniform - 1 : slabs - 1 - t->n_coc;
    if (zmin < zmax)
        for (int i = 1; i <= n; ++i) t->depth_bound[t->n_depth++] = zmin + (zmax - zmin) * (float)i / (float)(n + 1);
}

/* The statistics of lr_tile_finish, the C version of lr.cl's lr_tile_stats (same sums in the
 * same order, so that both give the same partitions). */
static void tile_stats(const LrSamples *img, const LrConfig *cfg, int tx, int ty, LrTile *t, LrLayerStats *st)
{
    int x0, y0, x1, y1;
    lr_tile_window(img, cfg, tx, ty, &x0, &y0, &x1, &y1);
    if (cfg->still_tiles) { /* a still tile has no samples to partition: no layers */
        int ntx, nty;
        lr_tile_count(img, cfg, &ntx, &nty);
        if (cfg->still_tiles[ty * ntx + tx]) x1 = x0, y1 = y0;
    }
    /* depth range of the window's hits */
    float zmin = INFINITY, zmax = -INFINITY, edges[LR_GAP_BINS - 1];
    int hist[LR_GAP_BINS] = {0};
    long moving_hits = 0;
    bool gaps = cfg->gap_slabs > 0;
    /* the moving hits decide only between two slab counts: none to count when they agree
     * (the still-window rule off, 8.47), as lr.cl's lr_tile_stats */
    bool count_moving = lr_config_counts_moving(cfg);
    if (gaps) lr_gap_edges(edges);
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int k = 0; k < img->spp; ++k) {
                const LrKey *s = &img->key[((size_t)py * img->width + px) * img->spp + k];
                float z = s->depth;
                if (z < INFINITY) {
                    zmin = min_f(zmin, z), zmax = max_f(zmax, z);
                    if (gaps) hist[lr_gap_bin(edges, s->coc_px)]++;
                    if (count_moving) moving_hits += lr_key_moving(s->motion_px);
                }
            }
    if (gaps) lr_tile_bounds_gaps(cfg, zmin, zmax, hist, edges, moving_hits, t);
    else lr_tile_bounds(cfg, zmin, zmax, t);
    int raw_n = lr_tile_raw_count(t);
    int ix0, iy0, ix1, iy1;
    lr_tile_pixels(img, cfg, tx, ty, &ix0, &iy0, &ix1, &iy1);
    double mx[LR_MAX_LAYERS + 1], my[LR_MAX_LAYERS + 1], bright[LR_MAX_LAYERS + 1];
    for (int i = 0; i < raw_n; ++i) {
        st[i] = (LrLayerStats){0, 1.0f, 0.0f, INFINITY, -INFINITY, INFINITY, -INFINITY, 0.0f, 0.0f, {{0}}};
        mx[i] = my[i] = bright[i] = 0.0;
    }
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int k = 0; k < img->spp; ++k) {
                size_t i = ((size_t)py * img->width + px) * img->spp + k;
                const LrKey *s = &img->key[i];
                int r = lr_tile_raw_layer(t, s->depth, s->coc_px, s->motion_px);
                st[r].count++;
                if (px >= ix0 && px < ix1 && py >= iy0 && py < iy1) { /* the tile's own pixels (LrTilt) */
                    const LrPlace *pl = &img->place[i];
                    float c = s->coc_px;
                    lr_tilt_add(&st[r].tilt, (pl->x_px - (float)x0) - c * pl->u, (pl->y_px - (float)y0) - c * pl->v, c);
                }
                mx[r] += s->motion_px[0];
                my[r] += s->motion_px[1];
                float b = img->bright[i]; /* NaN (not finite) for a non-finite radiance */
                bright[r] += isfinite(b) ? b : 0.0f;
                st[r].c_min_px = min_f(st[r].c_min_px, s->coc_px);
                st[r].c_max_px = max_f(st[r].c_max_px, s->coc_px);
            }
    for (int i = 0; i < raw_n; ++i) st[i].bright_sum = (float)bright[i];
    /* Figure 4: the mean motion sets psi */
    for (int i = 0; i < raw_n; ++i) {
        if (!st[i].count) continue;
        double ax = mx[i] / st[i].count, ay = my[i] / st[i].count, len = sqrt(ax * ax + ay * ay);
        st[i].cos_psi = len > 0 ? (float)(ax / len) : 1.0f;
        st[i].sin_psi = len > 0 ? (float)(ay / len) : 0.0f;
    }
    /* second sweep: motion ranges in each layer's rotated frame */
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int k = 0; k < img->spp; ++k) {
                const LrKey *s = &img->key[((size_t)py * img->width + px) * img->spp + k];
                LrLayerStats *a = &st[lr_tile_raw_layer(t, s->depth, s->coc_px, s->motion_px)];
                float along = a->cos_psi * s->motion_px[0] + a->sin_psi * s->motion_px[1];
                float across = -a->sin_psi * s->motion_px[0] + a->cos_psi * s->motion_px[1];
                a->d_min_px = min_f(a->d_min_px, along);
                a->d_max_px = max_f(a->d_max_px, along);
                a->across_px = max_f(a->across_px, fabsf(across));
            }
}

float lr_layer_contrast(const LrLayerStats *st, int raw_n, int i)
{
    double n_rest = 0.0, b_rest = 0.0;
    for (int k = 0; k < raw_n; ++k)
        if (k != i) n_rest += st[k].count, b_rest += st[k].bright_sum;
    if (!(st[i].count > 0) || !(st[i].bright_sum > 0.0f) || !(n_rest > 0.0)) return 1.0f;
    double mean = st[i].bright_sum / (double)st[i].count, rest = b_rest / n_rest;
    return rest > 0.0 ? (float)(mean / rest) : INFINITY;
}

void lr_tilt_ramp(const LrTilt *tilt, float eta_px, float rho_px, float *ramp_x_px, float *ramp_y_px)
{
    *ramp_x_px = *ramp_y_px = 0.0f;
    const float *m = tilt->sum;
    if (!(m[8] >= 16.0f)) return;
    double inv = 1.0 / m[8], x = m[0] * inv, y = m[1] * inv, c = m[2] * inv;
    double vxx = m[3] * inv - x * x, vyy = m[4] * inv - y * y, vxy = m[5] * inv - x * y;
    double cx = m[6] * inv - x * c, cy = m[7] * inv - y * c;
    double det = vxx * vyy - vxy * vxy, half = 0.5 * (vxx - vyy);
    /* the points' spread along their narrowest direction (the covariance's smaller eigenvalue,
     * px^2): a layer a few pixels wide in some direction (under sqrt(12) px, the variance of
     * such a band being its width^2 / 12) has no gradient across it worth fitting */
    double narrow = 0.5 * (vxx + vyy) - sqrt(half * half + vxy * vxy);
    if (!(narrow >= 1.0) || !(det > 0.0)) return;
    double gx = (cx * vyy - cy * vxy) / det, gy = (cy * vxx - cx * vxy) / det;
    float rx = (float)(-eta_px * gx / 4.0), ry = (float)(-rho_px * gy / 4.0);
    if (isfinite(rx) && isfinite(ry)) *ramp_x_px = rx, *ramp_y_px = ry;
}

/* The smallest blur radius of a layer's slopes (px): its least defocused part's circle of
 * confusion or half its slowest streak, 0 for a range across the focal plane or across still. */
static float smallest_blur_px(const LrSlopes *s)
{
    float c = s->c_min_px <= 0.0f && s->c_max_px >= 0.0f ? 0.0f : fminf(fabsf(s->c_min_px), fabsf(s->c_max_px));
    float d = s->d_min_px <= 0.0f && s->d_max_px >= 0.0f ? 0.0f : fminf(fabsf(s->d_min_px), fabsf(s->d_max_px));
    return fmaxf(c, 0.5f * d);
}

float lr_bright_clamp_px(const LrConfig *cfg, const LrSlopes *slopes)
{
    /* A still layer blurred by its lens past the still band keeps 8.24's clamp: there the
     * Gaussian carries the lens blur, and sharing it was worth more than its tails (measured,
     * docs/algorithms.md 8.49). */
    bool still = slopes->d_min_px == 0.0f && slopes->d_max_px == 0.0f;
    if (still && !lr_blur_within_band(slopes, &cfg->filter)) return cfg->bright_clamp_px;
    /* A screen Gaussian of std s moves about 2 s / (sqrt(2 pi) R) of a blurred disk's light past
     * its radius R (the rim, 2 pi R long, times the Gaussian's mean overshoot s / sqrt(2 pi),
     * over the area pi R^2); at the contrast bright_contrast the background hides at most
     * 1 / bright_contrast of it: s <= sqrt(2 pi) R / (2 bright_contrast). Between the pixel
     * box's own std and bright_clamp_px. */
    float s = 1.2533141f * smallest_blur_px(slopes) / cfg->bright_contrast;
    return fminf(cfg->bright_clamp_px, fmaxf(cfg->bright_clamp_min_px, s));
}

LrFilter lr_layer_filter(const LrConfig *cfg, const LrSlopes *slopes, float contrast)
{
    LrFilterConfig fc = cfg->filter;
    if (cfg->bright_contrast > 0.0f && contrast >= cfg->bright_contrast) {
        float clamp = lr_bright_clamp_px(cfg, slopes);
        if (fc.sigma_clamp_px > clamp) fc.sigma_clamp_px = clamp;
    }
    return lr_filter_make(slopes, &fc);
}

/* Layer `back` taken into `front` (lr_layers_merge allowed it): its samples counted, the slope
 * ranges' union, the filter remade from it (the front layer's contrast kept). */
static void merge_into(const LrConfig *cfg, LrLayer *front, const LrLayer *back)
{
    LrSlopes *a = &front->slopes;
    const LrSlopes *b = &back->slopes;
    front->count += back->count;
    for (int k = 0; k < LR_TILT_SUMS; ++k) front->tilt.sum[k] += back->tilt.sum[k];
    a->c_min_px = min_f(a->c_min_px, b->c_min_px), a->c_max_px = max_f(a->c_max_px, b->c_max_px);
    a->d_min_px = min_f(a->d_min_px, b->d_min_px), a->d_max_px = max_f(a->d_max_px, b->d_max_px);
    front->filter = lr_layer_filter(cfg, a, front->contrast);
}

bool lr_motion_filter_kept(const LrConfig *cfg, float d_min_px, float d_max_px, float across_px)
{
    float mean_len = 0.5f * (d_min_px + d_max_px);
    float along_range = d_max_px - d_min_px, share = cfg->motion_spread_max * fabsf(mean_len);
    /* ...except when even the layer's slowest sample streaks past the window along psi
     * (motion_long_px, the window's width): then every edge of the layer is a ramp at
     * least that long, 8x the clamped screen sigma (Appendix C), so the filter's error on
     * it stays small, while without the filter the streak keeps 8 spp of noise and the
     * tiles on either side of one whose range is too wide differ by a 4-px blur (the
     * tile-sized blotches of focal_motion_area, docs/algorithms.md 8.32). */
    bool long_streaks = d_min_px >= cfg->motion_long_px;
    return (across_px <= 0.5f || across_px <= share) &&
           (long_streaks || along_range <= cfg->motion_range_px || along_range <= share);
}

void lr_tile_finish(const LrConfig *cfg, const LrLayerStats *st, LrTile *t)
{
    int raw_n = lr_tile_raw_count(t);
    t->layer_count = 0;
    for (int i = 0; i < raw_n; ++i) {
        if (!st[i].count) {
            t->compact[i] = -1;
            continue;
        }
        int j = t->compact[i] = t->layer_count++;
        t->layer[j].count = st[i].count;
        t->layer[j].cos_psi = st[i].cos_psi;
        t->layer[j].sin_psi = st[i].sin_psi;
        t->layer[j].slopes.c_min_px = st[i].c_min_px;
        t->layer[j].slopes.c_max_px = st[i].c_max_px;
        /* Figure 4: the spread across the mean direction widens [d_min, d_max]; LR section 5:
         * no clear direction, or too wide a range of speeds along it, no motion filter
         * (d = 0, psi = 0). The second rule is the paper's "too large variance in motion":
         * a static floor sharing a layer with a sphere moving 60 px got the filter of the
         * whole wedge [0, 60], which blurs the floor along the motion by about as much as
         * the sphere (8.3: twice the central blur at the wedge's edge); without it the
         * hard bench scene's error was 12% higher (8.11). */
        float perp = st[i].across_px;
        bool ok = lr_motion_filter_kept(cfg, st[i].d_min_px, st[i].d_max_px, perp);
        t->layer[j].motion_filter = ok;
        if (ok) {
            t->layer[j].slopes.d_min_px = st[i].d_min_px - perp;
            t->layer[j].slopes.d_max_px = st[i].d_max_px + perp;
        } else {
            t->layer[j].slopes.d_min_px = t->layer[j].slopes.d_max_px = 0.0f;
            t->layer[j].cos_psi = 1.0f;
            t->layer[j].sin_psi = 0.0f;
        }
        /* A light far brighter than what surrounds it: the screen share's shape error (a
         * few percent of the layer's light past the disk's rim, docs/algorithms.md 8.24)
         * would outshine the background, so the layer keeps its blur in its samples. */
        t->layer[j].contrast = lr_layer_contrast(st, raw_n, i);
        t->layer[j].tilt = st[i].tilt;
        t->layer[j].filter = lr_layer_filter(cfg, &t->layer[j].slopes, t->layer[j].contrast);
    }
    /* Neighbours with (almost) the same filter: one partition (8.34) whose slope ranges are
     * the union of theirs, its filter made from them as any layer's. A layer is compared with
     * the merged layer in front of it, so a run's filter stays within the tolerances of
     * each layer it takes. */
    int map[LR_MAX_LAYERS + 1], kept = 0;
    for (int j = 0; j < t->layer_count; ++j) {
        if (kept > 0 && lr_layers_merge(cfg, &t->layer[kept - 1].filter, t->layer[kept - 1].cos_psi, t->layer[kept - 1].sin_psi,
                                        &t->layer[j].filter, t->layer[j].cos_psi, t->layer[j].sin_psi)) {
            map[j] = kept - 1;
            merge_into(cfg, &t->layer[kept - 1], &t->layer[j]);
            continue;
        }
        if (kept != j) t->layer[kept] = t->layer[j];
        map[j] = kept++;
    }
    for (int i = 0; i < raw_n; ++i)
        if (t->compact[i] >= 0) t->compact[i] = map[t->compact[i]];
    for (int i = raw_n; i < LR_MAX_LAYERS + 1; ++i) t->compact[i] = -1; /* no such raw layer (lr.cl reads all 17) */
    t->layer_count = kept;
    /* The tilt's centroid shift (8.35) for the layers the lens alone blurs, in the unrotated
     * frame their shears are in. */
    for (int j = 0; j < kept; ++j) {
        LrLayer *l = &t->layer[j];
        l->ramp_x_px = l->ramp_y_px = 0.0f;
        if (cfg->tilt_ramp && l->cos_psi == 1.0f && l->sin_psi == 0.0f && l->filter.xi_px == 0.0f)
            lr_tilt_ramp(&l->tilt, l->filter.eta_px, l->filter.rho_px, &l->ramp_x_px, &l->ramp_y_px);
    }
}

/* |a - b| within share of |a| (both 0 included) */
static bool near_share(float a, float b, float share) { return fabsf(a - b) <= share * fabsf(a); }

bool lr_layers_merge(const LrConfig *cfg, const LrFilter *a, float a_cos, float a_sin, const LrFilter *b, float b_cos,
                     float b_sin)
{
    if (!(cfg->merge_shift_sigmas > 0.0f) || !(cfg->merge_sigma_share >= 0.0f)) return false;
    if (a_cos != b_cos || a_sin != b_sin || a->inv_sigma_u != b->inv_sigma_u || a->inv_sigma_v != b->inv_sigma_v ||
        a->inv_sigma_t != b->inv_sigma_t)
        return false;
    /* the farthest a sample lands from where its own layer's shear puts it: |u_r|, |v_r| <= 1,
     * |t - 1/2| <= 1/2 (eq. 16), against the front filter's narrower screen sigma */
    float shift_px = fabsf(a->eta_px - b->eta_px) + 0.5f * fabsf(a->xi_px - b->xi_px) + fabsf(a->rho_px - b->rho_px);
    float sigma_px = fminf(1.0f / a->inv_sigma_x_px, 1.0f / a->inv_sigma_y_px), k = cfg->merge_sigma_share;
    /* a share of 1/sigma is, to first order, the same share of sigma */
    return shift_px <= cfg->merge_shift_sigmas * sigma_px && near_share(a->inv_sigma_x_px, b->inv_sigma_x_px, k) &&
           near_share(a->inv_sigma_y_px, b->inv_sigma_y_px, k) && near_share(a->aperture_x_px, b->aperture_x_px, k) &&
           near_share(a->aperture_y_px, b->aperture_y_px, k) && near_share(a->shutter_x_px, b->shutter_x_px, k);
}

int lr_tile_layer_end(const LrTile *t, int raw_n, int j)
{
    int end = 0;
    for (int i = 0; i < raw_n; ++i)
        if (t->compact[i] == j) end = i + 1;
    return end;
}

void lr_tile_partition(const LrSamples *img, const LrConfig *cfg, int tx, int ty, LrTile *t)
{
    LrLayerStats st[LR_MAX_LAYERS + 1];
    tile_stats(img, cfg, tx, ty, t, st);
    lr_tile_finish(cfg, st, t);
}

LrSamples lr_samples_split(int width, int height, int spp, const LrSample *s)
{
    size_t n = (size_t)width * (size_t)height * (size_t)spp;
    LrKey *key = malloc(sizeof(LrKey) * n);
    LrPlace *place = malloc(sizeof(LrPlace) * n);
    float *bright = malloc(sizeof(float) * n);
    if (key && place && bright)
        for (size_t i = 0; i < n; ++i) lr_split_sample(&s[i], i, key, place, bright);
    else free(key), free(place), free(bright), key = NULL, place = NULL, bright = NULL;
    return (LrSamples){width, height, spp, key, place, bright};
}

void lr_samples_free(LrSamples *img)
{
    free((void *)img->key), free((void *)img->place), free((void *)img->bright);
    img->key = NULL, img->place = NULL, img->bright = NULL;
}
