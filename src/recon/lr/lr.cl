/* LR (layered reconstruction, seeds/004) kernels: the partitions' statistics (lr_tile_stats;
 * the host turns them into filters, lr_partition.c: lr_tile_finish), Algorithm 1
 * (reprojection, eq. 16), Algorithm 2 (separable screen filter along / across the layer's
 * motion) and eq. 17 (front-to-back compositing). The plain C version of the same steps is
 * lr_reconstruct.c, which the tests compare against (bit for bit on PoCL).
 *
 * Buffers (host layout in lr_cl.c):
 *   samples       12 floats per sample (LrSample), pixel-major, spp per pixel
 *   tile_bounds   LR_TB_STRIDE floats per tile: n_depth, n_coc, depth bounds, CoC bounds
 *   tile_layers   LR_TL_STRIDE ints per tile: layer_count, then raw layer -> compact layer
 *   params        LR_LP_STRIDE floats per (tile, layer): cos psi, sin psi, 1/sigma_x, eta, xi,
 *                 1/sigma_u, 1/sigma_t, 1/sigma_y, rho, 1/sigma_v, radius_x, radius_y, then the
 *                 screen filter's tap weights exp(-(k / sigma)^2 / 2), k = 0..32, along (x)
 *                 and across (y): computed once per partition on the host, not per tap
 *   layer_ids     window_px^2 * spp bytes per tile: the raw layer of every window sample
 *                 (lr_tile_stats), with the flag LR_SKIP for a non-finite radiance
 *   grid, pass1   window_px^2 cells of 5 floats (opacity, weight, rgb) per (tile, layer)
 *
 * Launch shapes (lr_cl.c): all 2D in fixed 16x4 groups (cl_launch_2d), so that PoCL compiles
 * each kernel once whatever the image size or layer count; every kernel ignores the padding. */

#define LR_SAMPLE_STRIDE 12
#define LR_TB_STRIDE 25
#define LR_TL_STRIDE 18
#define LR_LP_STRIDE 78
#define LR_TAPS_X 12
#define LR_TAPS_Y 45
#define LR_SKIP 0x80 /* flag on a layer id: non-finite radiance, not reprojected */
#define LR_CH 5
#define LR_MOVING_PX 1.0f /* lr_partition.h: moving and static samples of a slab are separate layers */

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

#define LR_ST_STRIDE 8 /* per raw layer: count, cos psi, sin psi, c_min, c_max, d_min, d_max, across */

/* Same rule as lr_tile_raw_layer, on the tile's own bounds array: slab k's moving samples are
 * raw layer 2k, its static ones 2k + 1, when 2 slabs + 1 ids fit in 17. */
static int lr_raw_layer(const float *tb, float depth, float coc, float mx, float my)
{
    int n_depth = (int)tb[0], n_coc = (int)tb[1];
    int slabs = n_depth + n_coc + 1;
    bool split = 2 * slabs + 1 <= 17;
    if (!(depth < INFINITY)) return split ? 2 * slabs : slabs;
    int k = 0;
    for (int i = 0; i < n_depth; ++i) k += depth > tb[2 + i];
    for (int i = 0; i < n_coc; ++i) k += coc > tb[17 + i];
    if (!split) return k;
    bool moving = mx * mx + my * my >= LR_MOVING_PX * LR_MOVING_PX;
    return 2 * k + (moving ? 0 : 1);
}

/* The partition statistics of one tile (lr_partition.c: tile_stats, the same sums in the same
 * order): depth range -> layer bounds (written to tile_bounds), then per raw layer the count,
 * motion sum, CoC range, and in the mean motion's frame the motion ranges. The host finishes
 * the partitions (lr_tile_finish) from these few numbers instead of sweeping the samples. The
 * raw layer of every window sample is kept for the reprojection (layer_ids).
 * uniform: the uniform depth layers (1..7); coc_bounds: n_coc bounds, the same for every tile. */
__kernel void lr_tile_stats(int width, int height, int spp, int tile_px, int window_px, int ntx, int ntiles,
                            int uniform, int n_coc, __global const float *coc_bounds, __global const float *samples,
                            __global float *tile_bounds, __global float *stats, __global uchar *layer_ids)
{
#pragma OPENCL FP_CONTRACT OFF
    int tile = get_global_id(0);
    if (tile >= ntiles || get_global_id(1) != 0) return;
    LrWindow w = lr_window(tile % ntx, tile / ntx, width, height, tile_px, window_px);
    float zmin = INFINITY, zmax = -INFINITY;
    for (int py = w.y0; py < w.y1; ++py)
        for (int px = w.x0; px < w.x1; ++px)
            for (int k = 0; k < spp; ++k) {
                float z = samples[((size_t)(py * width + px) * spp + k) * LR_SAMPLE_STRIDE + 5];
                if (z < INFINITY) {
                    zmin = z < zmin ? z : zmin;
                    zmax = z > zmax ? z : zmax;
                }
            }
    float tb[LR_TB_STRIDE];
    for (int i = 0; i < LR_TB_STRIDE; ++i) tb[i] = 0.0f;
    int n_depth = 0;
    if (zmin < zmax)
        for (int i = 1; i < uniform; ++i) tb[2 + n_depth++] = zmin + (zmax - zmin) * (float)i / (float)uniform;
    tb[0] = (float)n_depth;
    tb[1] = (float)n_coc;
    for (int i = 0; i < n_coc; ++i) tb[17 + i] = coc_bounds[i];
    for (int i = 0; i < LR_TB_STRIDE; ++i) tile_bounds[tile * LR_TB_STRIDE + i] = tb[i];

    int raw_n = 2 * (n_depth + n_coc + 1) + 1 <= 17 ? 2 * (n_depth + n_coc + 1) + 1 : n_depth + n_coc + 2;
    int count[17];
    lr_sum mx[17], my[17];
    float cmin[17], cmax[17], cp[17], sp[17], dmin[17], dmax[17], perp[17];
    for (int i = 0; i < raw_n; ++i) {
        count[i] = 0;
        mx[i] = my[i] = 0;
        cmin[i] = dmin[i] = INFINITY;
        cmax[i] = dmax[i] = -INFINITY;
        perp[i] = 0.0f;
    }
    __global uchar *ids = layer_ids + (size_t)tile * window_px * window_px * spp;
    for (int py = w.y0, i = 0; py < w.y1; ++py)
        for (int px = w.x0; px < w.x1; ++px)
            for (int k = 0; k < spp; ++k, ++i) {
                __global const float *s = samples + ((size_t)(py * width + px) * spp + k) * LR_SAMPLE_STRIDE;
                int r = lr_raw_layer(tb, s[5], s[6], s[7], s[8]);
                bool finite = isfinite(s[9]) && isfinite(s[10]) && isfinite(s[11]);
                ids[i] = (uchar)(finite ? r : r | LR_SKIP); /* the reprojection skips non-finite radiance */
                count[r]++;
                mx[r] += (lr_sum)s[7];
                my[r] += (lr_sum)s[8];
                cmin[r] = s[6] < cmin[r] ? s[6] : cmin[r];
                cmax[r] = s[6] > cmax[r] ? s[6] : cmax[r];
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
    for (int py = w.y0, i = 0; py < w.y1; ++py)
        for (int px = w.x0; px < w.x1; ++px)
            for (int k = 0; k < spp; ++k, ++i) {
                __global const float *s = samples + ((size_t)(py * width + px) * spp + k) * LR_SAMPLE_STRIDE;
                int r = ids[i] & ~LR_SKIP;
                float along = cp[r] * s[7] + sp[r] * s[8];
                float across = fabs(-sp[r] * s[7] + cp[r] * s[8]);
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
    }
}

/* Algorithm 1 for one (tile, layer): serial over the window's samples (no float atomics in
 * OpenCL 1.2; the partitions are many, so the device is kept busy by them). One work-item
 * per (layer, tile). */
__kernel void lr_reproject(int width, int height, int spp, int tile_px, int window_px, int ntx, int ntiles,
                           int max_layers, __global const float *samples, __global const uchar *layer_ids,
                           __global const int *tile_layers, __global const float *params, __global float *grid)
{
#pragma OPENCL FP_CONTRACT OFF
    int j = get_global_id(0), tile = get_global_id(1);
    if (tile >= ntiles || j >= max_layers) return;
    __global const int *tl = tile_layers + tile * LR_TL_STRIDE;
    if (j >= tl[0]) return;
    int id = tile * max_layers + j;
    __global const float *lp = params + id * LR_LP_STRIDE;
    __global float *g = grid + (size_t)id * window_px * window_px * LR_CH;
    __global const uchar *ids = layer_ids + (size_t)tile * window_px * window_px * spp;
    __global const int *compact = tl + 1;
    LrWindow w = lr_window(tile % ntx, tile / ntx, width, height, tile_px, window_px);
    int ww = w.x1 - w.x0, wh = w.y1 - w.y0;
    float cp = lp[0], sp = lp[1], eta = lp[3], xi = lp[4], isu = lp[5], ist = lp[6], rho = lp[8], isv = lp[9];
    /* Only the grid cells the screen passes read matter: lr_along's box around the tile,
     * widened by the along radius. A sample moves at most |eta| + |xi|/2 + |rho| px (|u_r|,
     * |v_r| <= 1 on the unit lens, |t_c| <= 1/2), so source pixels farther than that from
     * the box cannot land in it and are not visited: for a sharp layer that is the tile and a
     * few pixels instead of the whole window. The cells read get exactly the C version's sums. */
    float rx = lp[10], ry = lp[11];
    int tx0 = (tile % ntx) * tile_px - w.x0, ty0 = (tile / ntx) * tile_px - w.y0;
    int mx = (int)ceil(ry * fabs(sp)) + 1 + (int)ceil(rx * fabs(cp)) + 1;
    int my = (int)ceil(ry * fabs(cp)) + 1 + (int)ceil(rx * fabs(sp)) + 1;
    int reach = (int)ceil(1.01f * (fabs(eta) + 0.5f * fabs(xi) + fabs(rho))) + 2;
    int cx0 = max(0, tx0 - mx - reach), cx1 = min(ww, tx0 + tile_px + mx + reach);
    int cy0 = max(0, ty0 - my - reach), cy1 = min(wh, ty0 + tile_px + my + reach);
    int bx0 = max(0, tx0 - mx), bx1 = min(ww, tx0 + tile_px + mx), by0 = max(0, ty0 - my), by1 = min(wh, ty0 + tile_px + my);
    for (int iy = by0; iy < by1; ++iy)
        for (int ix = bx0; ix < bx1; ++ix)
            for (int c = 0; c < LR_CH; ++c) g[(iy * ww + ix) * LR_CH + c] = 0.0f;
    for (int cell = 0; cell < (cy1 - cy0) * (cx1 - cx0); ++cell) {
        int sx = cx0 + cell % (cx1 - cx0), sy = cy0 + cell / (cx1 - cx0);
        int px = w.x0 + sx, py = w.y0 + sy, first = (sy * ww + sx) * spp;
        for (int k = 0; k < spp; ++k) {
            int raw = ids[first + k];
            if (raw & LR_SKIP) continue; /* non-finite radiance (counted on the host) */
            int layer = compact[raw];
            if (layer < j) continue;
            __global const float *s = samples + ((size_t)(py * width + px) * spp + k) * LR_SAMPLE_STRIDE;
            float ur = cp * s[2] + sp * s[3], vr = -sp * s[2] + cp * s[3];
            float tc = s[4] - 0.5f;
            float along = eta * ur + xi * tc, across = rho * vr;
            float p = s[0] + cp * along - sp * across; /* eq. 16 */
            float q = s[1] + sp * along + cp * across;
            int ix = (int)floor(p) - w.x0, iy = (int)floor(q) - w.y0;
            if (ix < bx0 || iy < by0 || ix >= bx1 || iy >= by1) continue; /* never read */
            float au = isu * ur, av = isv * vr, at = ist * tc;
            float wt = lr_gauss(au * au + av * av + at * at); /* w_u w_v w_t of eq. 14 */
            if (wt == 0.0f) continue;
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
}

/* One 1D Gaussian pass of Algorithm 2 at window cell (ix, iy): the cells at k (dx, dy),
 * k in [-r, r], nearest pixel, weighted by taps[|k|] = exp(-(k / sigma)^2 / 2), summed into acc. */
static void lr_pass_sum(__global const float *g, int ww, int wh, int ix, int iy, float dx, float dy, int r,
                        __global const float *taps, float *acc)
{
#pragma OPENCL FP_CONTRACT OFF
    for (int c = 0; c < LR_CH; ++c) acc[c] = 0.0f;
    for (int k = -r; k <= r; ++k) {
        int jx = ix + (int)floor((float)k * dx + 0.5f), jy = iy + (int)floor((float)k * dy + 0.5f);
        if (jx < 0 || jy < 0 || jx >= ww || jy >= wh) continue;
        float wk = taps[k < 0 ? -k : k];
        for (int c = 0; c < LR_CH; ++c) acc[c] += wk * g[(jy * ww + jx) * LR_CH + c];
    }
}

/* Algorithm 2, first pass: along the layer's motion, at the window cells the second pass
 * reads (the tile widened by the across radius projected on x and y), not the whole window. */
__kernel void lr_along(int width, int height, int tile_px, int window_px, int ntx, int ntiles, int max_layers,
                       __global const int *tile_layers, __global const float *params, __global const float *grid,
                       __global float *pass1)
{
#pragma OPENCL FP_CONTRACT OFF
    int cell = get_global_id(0), id = get_global_id(1);
    int tile = id / max_layers, j = id % max_layers;
    if (tile >= ntiles || cell >= window_px * window_px || j >= tile_layers[tile * LR_TL_STRIDE]) return;
    int tx = tile % ntx, ty = tile / ntx;
    LrWindow w = lr_window(tx, ty, width, height, tile_px, window_px);
    int ww = w.x1 - w.x0, wh = w.y1 - w.y0;
    if (cell >= ww * wh) return;
    int ix = cell % ww, iy = cell / ww;
    __global const float *lp = params + id * LR_LP_STRIDE;
    /* the second pass reads tile pixel + round(k (-sin psi, cos psi)), |k| <= radius_y */
    float ry = lp[11];
    int mx = (int)ceil(ry * fabs(lp[1])) + 1, my = (int)ceil(ry * fabs(lp[0])) + 1;
    int tx0 = tx * tile_px - w.x0, ty0 = ty * tile_px - w.y0;
    if (ix < tx0 - mx || ix >= tx0 + tile_px + mx || iy < ty0 - my || iy >= ty0 + tile_px + my) return;
    __global const float *g = grid + (size_t)id * window_px * window_px * LR_CH;
    float acc[LR_CH];
    lr_pass_sum(g, ww, wh, ix, iy, lp[0], lp[1], (int)lp[10], lp + LR_TAPS_X, acc); /* along (cos psi, sin psi) */
    __global float *o = pass1 + (size_t)id * window_px * window_px * LR_CH + (iy * ww + ix) * LR_CH;
    for (int c = 0; c < LR_CH; ++c) o[c] = acc[c];
}

/* Algorithm 2, second pass (across the motion), normalisation and eq. 17, one pixel. */
__kernel void lr_across_composite(int width, int height, int tile_px, int window_px, int ntx, int ntiles, int max_layers,
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
        lr_pass_sum(p1, ww, wh, ix, iy, -lp[1], lp[0], (int)lp[11], lp + LR_TAPS_Y, acc); /* across: (-sin, cos) */
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
