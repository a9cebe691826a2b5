/* LR partitions: tiles, depth layers and per-layer slopes (LR sections 5 and 7, Figure 4). */
#include "recon/lr/lr_partition.h"

#include <math.h>
#include <string.h>

LrConfig lr_config_default(void)
{
    LrConfig c;
    c.filter = lr_filter_config_default();
    c.tile_px = 16;
    c.window_px = 32;
    c.uniform_layers = 4;
    c.focus_bounds = 4;
    c.focus_step_px = 1.0f;
    c.motion_spread_max = 0.5f;
    c.filter.sigma_clamp_px = (float)(c.window_px - c.tile_px) / 4.0f; /* Appendix C */
    return c;
}

void lr_tile_window(const LrSamples *img, const LrConfig *cfg, int tx, int ty, int *x0, int *y0, int *x1, int *y1)
{
    int margin = (cfg->window_px - cfg->tile_px) / 2;
    int ax = tx * cfg->tile_px - margin, ay = ty * cfg->tile_px - margin;
    *x0 = ax < 0 ? 0 : ax;
    *y0 = ay < 0 ? 0 : ay;
    *x1 = ax + cfg->window_px > img->width ? img->width : ax + cfg->window_px;
    *y1 = ay + cfg->window_px > img->height ? img->height : ay + cfg->window_px;
}

static int raw_layer(const LrTile *t, const LrSample *s)
{
    if (!(s->depth < INFINITY)) return t->n_depth + t->n_coc + 1; /* misses: behind everything */
    int k = 0;
    for (int i = 0; i < t->n_depth; ++i) k += s->depth > t->depth_bound[i];
    for (int i = 0; i < t->n_coc; ++i) k += s->coc_px > t->coc_bound_px[i];
    return k;
}

int lr_tile_layer_of(const LrTile *tile, const LrSample *s) { return tile->compact[raw_layer(tile, s)]; }

/* Per-layer running sums over the window. */
typedef struct {
    int n;
    double mx, my;       /* sum of motion */
    float cmin, cmax;
} LayerAcc;

void lr_tile_partition(const LrSamples *img, const LrConfig *cfg, int tx, int ty, LrTile *t)
{
    memset(t, 0, sizeof *t);
    int x0, y0, x1, y1;
    lr_tile_window(img, cfg, tx, ty, &x0, &y0, &x1, &y1);
    /* depth range of the window's hits */
    float zmin = INFINITY, zmax = -INFINITY;
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int k = 0; k < img->spp; ++k) {
                float z = img->s[((size_t)py * img->width + px) * img->spp + k].depth;
                if (z < INFINITY) zmin = fminf(zmin, z), zmax = fmaxf(zmax, z);
            }
    /* Uniform depth layers, plus boundaries symmetric about the focal plane (c = 0) at
     * c = +-step, +-4 step, ... so that the slopes near focus, where the filter is most
     * sensitive to the slope range (1/c), share a layer only with similar slopes. */
    int uniform = cfg->uniform_layers < 1 ? 1 : cfg->uniform_layers > 7 ? 7 : cfg->uniform_layers;
    if (zmin < zmax)
        for (int i = 1; i < uniform; ++i) t->depth_bound[t->n_depth++] = zmin + (zmax - zmin) * (float)i / (float)uniform;
    int half = cfg->focus_bounds / 2 > LR_MAX_COC_BOUNDS / 2 ? LR_MAX_COC_BOUNDS / 2 : cfg->focus_bounds / 2;
    for (int k = half; k >= 1; --k) t->coc_bound_px[t->n_coc++] = -cfg->focus_step_px * (float)(k * k);
    for (int k = 1; k <= half; ++k) t->coc_bound_px[t->n_coc++] = cfg->focus_step_px * (float)(k * k);

    int raw_n = t->n_depth + t->n_coc + 2;
    LayerAcc acc[LR_MAX_LAYERS + 1];
    for (int i = 0; i < raw_n; ++i) acc[i] = (LayerAcc){0, 0, 0, INFINITY, -INFINITY};
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int k = 0; k < img->spp; ++k) {
                const LrSample *s = &img->s[((size_t)py * img->width + px) * img->spp + k];
                LayerAcc *a = &acc[raw_layer(t, s)];
                a->n++;
                a->mx += s->motion_px[0];
                a->my += s->motion_px[1];
                a->cmin = fminf(a->cmin, s->coc_px);
                a->cmax = fmaxf(a->cmax, s->coc_px);
            }
    for (int i = 0; i < raw_n; ++i) {
        if (!acc[i].n) {
            t->compact[i] = -1;
            continue;
        }
        int j = t->compact[i] = t->layer_count++;
        t->layer[j].count = acc[i].n;
        /* Figure 4: mean motion sets psi; the spread across it widens [d_min, d_max]. */
        double mx = acc[i].mx / acc[i].n, my = acc[i].my / acc[i].n, mlen = sqrt(mx * mx + my * my);
        float cp = mlen > 0 ? (float)(mx / mlen) : 1.0f, sp = mlen > 0 ? (float)(my / mlen) : 0.0f;
        t->layer[j].cos_psi = cp;
        t->layer[j].sin_psi = sp;
        t->layer[j].slopes.c_min_px = acc[i].cmin;
        t->layer[j].slopes.c_max_px = acc[i].cmax;
    }
    /* second sweep: motion ranges in each layer's rotated frame */
    float dmin[LR_MAX_LAYERS], dmax[LR_MAX_LAYERS], perp[LR_MAX_LAYERS];
    for (int j = 0; j < t->layer_count; ++j) dmin[j] = INFINITY, dmax[j] = -INFINITY, perp[j] = 0;
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int k = 0; k < img->spp; ++k) {
                const LrSample *s = &img->s[((size_t)py * img->width + px) * img->spp + k];
                int j = lr_tile_layer_of(t, s);
                float cp = t->layer[j].cos_psi, sp = t->layer[j].sin_psi;
                float along = cp * s->motion_px[0] + sp * s->motion_px[1];
                float across = -sp * s->motion_px[0] + cp * s->motion_px[1];
                dmin[j] = fminf(dmin[j], along);
                dmax[j] = fmaxf(dmax[j], along);
                perp[j] = fmaxf(perp[j], fabsf(across));
            }
    for (int j = 0; j < t->layer_count; ++j) {
        float mean_len = 0.5f * (dmin[j] + dmax[j]);
        bool ok = perp[j] <= 0.5f || perp[j] <= cfg->motion_spread_max * fabsf(mean_len);
        t->layer[j].motion_filter = ok;
        if (ok) {
            t->layer[j].slopes.d_min_px = dmin[j] - perp[j];
            t->layer[j].slopes.d_max_px = dmax[j] + perp[j];
        } else { /* LR section 5: no clear direction, no motion filter (d = 0, psi = 0) */
            t->layer[j].slopes.d_min_px = t->layer[j].slopes.d_max_px = 0.0f;
            t->layer[j].cos_psi = 1.0f;
            t->layer[j].sin_psi = 0.0f;
        }
        t->layer[j].filter = lr_filter_make(&t->layer[j].slopes, &cfg->filter);
    }
}
