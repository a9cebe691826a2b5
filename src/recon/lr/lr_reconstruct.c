/* LR Algorithms 1 and 2 and eq. 17 in plain C (see lr_reconstruct.h). */
#include "recon/lr/lr_reconstruct.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "recon/lr/lr_band_class.h"
#include "recon/lr/lr_bucket.h"

void lr_reproject(const LrPlace *s, float cp, float sp, const LrFilter *f, float *p_px, float *q_px, float *weight)
{
    /* rotated lens coordinates (the lens rotates with the screen: defocus is isotropic) */
    float ur = cp * s->u + sp * s->v, vr = -sp * s->u + cp * s->v;
    float tc = s->t - 0.5f; /* the filter is centred on mid-shutter */
    float along = f->eta_px * ur + f->xi_px * tc, across = f->rho_px * vr;
    *p_px = s->x_px + cp * along - sp * across; /* eq. 16: R^T (shift in the rotated frame) */
    *q_px = s->y_px + sp * along + cp * across;
    float au = f->inv_sigma_u * ur, av = f->inv_sigma_v * vr, at = f->inv_sigma_t * tc;
    *weight = lr_gauss(au * au + av * av + at * at); /* w_u w_v w_t of eq. 14 */
}

enum { CH_A = 0, CH_W = 1, CH_R = 2, CH_COUNT = 5 }; /* opacity, weight, irradiance rgb */

/* Channel c of grid cell (x, y), 0 outside the window. */
static float cell_or_zero(const float *grid, int ww, int wh, int x, int y, int c)
{
    return x >= 0 && x < ww && y >= 0 && y < wh ? grid[((size_t)y * ww + x) * CH_COUNT + c] : 0.0f;
}

/* The round screen filter at window cell (ix, iy): the grid's cells within r, weighted by
 * table[dx^2 + dy^2]. The four taps (+-dx, +-dy) share a weight: per dy >= 0 the cells of
 * rows iy - dy and iy + dy are added first (row iy once), then per dx >= 0 those of columns
 * ix + dx and ix - dx (column ix once), and the weight multiplies the sum; dy, then dx
 * ascending. lr.cl's lr_round_row adds the same floats in the same order. */
static void lr_round_sum(const float *grid, int ww, int wh, int ix, int iy, int r, const float *table, float *acc)
{
    for (int dy = 0; dy <= r; ++dy) {
        int w = r;
        while (w * w + dy * dy > r * r) --w;
        if ((iy - dy < 0 || iy - dy >= wh) && (dy == 0 || iy + dy < 0 || iy + dy >= wh)) continue;
        for (int dx = 0; dx <= w; ++dx) {
            float wk = table[dx * dx + dy * dy];
            for (int c = 0; c < CH_COUNT; ++c) {
                /* the rows' sum at a column (row iy once): 0 for a row outside the window, as
                 * lr_round_row's rs */
                float right = cell_or_zero(grid, ww, wh, ix + dx, iy - dy, c) +
                              (dy > 0 ? cell_or_zero(grid, ww, wh, ix + dx, iy + dy, c) : 0.0f);
                float left = cell_or_zero(grid, ww, wh, ix - dx, iy - dy, c) +
                             (dy > 0 ? cell_or_zero(grid, ww, wh, ix - dx, iy + dy, c) : 0.0f);
                acc[c] += wk * (dx == 0 ? right : right + left);
            }
        }
    }
}

static void filter_tile(const LrSamples *img, const LrConfig *cfg, int tx, int ty, float *grid, float *pass1,
                        unsigned char *ids, int *order, size_t *sample_at, LrOutput *out)
{
    LrTile tile;
    lr_tile_partition(img, cfg, tx, ty, &tile);
    int x0, y0, x1, y1;
    lr_tile_window(img, cfg, tx, ty, &x0, &y0, &x1, &y1);
    int ww = x1 - x0, wh = y1 - y0;
    int tx0, ty0, tx1, ty1;
    lr_tile_pixels(img, cfg, tx, ty, &tx0, &ty0, &tx1, &ty1);
    int tw = tx1 - tx0;
    int npix = tw * (ty1 - ty0);
    float *trans = malloc(sizeof(float) * (size_t)npix); /* transmittance so far (eq. 17) */
    for (int i = 0; i < npix; ++i) trans[i] = 1.0f;
    for (int i = 0; i < npix; ++i) {
        int px = tx0 + i % tw, py = ty0 + i / tw;
        float *o = &out->rgb[((size_t)py * img->width + px) * 3];
        o[0] = o[1] = o[2] = 0.0f;
        if (out->layers) out->layers[(size_t)py * img->width + px] = (float)tile.layer_count;
        if (out->extent_px) out->extent_px[(size_t)py * img->width + px] = 0.0f;
    }
    if (tile.layer_count == 0) { /* nothing to reproject (a still tile: lr_partition.h) */
        free(trans);
        return;
    }
    /* Every window sample's raw layer once, then the window sorted by layer (lr_bucket.h):
     * layer j's own samples and those behind it are the raw layers from j's on. */
    int spp = img->spp, nwin = ww * wh * spp, raw_n = lr_tile_raw_count(&tile);
    for (int py = y0, i = 0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int k = 0; k < spp; ++k, ++i) {
                sample_at[i] = ((size_t)py * img->width + px) * spp + k;
                const LrKey *s = &img->key[sample_at[i]];
                bool finite = !isnan(img->bright[sample_at[i]]); /* lr_bright; counted once, by the caller */
                ids[i] = (unsigned char)(lr_tile_raw_layer(&tile, s->depth, s->coc_px, s->motion_px) | (finite ? 0 : LR_LAYER_SKIP));
            }
    int start[LR_MAX_LAYERS + 2];
    lr_bucket_by_layer(ids, nwin, raw_n, start, order);
    unsigned classes = lr_band_tile_classes(img, cfg, tx, ty); /* the band classes among the tile's pixels */
    for (int j = 0; j < tile.layer_count; ++j) {
        const LrFilter *f = &tile.layer[j].filter;
        float cp = tile.layer[j].cos_psi, sp = tile.layer[j].sin_psi;
        int raw_j = 0, raw_e = lr_tile_layer_end(&tile, raw_n, j); /* own: raw layers [raw_j, raw_e) */
        while (tile.compact[raw_j] != j) ++raw_j;
        memset(grid, 0, sizeof(float) * CH_COUNT * (size_t)ww * wh);
        /* Algorithm 1: samples of this layer add opacity and radiance, samples behind it add
         * weight only (they saw through layer j); layer by layer, pixel-major within one. */
        for (int r = raw_j; r < raw_n; ++r)
            for (int e = start[r]; e < start[r + 1]; ++e) {
                const LrPlace *s = &img->place[sample_at[order[e]]];
                float p, q, w;
                lr_reproject(s, cp, sp, f, &p, &q, &w);
                if (r < raw_e) /* the tilt's centroid shift (8.35), the layer's own samples only */
                    p += tile.layer[j].ramp_x_px, q += tile.layer[j].ramp_y_px;
                int ix = (int)floorf(p) - x0, iy = (int)floorf(q) - y0;
                if (ix < 0 || iy < 0 || ix >= ww || iy >= wh || w == 0.0f) continue;
                float *g = &grid[((size_t)iy * ww + ix) * CH_COUNT];
                g[CH_W] += w;
                if (r < raw_e) {
                    g[CH_A] += w;
                    for (int c = 0; c < 3; ++c) g[CH_R + c] += w * s->L[c];
                }
            }
        /* Algorithm 2, pass 1: along the motion, over the whole window (nearest pixel); a
         * layer with the round filter (lr_screen_round) has no passes, one 2D sum below.
         * A still layer takes at each pixel its band class's screen filter (8.40): the along
         * pass once per class whose filter differs from the frame band's (lr_band_screen). */
        LrScreen screen[LR_BAND_CLASSES];
        LrFilter class_filter[LR_BAND_CLASSES];
        bool has[LR_BAND_CLASSES] = {true, false, false};
        lr_screen_make(f, cfg, cp, sp, &screen[0]);
        class_filter[0] = *f;
        for (int c = 1; c < LR_BAND_CLASSES; ++c)
            has[c] = (classes >> c & 1u) && lr_band_screen(cfg, &tile.layer[j], c, &screen[0], &screen[c], &class_filter[c]);
        for (int c = 0; c < LR_BAND_CLASSES; ++c) {
            if (!has[c] || screen[c].round) continue;
            float *p1 = pass1 + (size_t)c * CH_COUNT * ww * wh;
            for (int iy = 0; iy < wh; ++iy)
                for (int ix = 0; ix < ww; ++ix) {
                    float acc[CH_COUNT] = {0};
                    for (int k = -screen[c].rx; k <= screen[c].rx; ++k) {
                        int jx = ix + (int)floorf((float)k * cp + 0.5f), jy = iy + (int)floorf((float)k * sp + 0.5f);
                        if (jx < 0 || jy < 0 || jx >= ww || jy >= wh) continue;
                        float w = screen[c].taps_x[k < 0 ? -k : k];
                        const float *g = &grid[((size_t)jy * ww + jx) * CH_COUNT];
                        for (int ch = 0; ch < CH_COUNT; ++ch) acc[ch] += w * g[ch];
                    }
                    memcpy(&p1[((size_t)iy * ww + ix) * CH_COUNT], acc, sizeof acc);
                }
        }
        /* pass 2: across the motion, tile pixels only, each with its class's filter; then
         * normalise and composite. */
        for (int i = 0; i < npix; ++i) {
            int px = tx0 + i % tw, py = ty0 + i / tw, ix = px - x0, iy = py - y0;
            int c = cfg->band_class ? cfg->band_class[(size_t)py * img->width + px] : LR_BAND_FRAME;
            if (c >= LR_BAND_CLASSES || !has[c]) c = LR_BAND_FRAME;
            const LrScreen *sc = &screen[c];
            const float *p1 = pass1 + (size_t)c * CH_COUNT * ww * wh;
            float acc[CH_COUNT] = {0};
            if (sc->round)
                lr_round_sum(grid, ww, wh, ix, iy, sc->ry, sc->table, acc);
            else
                for (int k = -sc->ry; k <= sc->ry; ++k) {
                    int jx = ix + (int)floorf(-(float)k * sp + 0.5f), jy = iy + (int)floorf((float)k * cp + 0.5f);
                    if (jx < 0 || jy < 0 || jx >= ww || jy >= wh) continue;
                    float w = sc->taps_y[k < 0 ? -k : k];
                    const float *g = &p1[((size_t)jy * ww + jx) * CH_COUNT];
                    for (int ch = 0; ch < CH_COUNT; ++ch) acc[ch] += w * g[ch];
                }
            if (!(acc[CH_W] > 0.0f)) continue; /* nothing of this layer or behind reached here */
            float alpha = acc[CH_A] / acc[CH_W];
            float *o = &out->rgb[((size_t)py * img->width + px) * 3];
            for (int c = 0; c < 3; ++c) o[c] += trans[i] * acc[CH_R + c] / acc[CH_W]; /* eq. 17 */
            if (out->extent_px && alpha > 0.0f && out->extent_px[(size_t)py * img->width + px] == 0.0f)
                out->extent_px[(size_t)py * img->width + px] = 1.0f / class_filter[c].inv_sigma_x_px; /* the filter applied here */
            trans[i] *= 1.0f - alpha;
        }
    }
    free(trans);
}

void lr_reconstruct_c(const LrSamples *img, const LrConfig *cfg, LrOutput *out)
{
    size_t cells = (size_t)cfg->window_px * cfg->window_px * CH_COUNT;
    /* pass1: one window per band class (8.40) */
    float *grid = malloc(sizeof(float) * cells), *pass1 = malloc(sizeof(float) * cells * LR_BAND_CLASSES);
    size_t nwin = (size_t)cfg->window_px * cfg->window_px * img->spp;
    unsigned char *ids = malloc(nwin);
    int *order = malloc(sizeof(int) * nwin);
    size_t *sample_at = malloc(sizeof(size_t) * nwin); /* window sample -> index in img's arrays */
    out->nonfinite = 0;
    for (size_t i = 0; i < (size_t)img->width * img->height * img->spp; ++i)
        if (isnan(img->bright[i])) out->nonfinite++; /* lr_bright */
    int ntx, nty;
    lr_tile_count(img, cfg, &ntx, &nty);
    for (int ty = 0; ty < nty; ++ty)
        for (int tx = 0; tx < ntx; ++tx) filter_tile(img, cfg, tx, ty, grid, pass1, ids, order, sample_at, out);
    free(grid);
    free(pass1);
    free(ids);
    free(order);
    free(sample_at);
}
