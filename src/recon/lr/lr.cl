/* LR (layered reconstruction, seeds/004) kernels: Algorithm 1 (reprojection, eq. 16),
 * Algorithm 2 (separable screen filter along / across the layer's motion) and eq. 17
 * (front-to-back compositing). The partitions come from the host (lr_partition.c); the plain
 * C version of the same steps is lr_reconstruct.c, which the tests compare against.
 *
 * Buffers (host layout in lr_cl.c):
 *   samples       12 floats per sample (LrSample), pixel-major, spp per pixel
 *   tile_bounds   LR_TB_STRIDE floats per tile: n_depth, n_coc, depth bounds, CoC bounds
 *   tile_layers   LR_TL_STRIDE ints per tile: layer_count, then raw layer -> compact layer
 *   params        LR_LP_STRIDE floats per (tile, layer): cos psi, sin psi, 1/sigma_x, eta, xi,
 *                 1/sigma_u, 1/sigma_t, 1/sigma_y, rho, 1/sigma_v, radius_x, radius_y
 *   grid, pass1   window_px^2 cells of 5 floats (opacity, weight, rgb) per (tile, layer) */

#define LR_SAMPLE_STRIDE 12
#define LR_TB_STRIDE 25
#define LR_TL_STRIDE 18
#define LR_LP_STRIDE 12
#define LR_CH 5

typedef struct {
    int x0, y0, x1, y1;
} LrWindow;

static LrWindow lr_window(int tx, int ty, int width, int height, int tile_px, int window_px)
{
    int margin = (window_px - tile_px) / 2;
    int ax = tx * tile_px - margin, ay = ty * tile_px - margin;
    LrWindow w;
    w.x0 = ax < 0 ? 0 : ax;
    w.y0 = ay < 0 ? 0 : ay;
    w.x1 = ax + window_px > width ? width : ax + window_px;
    w.y1 = ay + window_px > height ? height : ay + window_px;
    return w;
}

/* Same rule as lr_tile_layer_of: count the bounds below the sample, misses last. */
static int lr_layer_of(__global const float *tb, __global const int *tl, float depth, float coc)
{
    int n_depth = (int)tb[0], n_coc = (int)tb[1];
    int k = 0;
    if (!(depth < INFINITY)) {
        k = n_depth + n_coc + 1;
    } else {
        for (int i = 0; i < n_depth; ++i) k += depth > tb[2 + i];
        for (int i = 0; i < n_coc; ++i) k += coc > tb[17 + i];
    }
    return tl[1 + k];
}

/* Algorithm 1 for one (tile, layer): serial over the window's samples (no float atomics). */
__kernel void lr_reproject(int width, int height, int spp, int tile_px, int window_px, int ntx, int max_layers,
                           __global const float *samples, __global const float *tile_bounds,
                           __global const int *tile_layers, __global const float *params, __global float *grid)
{
#pragma OPENCL FP_CONTRACT OFF
    int id = get_global_id(0);
    int tile = id / max_layers, j = id % max_layers;
    __global const int *tl = tile_layers + tile * LR_TL_STRIDE;
    if (j >= tl[0]) return;
    __global const float *tb = tile_bounds + tile * LR_TB_STRIDE;
    __global const float *lp = params + id * LR_LP_STRIDE;
    __global float *g = grid + (size_t)id * window_px * window_px * LR_CH;
    LrWindow w = lr_window(tile % ntx, tile / ntx, width, height, tile_px, window_px);
    int ww = w.x1 - w.x0, wh = w.y1 - w.y0;
    for (int i = 0; i < ww * wh * LR_CH; ++i) g[i] = 0.0f;
    float cp = lp[0], sp = lp[1], eta = lp[3], xi = lp[4], isu = lp[5], ist = lp[6], rho = lp[8], isv = lp[9];
    for (int py = w.y0; py < w.y1; ++py)
        for (int px = w.x0; px < w.x1; ++px)
            for (int k = 0; k < spp; ++k) {
                __global const float *s = samples + ((size_t)(py * width + px) * spp + k) * LR_SAMPLE_STRIDE;
                int layer = lr_layer_of(tb, tl, s[5], s[6]);
                if (layer < j) continue;
                if (!(isfinite(s[9]) && isfinite(s[10]) && isfinite(s[11]))) continue;
                float ur = cp * s[2] + sp * s[3], vr = -sp * s[2] + cp * s[3];
                float tc = s[4] - 0.5f;
                float along = eta * ur + xi * tc, across = rho * vr;
                float p = s[0] + cp * along - sp * across; /* eq. 16 */
                float q = s[1] + sp * along + cp * across;
                float au = isu * ur, av = isv * vr, at = ist * tc;
                float wt = exp(-0.5f * (au * au + av * av + at * at));
                int ix = (int)floor(p) - w.x0, iy = (int)floor(q) - w.y0;
                if (ix < 0 || iy < 0 || ix >= ww || iy >= wh) continue;
                __global float *c = g + (iy * ww + ix) * LR_CH;
                c[1] += wt;
                if (layer == j) {
                    c[0] += wt;
                    c[2] += wt * s[9];
                    c[3] += wt * s[10];
                    c[4] += wt * s[11];
                }
            }
}

/* One 1D Gaussian pass of Algorithm 2 at window cell (ix, iy): the cells at k (dx, dy),
 * k in [-r, r], nearest pixel, weighted by exp(-(k inv_sigma)^2 / 2), summed into acc. */
static void lr_pass_sum(__global const float *g, int ww, int wh, int ix, int iy, float dx, float dy, int r,
                        float inv_sigma, float *acc)
{
#pragma OPENCL FP_CONTRACT OFF
    for (int c = 0; c < LR_CH; ++c) acc[c] = 0.0f;
    for (int k = -r; k <= r; ++k) {
        int jx = ix + (int)floor((float)k * dx + 0.5f), jy = iy + (int)floor((float)k * dy + 0.5f);
        if (jx < 0 || jy < 0 || jx >= ww || jy >= wh) continue;
        float a = (float)k * inv_sigma, wk = exp(-0.5f * a * a);
        for (int c = 0; c < LR_CH; ++c) acc[c] += wk * g[(jy * ww + jx) * LR_CH + c];
    }
}

/* Algorithm 2, first pass: along the layer's motion, every window cell. */
__kernel void lr_along(int width, int height, int tile_px, int window_px, int ntx, int max_layers,
                       __global const int *tile_layers, __global const float *params, __global const float *grid,
                       __global float *pass1)
{
#pragma OPENCL FP_CONTRACT OFF
    int cell = get_global_id(0), id = get_global_id(1);
    int tile = id / max_layers, j = id % max_layers;
    if (j >= tile_layers[tile * LR_TL_STRIDE]) return;
    LrWindow w = lr_window(tile % ntx, tile / ntx, width, height, tile_px, window_px);
    int ww = w.x1 - w.x0, wh = w.y1 - w.y0;
    if (cell >= ww * wh) return;
    int ix = cell % ww, iy = cell / ww;
    __global const float *lp = params + id * LR_LP_STRIDE;
    __global const float *g = grid + (size_t)id * window_px * window_px * LR_CH;
    float acc[LR_CH];
    lr_pass_sum(g, ww, wh, ix, iy, lp[0], lp[1], (int)lp[10], lp[2], acc); /* along (cos psi, sin psi) */
    __global float *o = pass1 + (size_t)id * window_px * window_px * LR_CH + (iy * ww + ix) * LR_CH;
    for (int c = 0; c < LR_CH; ++c) o[c] = acc[c];
}

/* Algorithm 2, second pass (across the motion), normalisation and eq. 17, one pixel. */
__kernel void lr_across_composite(int width, int height, int tile_px, int window_px, int ntx, int max_layers,
                                  __global const int *tile_layers, __global const float *params,
                                  __global const float *pass1, __global float *rgb, __global float *layers_aov,
                                  __global float *extent_aov)
{
#pragma OPENCL FP_CONTRACT OFF
    int px = get_global_id(0), py = get_global_id(1);
    if (px >= width || py >= height) return;
    int tx = px / tile_px, ty = py / tile_px, tile = ty * ntx + tx;
    int count = tile_layers[tile * LR_TL_STRIDE];
    LrWindow w = lr_window(tx, ty, width, height, tile_px, window_px);
    int ww = w.x1 - w.x0, wh = w.y1 - w.y0, ix = px - w.x0, iy = py - w.y0;
    float trans = 1.0f, out[3] = {0.0f, 0.0f, 0.0f}, extent = 0.0f;
    for (int j = 0; j < count; ++j) {
        int id = tile * max_layers + j;
        __global const float *lp = params + id * LR_LP_STRIDE;
        __global const float *p1 = pass1 + (size_t)id * window_px * window_px * LR_CH;
        float acc[LR_CH];
        lr_pass_sum(p1, ww, wh, ix, iy, -lp[1], lp[0], (int)lp[11], lp[7], acc); /* across: (-sin, cos) */
        if (!(acc[1] > 0.0f)) continue;
        float alpha = acc[0] / acc[1];
        for (int c = 0; c < 3; ++c) out[c] += trans * acc[2 + c] / acc[1];
        if (alpha > 0.0f && extent == 0.0f) extent = 1.0f / lp[2];
        trans *= 1.0f - alpha;
    }
    size_t i = (size_t)py * width + px;
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = out[c];
    layers_aov[i] = (float)count;
    extent_aov[i] = extent;
}
