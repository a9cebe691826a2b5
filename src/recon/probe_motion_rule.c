/* Which probe samples LR would blur along their motion (see probe_motion_rule.h). */
#include "recon/probe_motion_rule.h"

#include <math.h>
#include <stdlib.h>

#include "recon/lr/lr_partition.h"

enum { GROUPS = 8 }; /* sign of c x octave of |c| */

static bool sample_moves(const ProbeMotionSample *s)
{
    float mx = s->motion_px[0], my = s->motion_px[1];
    return isfinite(s->coc_slope_px) && mx * mx + my * my >= LR_MOVING_PX * LR_MOVING_PX;
}

/* The group of a moving sample: LR's layers split by depth, so by c (which grows with depth);
 * bands of |c| below 1, 1-4, 4-16 and above 16 px, on either side of the focal plane. */
static int coc_group(float coc_slope_px)
{
    float a = fabsf(coc_slope_px);
    int band = a < 1.0f ? 0 : a < 4.0f ? 1 : a < 16.0f ? 2 : 3;
    return (coc_slope_px < 0.0f ? 4 : 0) + band;
}

static bool inside(const ProbeMotionSample *s, float x0, float y0, float x1, float y1)
{
    return s->x >= x0 && s->x < x1 && s->y >= y0 && s->y < y1;
}

bool probe_motion_filterable(const ProbeMotionSample *s, int n, int width, int height, bool *filterable)
{
    for (int k = 0; k < n; ++k) filterable[k] = true;
    LrConfig cfg = lr_config_default();
    int tile = cfg.tile_px, margin = (cfg.window_px - cfg.tile_px) / 2; /* margin <= tile */
    int tiles_x = (width + tile - 1) / tile, tiles_y = (height + tile - 1) / tile, tiles = tiles_x * tiles_y;
    /* the moving samples listed by tile (a counting sort), so a window reads its 3 x 3 tiles */
    int *first = calloc((size_t)tiles + 1, sizeof *first), *order = malloc(sizeof *order * (size_t)(n > 0 ? n : 1));
    int *tile_of = malloc(sizeof *tile_of * (size_t)(n > 0 ? n : 1));
    if (!first || !order || !tile_of) {
        free(first), free(order), free(tile_of);
        return false;
    }
    for (int k = 0; k < n; ++k) {
        int tx = (int)floorf(s[k].x / (float)tile), ty = (int)floorf(s[k].y / (float)tile);
        bool in = sample_moves(&s[k]) && tx >= 0 && tx < tiles_x && ty >= 0 && ty < tiles_y;
        tile_of[k] = in ? ty * tiles_x + tx : -1;
        if (in) first[tile_of[k] + 1]++;
    }
    for (int t = 0; t < tiles; ++t) first[t + 1] += first[t];
    int *fill = calloc((size_t)tiles, sizeof *fill);
    if (!fill) {
        free(first), free(order), free(tile_of);
        return false;
    }
    for (int k = 0; k < n; ++k)
        if (tile_of[k] >= 0) order[first[tile_of[k]] + fill[tile_of[k]]++] = k;
    for (int ty = 0; ty < tiles_y; ++ty) {
        for (int tx = 0; tx < tiles_x; ++tx) {
            int own = ty * tiles_x + tx;
            if (first[own] == first[own + 1]) continue; /* nothing moves in the tile */
            float x0 = (float)(tx * tile - margin), y0 = (float)(ty * tile - margin);
            float x1 = (float)((tx + 1) * tile + margin), y1 = (float)((ty + 1) * tile + margin);
            /* each group's mean motion over the window, then its speeds along it and across */
            double sum[GROUPS][2] = {{0.0}};
            float along_min[GROUPS], along_max[GROUPS], across[GROUPS];
            int count[GROUPS] = {0};
            for (int g = 0; g < GROUPS; ++g) along_min[g] = INFINITY, along_max[g] = -INFINITY, across[g] = 0.0f;
            for (int pass = 0; pass < 2; ++pass) {
                for (int ny = ty - 1; ny <= ty + 1; ++ny) {
                    for (int nx = tx - 1; nx <= tx + 1; ++nx) {
                        if (nx < 0 || nx >= tiles_x || ny < 0 || ny >= tiles_y) continue;
                        int t = ny * tiles_x + nx;
                        for (int i = first[t]; i < first[t + 1]; ++i) {
                            const ProbeMotionSample *p = &s[order[i]];
                            if (!inside(p, x0, y0, x1, y1)) continue;
                            int g = coc_group(p->coc_slope_px);
                            if (pass == 0) {
                                sum[g][0] += p->motion_px[0], sum[g][1] += p->motion_px[1], count[g]++;
                                continue;
                            }
                            double len = hypot(sum[g][0], sum[g][1]);
                            double ax = len > 0.0 ? sum[g][0] / len : 1.0, ay = len > 0.0 ? sum[g][1] / len : 0.0;
                            float along = (float)(p->motion_px[0] * ax + p->motion_px[1] * ay);
                            float perp = (float)fabs(-p->motion_px[0] * ay + p->motion_px[1] * ax);
                            along_min[g] = fminf(along_min[g], along), along_max[g] = fmaxf(along_max[g], along);
                            across[g] = fmaxf(across[g], perp);
                        }
                    }
                }
            }
            /* the tile's own moving samples take their group's verdict */
            for (int i = first[own]; i < first[own + 1]; ++i) {
                int k = order[i], g = coc_group(s[k].coc_slope_px);
                filterable[k] = !count[g] || lr_motion_filter_kept(&cfg, along_min[g], along_max[g], across[g]);
            }
        }
    }
    free(first), free(order), free(tile_of), free(fill);
    return true;
}
