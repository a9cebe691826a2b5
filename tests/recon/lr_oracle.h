/* The slow oracle for LR's reconstruction: per pixel and per layer, a direct gather of every
 * window sample with the weight of LR eq. 14 (its lens and time factors, times the screen
 * profile along and across the motion, lr_screen_taps: the Gaussians, or with flat weights
 * the Gaussian, disk and box shares; or the round filter's 2D table, lr_screen_round),
 * evaluated in the layer's rotated frame at the sample's
 * reprojected (quantised) pixel, then eq. 17. No grids, no
 * separable passes. Exact agreement with the separable form needs the offsets to be whole
 * pixels along both rotated axes, i.e. psi a multiple of 90 degrees. */
#ifndef WEDGE_TESTS_LR_ORACLE_H
#define WEDGE_TESTS_LR_ORACLE_H

#include <math.h>

#include "recon/lr/lr_reconstruct.h"

static void lr_oracle_pixel(const LrSamples *img, const LrConfig *cfg, int px, int py, double rgb[3])
{
    int tx = px / cfg->tile_px, ty = py / cfg->tile_px;
    LrTile tile;
    lr_tile_partition(img, cfg, tx, ty, &tile);
    int x0, y0, x1, y1;
    lr_tile_window(img, cfg, tx, ty, &x0, &y0, &x1, &y1);
    double trans = 1.0;
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    for (int j = 0; j < tile.layer_count; ++j) {
        const LrFilter *f = &tile.layer[j].filter;
        double cp = tile.layer[j].cos_psi, sp = tile.layer[j].sin_psi;
        int rx, ry;
        lr_screen_radii_px(f, cfg, &rx, &ry);
        float taps_x[LR_MAX_RADIUS_PX + 1], taps_y[LR_MAX_RADIUS_PX + 1];
        lr_screen_taps(f, cfg, false, rx, taps_x);
        lr_screen_taps(f, cfg, true, ry, taps_y);
        int rr = 0;
        float round[LR_ROUND_TABLE];
        bool is_round = lr_screen_round(f, cfg, (float)cp, (float)sp, &rr, round);
        double A = 0, W = 0, E[3] = {0, 0, 0};
        for (int sy = y0; sy < y1; ++sy)
            for (int sx = x0; sx < x1; ++sx)
                for (int k = 0; k < img->spp; ++k) {
                    size_t si = ((size_t)sy * img->width + sx) * img->spp + k;
                    const LrPlace *s = &img->place[si];
                    int layer = lr_tile_layer_of(&tile, &img->key[si]);
                    if (layer < j) continue;
                    float p, q, wuvt;
                    lr_reproject(s, (float)cp, (float)sp, f, &p, &q, &wuvt);
                    int cx = (int)floor(p), cy = (int)floor(q);
                    if (cx < x0 || cy < y0 || cx >= x1 || cy >= y1) continue;
                    /* offsets along (k1) and across (k2) the motion, whole pixels here */
                    double dx = cx - px, dy = cy - py;
                    double k1 = floor(cp * dx + sp * dy + 0.5), k2 = floor(-sp * dx + cp * dy + 0.5);
                    if (is_round) { /* one 2D weight over the squared offset (lr_screen_round) */
                        int d2 = (int)(dx * dx + dy * dy);
                        if (d2 > rr * rr) continue;
                        double w = wuvt * round[d2];
                        W += w;
                        if (layer == j) {
                            A += w;
                            for (int c = 0; c < 3; ++c) E[c] += w * s->L[c];
                        }
                        continue;
                    }
                    if (fabs(k1) > rx || fabs(k2) > ry) continue;
                    /* the separable passes see the intermediate pixel P + k2 (across) too */
                    int mx = px + (int)floor(-k2 * sp + 0.5), my = py + (int)floor(k2 * cp + 0.5);
                    if (mx < x0 || my < y0 || mx >= x1 || my >= y1) continue;
                    double w = wuvt * taps_x[(int)fabs(k1)] * taps_y[(int)fabs(k2)];
                    W += w;
                    if (layer == j) {
                        A += w;
                        for (int c = 0; c < 3; ++c) E[c] += w * s->L[c];
                    }
                }
        if (!(W > 0)) continue;
        for (int c = 0; c < 3; ++c) rgb[c] += trans * E[c] / W;
        trans *= 1.0 - A / W;
    }
}

#endif
