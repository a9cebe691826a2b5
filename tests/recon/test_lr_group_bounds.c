/* LR's layer bounds shared by a group of tiles (lr_partition.h: LrConfig.bounds_group_tiles,
 * lr_tile_group; docs/algorithms.md 8.44), against brute force over the samples:
 * - every tile of a group has the same bounds, and they are the bounds of the depth range and
 *   CoC histogram of the union of the group's windows, swept sample by sample here (with a
 *   group of 1, a window's own: the partition of every window by itself);
 * - the layers bracket every sample of every window of the group: the union's depth range
 *   holds each of them, and the depth bounds are ascending inside it;
 * - the statistics summed cell by cell (lr_stats_cell_px) are the window's: each layer's
 *   sample count and CoC range, and its tilt sums' count over the tile's own pixels, equal a
 *   sweep of the window's samples by the layer each falls in.
 * On frames whose tiles, windows and inset put the cells at 8, 2 and 16 px, with partial
 * groups at the right and bottom edges. (OpenCL against the C partition: test_lr_cl.c.) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "lr_scene.h"

static bool same_bounds(const LrTile *a, const LrTile *b)
{
    return a->n_depth == b->n_depth && a->n_coc == b->n_coc &&
           !memcmp(a->depth_bound, b->depth_bound, sizeof(float) * (size_t)a->n_depth) &&
           !memcmp(a->coc_bound_px, b->coc_bound_px, sizeof(float) * (size_t)a->n_coc);
}

/* The bounds of the hits of pixels [x0, x1) x [y0, y1), swept sample by sample; *zmin, *zmax
 * their depth range. */
static void rect_bounds(const LrSamples *img, const LrConfig *cfg, int x0, int y0, int x1, int y1, LrTile *t, float *zmin, float *zmax)
{
    float edges[LR_GAP_BINS - 1];
    int hist[LR_GAP_BINS] = {0};
    lr_gap_edges(edges);
    *zmin = INFINITY, *zmax = -INFINITY;
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int k = 0; k < img->spp; ++k) {
                const LrKey *s = &img->key[((size_t)py * img->width + px) * img->spp + k];
                if (!(s->depth < INFINITY)) continue;
                *zmin = fminf(*zmin, s->depth), *zmax = fmaxf(*zmax, s->depth);
                hist[lr_gap_bin(edges, s->coc_px)]++;
            }
    lr_tile_bounds_gaps(cfg, *zmin, *zmax, hist, edges, t);
}

typedef struct {
    int bad_share, bad_bounds, bad_bracket, bad_count, bad_coc, bad_tilt, tiles, groups_of_many;
} Tally;

static void check_frame(int w, int h, int spp, const LrTestLayer *layers, int nl, int tile_px, int window_px, int inset_px, int group,
                        Tally *y)
{
    LrSample *s = malloc(sizeof(LrSample) * (size_t)w * h * spp);
    lr_test_scene(s, w, h, spp, layers, nl, 17);
    unsigned seed = 3;
    for (int i = 0; i < w * h * spp; ++i) s[i].coc_px += 2.0f * (lr_test_unit(&seed) - 0.5f); /* a tilted surface's spread */
    LrSamples img = lr_samples_split(w, h, spp, s);
    LrConfig cfg = lr_config_default();
    cfg.tile_px = tile_px, cfg.window_px = window_px, cfg.inset_px = inset_px, cfg.bounds_group_tiles = group;
    int ntx, nty;
    lr_tile_count(&img, &cfg, &ntx, &nty);
    LrTile *tiles = malloc(sizeof(LrTile) * (size_t)ntx * nty);
    for (int ty = 0; ty < nty; ++ty)
        for (int tx = 0; tx < ntx; ++tx) lr_tile_partition(&img, &cfg, tx, ty, &tiles[ty * ntx + tx]);
    for (int ty = 0; ty < nty; ++ty)
        for (int tx = 0; tx < ntx; ++tx) {
            const LrTile *t = &tiles[ty * ntx + tx];
            ++y->tiles;
            /* the group, from the definition: tiles with the same (tx / group, ty / group) */
            int gx0 = tx / group * group, gy0 = ty / group * group;
            int gx1 = gx0 + group < ntx ? gx0 + group : ntx, gy1 = gy0 + group < nty ? gy0 + group : nty;
            int a0, b0, a1, b1;
            lr_tile_group(&img, &cfg, tx, ty, &a0, &b0, &a1, &b1);
            y->bad_share += a0 != gx0 || b0 != gy0 || a1 != gx1 || b1 != gy1;
            y->groups_of_many += (gx1 - gx0) * (gy1 - gy0) > 1;
            for (int uy = gy0; uy < gy1; ++uy)
                for (int ux = gx0; ux < gx1; ++ux) y->bad_share += !same_bounds(t, &tiles[uy * ntx + ux]);
            /* the union of the group's windows, and its bounds swept here */
            int ux0 = w, uy0 = h, ux1 = 0, uy1 = 0;
            for (int uy = gy0; uy < gy1; ++uy)
                for (int ux = gx0; ux < gx1; ++ux) {
                    int x0, y0, x1, y1;
                    lr_tile_window(&img, &cfg, ux, uy, &x0, &y0, &x1, &y1);
                    ux0 = x0 < ux0 ? x0 : ux0, uy0 = y0 < uy0 ? y0 : uy0, ux1 = x1 > ux1 ? x1 : ux1, uy1 = y1 > uy1 ? y1 : uy1;
                }
            LrTile want;
            float zmin, zmax;
            rect_bounds(&img, &cfg, ux0, uy0, ux1, uy1, &want, &zmin, &zmax);
            y->bad_bounds += !same_bounds(t, &want);
            for (int i = 0; i < t->n_depth; ++i)
                y->bad_bracket += !(t->depth_bound[i] > zmin && t->depth_bound[i] < zmax) || (i > 0 && !(t->depth_bound[i] > t->depth_bound[i - 1]));
            /* the window's samples by layer: counts, CoC ranges, own-pixel counts */
            int x0, y0, x1, y1, ix0, iy0, ix1, iy1;
            lr_tile_window(&img, &cfg, tx, ty, &x0, &y0, &x1, &y1);
            lr_tile_pixels(&img, &cfg, tx, ty, &ix0, &iy0, &ix1, &iy1);
            int count[LR_MAX_LAYERS] = {0}, own[LR_MAX_LAYERS] = {0};
            float cmin[LR_MAX_LAYERS], cmax[LR_MAX_LAYERS];
            for (int j = 0; j < LR_MAX_LAYERS; ++j) cmin[j] = INFINITY, cmax[j] = -INFINITY;
            for (int py = y0; py < y1; ++py)
                for (int px = x0; px < x1; ++px)
                    for (int k = 0; k < spp; ++k) {
                        const LrKey *key = &img.key[((size_t)py * w + px) * spp + k];
                        if (key->depth < INFINITY) y->bad_bracket += !(key->depth >= zmin && key->depth <= zmax);
                        int j = lr_tile_layer_of(t, key);
                        if (j < 0 || j >= t->layer_count) {
                            ++y->bad_count;
                            continue;
                        }
                        count[j]++;
                        own[j] += px >= ix0 && px < ix1 && py >= iy0 && py < iy1;
                        cmin[j] = fminf(cmin[j], key->coc_px), cmax[j] = fmaxf(cmax[j], key->coc_px);
                    }
            for (int j = 0; j < t->layer_count; ++j) {
                y->bad_count += t->layer[j].count != count[j];
                y->bad_coc += t->layer[j].slopes.c_min_px != cmin[j] || t->layer[j].slopes.c_max_px != cmax[j];
                y->bad_tilt += t->layer[j].tilt.sum[8] != (float)own[j];
            }
        }
    free(tiles);
    lr_samples_free(&img);
    free(s);
}

int main(void)
{
    /* a moving disk in front of focus, a static one behind it, over a plane: three surfaces,
     * depths and slopes apart, so that windows differ in their ranges and gaps */
    LrTestLayer scene[3] = {{1.5f, -9.0f, {12.0f, 3.0f}, 20.0f, 22.0f, 11.0f, 0.6f},
                            {3.0f, 2.5f, {0.0f, 0.0f}, 58.0f, 40.0f, 14.0f, 0.8f},
                            {7.0f, 6.0f, {0.0f, 0.0f}, 0, 0, 0, 0.3f}};
    for (int group = 1; group <= LR_MAX_BOUNDS_GROUP; ++group) {
        Tally y = {0};
        check_frame(83, 61, 4, scene, 3, 16, 32, 0, group, &y);  /* 8-px cells; 6 x 4 tiles */
        check_frame(83, 61, 4, scene, 3, 16, 32, 8, group, &y);  /* an overscan band */
        check_frame(83, 61, 4, scene, 3, 16, 28, 5, group, &y);  /* margin 6: 2-px cells off the 8-px grid */
        check_frame(90, 75, 2, scene, 3, 32, 64, 16, group, &y); /* 16-px cells */
        CHECK(y.bad_share == 0 && y.bad_bounds == 0 && y.bad_bracket == 0);
        CHECK(y.bad_count == 0 && y.bad_coc == 0 && y.bad_tilt == 0);
        CHECK(group == 1 ? y.groups_of_many == 0 : y.groups_of_many > 0);
        if (y.bad_share || y.bad_bounds || y.bad_bracket || y.bad_count || y.bad_coc || y.bad_tilt)
            fprintf(stderr, "group %d: %d tiles; shared %d, bounds %d, bracket %d, count %d, coc %d, tilt %d wrong\n", group, y.tiles,
                    y.bad_share, y.bad_bounds, y.bad_bracket, y.bad_count, y.bad_coc, y.bad_tilt);
    }
    /* the cells: gcd(tile, margin), the tile itself without a margin */
    LrConfig cfg = lr_config_default();
    CHECK(lr_stats_cell_px(&cfg) == 8);
    cfg.window_px = 28;
    CHECK(lr_stats_cell_px(&cfg) == 2);
    cfg.window_px = 16;
    CHECK(lr_stats_cell_px(&cfg) == 16);
    cfg.bounds_group_tiles = 9;
    CHECK(lr_config_bounds_group(&cfg) == LR_MAX_BOUNDS_GROUP);
    cfg.bounds_group_tiles = 0;
    CHECK(lr_config_bounds_group(&cfg) == 1);
    CHECK_DONE();
}
