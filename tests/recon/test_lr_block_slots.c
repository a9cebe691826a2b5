/* LR's partition statistics summed from its 8x8 blocks' slot sums (lr_partition.h:
 * lr_stats_by_block; docs/algorithms.md 8.44) against brute force: for every tile, each layer's
 * sample count, CoC range and own-pixel count (the tilt's) equal a sweep of the window's
 * samples by the layer each falls in (lr_tile_layer_of), and its tilt sums agree with the
 * sweep's (double) to float rounding. On frames where the slots combine whole (one depth per
 * surface) and where depths spread within a surface so that some blocks' slots straddle a depth
 * bound and are taken sample by sample: both paths are checked to occur. The rule itself: the
 * histogram bounds, windows and own pixels on the block grid. (OpenCL against the C
 * partition, both paths: test_lr_cl.c.) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "lr_scene.h"

typedef struct {
    int bad_count, bad_coc, bad_own, bad_tilt, straddled, combined;
} Tally;

/* Whether block (bx, by)'s samples of some slot (CoC bin x moving, hits only) straddle one of
 * t's depth bounds, found by brute force. */
static bool block_straddles(const LrSamples *img, const LrTile *t, const float *edges, int bx, int by)
{
    float lo[LR_BLOCK_SLOTS], hi[LR_BLOCK_SLOTS];
    for (int i = 0; i < LR_BLOCK_SLOTS; ++i) lo[i] = INFINITY, hi[i] = -INFINITY;
    for (int py = by * LR_BLOCK_PX; py < (by + 1) * LR_BLOCK_PX && py < img->height; ++py)
        for (int px = bx * LR_BLOCK_PX; px < (bx + 1) * LR_BLOCK_PX && px < img->width; ++px)
            for (int k = 0; k < img->spp; ++k) {
                const LrKey *s = &img->key[((size_t)py * img->width + px) * img->spp + k];
                if (!(s->depth < INFINITY)) continue;
                bool moving = hypotf(s->motion_px[0], s->motion_px[1]) >= LR_MOVING_PX;
                int e = 2 * lr_gap_bin(edges, s->coc_px) + !moving;
                lo[e] = fminf(lo[e], s->depth), hi[e] = fmaxf(hi[e], s->depth);
            }
    for (int e = 0; e < LR_BLOCK_SLOTS; ++e)
        for (int j = 0; j < t->n_depth; ++j)
            if (lo[e] <= t->depth_bound[j] && t->depth_bound[j] < hi[e]) return true;
    return false;
}

static void check_frame(int w, int h, int spp, const LrTestLayer *layers, int nl, float coc_spread, float depth_spread, int inset_px,
                        Tally *y)
{
    LrSample *s = malloc(sizeof(LrSample) * (size_t)w * h * spp);
    lr_test_scene(s, w, h, spp, layers, nl, 23);
    unsigned seed = 9;
    for (int i = 0; i < w * h * spp; ++i) {
        s[i].coc_px += coc_spread * (lr_test_unit(&seed) - 0.5f);
        if (s[i].depth < INFINITY) s[i].depth *= 1.0f + depth_spread * (lr_test_unit(&seed) - 0.5f);
    }
    LrSamples img = lr_samples_split(w, h, spp, s);
    LrConfig cfg = lr_config_default();
    cfg.inset_px = inset_px;
    CHECK(lr_stats_by_block(&cfg));
    float edges[LR_GAP_BINS - 1];
    lr_gap_edges(edges);
    int ntx, nty;
    lr_tile_count(&img, &cfg, &ntx, &nty);
    for (int ty = 0; ty < nty; ++ty)
        for (int tx = 0; tx < ntx; ++tx) {
            LrTile t;
            lr_tile_partition(&img, &cfg, tx, ty, &t);
            int x0, y0, x1, y1, ix0, iy0, ix1, iy1;
            lr_tile_window(&img, &cfg, tx, ty, &x0, &y0, &x1, &y1);
            lr_tile_pixels(&img, &cfg, tx, ty, &ix0, &iy0, &ix1, &iy1);
            for (int by = y0 / LR_BLOCK_PX; by * LR_BLOCK_PX < y1; ++by)
                for (int bx = x0 / LR_BLOCK_PX; bx * LR_BLOCK_PX < x1; ++bx) {
                    bool st = block_straddles(&img, &t, edges, bx, by);
                    y->straddled += st, y->combined += !st;
                }
            int count[LR_MAX_LAYERS] = {0}, own[LR_MAX_LAYERS] = {0};
            float cmin[LR_MAX_LAYERS], cmax[LR_MAX_LAYERS];
            double tilt[LR_MAX_LAYERS][LR_TILT_SUMS] = {{0}};
            for (int j = 0; j < LR_MAX_LAYERS; ++j) cmin[j] = INFINITY, cmax[j] = -INFINITY;
            for (int py = y0; py < y1; ++py)
                for (int px = x0; px < x1; ++px)
                    for (int k = 0; k < spp; ++k) {
                        size_t i = ((size_t)py * w + px) * spp + k;
                        const LrKey *key = &img.key[i];
                        int j = lr_tile_layer_of(&t, key);
                        if (j < 0 || j >= t.layer_count) {
                            ++y->bad_count;
                            continue;
                        }
                        count[j]++;
                        cmin[j] = fminf(cmin[j], key->coc_px), cmax[j] = fmaxf(cmax[j], key->coc_px);
                        if (px >= ix0 && px < ix1 && py >= iy0 && py < iy1) {
                            const LrPlace *p = &img.place[i];
                            double c = key->coc_px, xs = (p->x_px - (float)x0) - key->coc_px * p->u, ys = (p->y_px - (float)y0) - key->coc_px * p->v;
                            double v[LR_TILT_SUMS] = {xs, ys, c, xs * xs, ys * ys, xs * ys, xs * c, ys * c, 1.0};
                            for (int m = 0; m < LR_TILT_SUMS; ++m) tilt[j][m] += v[m];
                            own[j]++;
                        }
                    }
            for (int j = 0; j < t.layer_count; ++j) {
                const LrLayer *l = &t.layer[j];
                y->bad_count += l->count != count[j];
                y->bad_coc += l->slopes.c_min_px != cmin[j] || l->slopes.c_max_px != cmax[j];
                y->bad_own += l->tilt.sum[8] != (float)own[j];
                /* float sums in another order: within a few ulps of the largest term's sum */
                for (int m = 0; m < LR_TILT_SUMS - 1; ++m) {
                    double scale = 1e-5 * (fabs(tilt[j][m]) + (double)own[j] * 100.0);
                    y->bad_tilt += !(fabs(l->tilt.sum[m] - tilt[j][m]) <= scale);
                }
            }
        }
    lr_samples_free(&img);
    free(s);
}

int main(void)
{
    /* a moving disk in front of focus, a static disk behind it, over a plane */
    LrTestLayer scene[3] = {{1.5f, -9.0f, {12.0f, 3.0f}, 20.0f, 22.0f, 11.0f, 0.6f},
                            {3.0f, 2.5f, {0.0f, 0.0f}, 58.0f, 40.0f, 14.0f, 0.8f},
                            {7.0f, 6.0f, {0.0f, 0.0f}, 0, 0, 0, 0.3f}};
    /* one slope everywhere: a window of few occupied bins, whose depth bounds split the surfaces
     * (and, with depths spread, some blocks' slots) */
    LrTestLayer flat[3] = {{1.5f, 0.5f, {6.0f, 0.0f}, 20.0f, 22.0f, 11.0f, 0.6f},
                           {3.0f, 0.5f, {0.0f, 0.0f}, 58.0f, 40.0f, 14.0f, 0.8f},
                           {7.0f, 0.5f, {0.0f, 0.0f}, 0, 0, 0, 0.3f}};
    Tally y = {0};
    check_frame(83, 61, 4, scene, 3, 1.5f, 0.0f, 0, &y);
    check_frame(83, 61, 4, scene, 3, 1.5f, 0.0f, 8, &y);
    check_frame(83, 61, 4, scene, 3, 0.0f, 0.8f, 0, &y);
    check_frame(83, 61, 4, flat, 3, 0.0f, 0.0f, 0, &y);
    check_frame(83, 61, 4, flat, 3, 0.0f, 0.8f, 0, &y);
    check_frame(83, 61, 4, flat, 3, 0.3f, 0.8f, 8, &y);
    CHECK(y.bad_count == 0 && y.bad_coc == 0 && y.bad_own == 0 && y.bad_tilt == 0);
    CHECK(y.straddled > 0 && y.combined > 0);
    fprintf(stderr, "blocks of windows: %d combined from their slots, %d sample by sample\n", y.combined, y.straddled);
    if (y.bad_count || y.bad_coc || y.bad_own || y.bad_tilt)
        fprintf(stderr, "wrong: count %d, coc %d, own %d, tilt %d\n", y.bad_count, y.bad_coc, y.bad_own, y.bad_tilt);
    /* the rule: the histogram's bounds, and windows and own pixels on the 8-px grid */
    LrConfig cfg = lr_config_default();
    CHECK(lr_stats_by_block(&cfg));
    cfg.gap_slabs = 0;
    CHECK(!lr_stats_by_block(&cfg));
    cfg = lr_config_default();
    cfg.inset_px = 4;
    CHECK(!lr_stats_by_block(&cfg));
    cfg.inset_px = 0, cfg.window_px = 24; /* windows on the grid, own pixels (margin 4) not */
    CHECK(!lr_stats_by_block(&cfg));
    CHECK_DONE();
}
