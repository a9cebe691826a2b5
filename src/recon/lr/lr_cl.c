/* Host side of lr.cl (see lr_cl.h). Host arrays and device buffers live as long as the LrCl
 * and only grow: a frame of the same size and layer count allocates nothing (the first version
 * allocated and page-faulted ~50 MB per frame). */
#include "recon/lr/lr_cl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/clock.h"
#include "recon/cl/cl_runtime_internal.h"
#include "recon/lr/lr_band_class.h"
#include "recon/lr/lr_bucket.h"

/* as in lr.cl */
enum { TB_STRIDE = 2 + LR_MAX_DEPTH_BOUNDS + LR_MAX_COC_BOUNDS, TB_COC = 2 + LR_MAX_DEPTH_BOUNDS, TL_STRIDE = 18, LP_HEAD = 14, LP_TAPS_X = LP_HEAD, LP_TAPS_Y = LP_HEAD + LR_MAX_RADIUS_PX + 1,
       LP_ROUND = LP_HEAD + 2 * (LR_MAX_RADIUS_PX + 1), LP_ROUND_T = LP_ROUND + 1, LP_BAND = LP_ROUND_T + LR_ROUND_TABLE,
       LP_STRIDE = LP_BAND + 2, CH = 5,
       ST_STRIDE = 9 + LR_TILT_SUMS, LS_STRIDE = 18, BATCH_TILES = 16,
       PACK_FIELDS = 5, BLOCK_PX = 8, BH_STRIDE = LR_GAP_BINS + 1, TILE_MAX = 32 };

_Static_assert(sizeof(LrKey) == 4 * sizeof(float) && sizeof(LrPlace) == 8 * sizeof(float), "lr.cl reads LrKey as a float4, LrPlace as 8 floats");
_Static_assert(LR_MAX_DEPTH_BOUNDS == 15 && LR_MAX_COC_BOUNDS == 15 && LR_MAX_LAYERS + 1 == 17 && TB_STRIDE == 32 && TB_COC == 17,
               "lr.cl's tile layouts (LR_TB_STRIDE, LR_TB_COC, LR_COC_SLABS)");
_Static_assert(BH_STRIDE == 49, "lr.cl's LR_BH_STRIDE");
_Static_assert(LP_STRIDE == 340 && LP_TAPS_X == 14 && LP_TAPS_Y == 47 && LP_ROUND == 80 && LP_BAND == 338,
               "lr.cl's LR_LP_STRIDE, LR_TAPS_X, LR_TAPS_Y, LR_ROUND and LR_BAND");
_Static_assert(LR_BAND_NARROW == 1 && LR_BAND_WIDE == 2 && LR_BAND_CLASSES == 3, "lr.cl's band classes");
_Static_assert(ST_STRIDE == 18, "lr.cl's LR_ST_STRIDE");
_Static_assert(LR_MAX_LAYERS + 1 < LR_LAYER_SKIP && LR_LAYER_SKIP == 0x80, "lr.cl's raw layer ids are bytes, 0x80 (LR_SKIP) flags a skipped sample");
_Static_assert(LS_STRIDE == LR_MAX_LAYERS + 2, "lr.cl's LR_LS_STRIDE: a start per raw layer and the end");

/* A device buffer that keeps its size between runs and grows when asked for more. */
typedef struct {
    cl_mem mem;
    size_t bytes;
} GrowBuf;

struct LrCl {
    ClRuntime *rt;
    cl_kernel blocks, stats, filter;
    /* host partitions, flattened into the kernel layouts; capacities in tiles / partitions */
    float *tb, *st, *lp;
    int *tl;
    LrTile *tiles;
    size_t tiles_cap, parts_cap;
    /* the band classes' screen records (8.40): LP_STRIDE floats each, capacity in records */
    float *lpc;
    size_t lpc_cap;
    GrowBuf b_cb, b_bh, b_bz, b_st, b_tb, b_tl, b_ids, b_order, b_ls, b_pack, b_g, b_p1, b_rgb, b_l, b_e, b_still,
        b_p1c, b_cls;
    LrClTimes last;
};

LrClTimes lr_cl_last_times(const LrCl *lr) { return lr->last; }

static bool cl_ok(cl_int err, const char *what, Diag *d)
{
    if (err == CL_SUCCESS) return true;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL %s (LR): %s", what, cl_error_name(err));
    return false;
}

static bool grow(ClRuntime *rt, GrowBuf *b, size_t bytes, cl_mem_flags flags, Diag *d)
{
    if (b->mem && b->bytes >= bytes) return true;
    if (b->mem) clReleaseMemObject(b->mem);
    b->mem = NULL;
    b->bytes = 0;
    cl_int err = CL_SUCCESS;
    b->mem = clCreateBuffer(rt->context, flags, bytes > 0 ? bytes : 1, NULL, &err);
    if (!cl_ok(err, "buffer allocation", d)) return false;
    b->bytes = bytes;
    return true;
}

LrCl *lr_cl_create(ClRuntime *rt, Diag *d)
{
    LrCl *lr = calloc(1, sizeof *lr);
    if (!lr) return NULL;
    lr->rt = rt;
    if (!(lr->blocks = cl_runtime_kernel(rt, "lr_block_stats", d)) || !(lr->stats = cl_runtime_kernel(rt, "lr_tile_stats", d)) ||
        !(lr->filter = cl_runtime_kernel(rt, "lr_tile_filter", d))) {
        lr_cl_destroy(lr);
        return NULL;
    }
    return lr;
}

void lr_cl_destroy(LrCl *lr)
{
    if (!lr) return;
    cl_kernel k[3] = {lr->blocks, lr->stats, lr->filter};
    for (int i = 0; i < 3; ++i)
        if (k[i]) clReleaseKernel(k[i]);
    GrowBuf *b[18] = {&lr->b_cb, &lr->b_bh, &lr->b_bz, &lr->b_st, &lr->b_tb, &lr->b_tl, &lr->b_ids, &lr->b_order, &lr->b_ls, &lr->b_pack,
                      &lr->b_g, &lr->b_p1, &lr->b_rgb, &lr->b_l, &lr->b_e, &lr->b_still, &lr->b_p1c, &lr->b_cls};
    for (int i = 0; i < 18; ++i)
        if (b[i]->mem) clReleaseMemObject(b[i]->mem);
    free(lr->tb), free(lr->st), free(lr->lp), free(lr->tl), free(lr->tiles), free(lr->lpc);
    free(lr);
}

/* The partitions from the device's statistics (lr_tile_stats), flattened into the kernel
 * layouts; returns the most layers of a tile. */
static int finish_tiles(LrCl *lr, const LrConfig *cfg, int ntiles)
{
    int max_layers = 1;
    for (int t = 0; t < ntiles; ++t) {
        LrTile *T = &lr->tiles[t];
        const float *b = lr->tb + (size_t)t * TB_STRIDE;
        memset(T, 0, sizeof *T);
        T->n_depth = (int)b[0];
        T->n_coc = (int)b[1];
        for (int i = 0; i < T->n_depth; ++i) T->depth_bound[i] = b[2 + i];
        for (int i = 0; i < T->n_coc; ++i) T->coc_bound_px[i] = b[TB_COC + i];
        LrLayerStats st[LR_MAX_LAYERS + 1];
        const float *o = lr->st + (size_t)t * (LR_MAX_LAYERS + 1) * ST_STRIDE;
        for (int i = 0; i < LR_MAX_LAYERS + 1; ++i, o += ST_STRIDE) {
            st[i] = (LrLayerStats){(int)o[0], o[1], o[2], o[3], o[4], o[5], o[6], o[7], o[8], {{0}}};
            memcpy(st[i].tilt.sum, o + 9, sizeof st[i].tilt.sum);
        }
        lr_tile_finish(cfg, st, T);
        int *l = lr->tl + (size_t)t * TL_STRIDE;
        l[0] = T->layer_count;
        for (int i = 0; i < LR_MAX_LAYERS + 1; ++i) l[1 + i] = T->compact[i];
        if (T->layer_count > max_layers) max_layers = T->layer_count;
    }
    return max_layers;
}

/* A screen filter into a parameter record: for a layer with the round filter its flag and
 * table (lr_screen_round), else the two tap tables (lr_screen_taps): the kernels read the taps
 * only in the two passes a round layer does not take (lr_reproject_layer's along pass,
 * lr_across_row's row pass), and on the bench scenes most layers are round. */
static void put_screen(float *p, const LrScreen *s)
{
    p[10] = (float)s->rx, p[11] = (float)s->ry;
    if (s->round) {
        p[LP_ROUND] = 1.0f;
        memcpy(p + LP_ROUND_T, s->table, sizeof(float) * (size_t)(s->rx * s->rx + 1));
        return;
    }
    memcpy(p + LP_TAPS_X, s->taps_x, sizeof(float) * (size_t)(s->rx + 1));
    memcpy(p + LP_TAPS_Y, s->taps_y, sizeof(float) * (size_t)(s->ry + 1));
}

/* Per (tile, layer): rotation, filter, its screen filter (put_screen), and per band class
 * whose screen filter differs from the frame band's (lr_band_screen: a still layer, the class
 * among the tile's pixels) the index of its record in lr->lpc, else -1 (LP_BAND, LP_BAND + 1).
 * Returns the class records written, or -1 when out of memory. */
static long flatten_params(LrCl *lr, const LrSamples *img, const LrConfig *cfg, int ntx, int ntiles, int L)
{
    long records = 0;
    for (int t = 0; t < ntiles; ++t) {
        unsigned classes = lr_band_tile_classes(img, cfg, t % ntx, t / ntx);
        for (int j = 0; j < lr->tiles[t].layer_count; ++j) {
            const LrFilter *f = &lr->tiles[t].layer[j].filter;
            float *p = lr->lp + ((size_t)t * L + j) * LP_STRIDE;
            const LrLayer *l = &lr->tiles[t].layer[j];
            LrScreen screen, band;
            LrFilter band_filter;
            lr_screen_make(f, cfg, l->cos_psi, l->sin_psi, &screen);
            float v[LP_HEAD] = {l->cos_psi, l->sin_psi, f->inv_sigma_x_px, f->eta_px, f->xi_px, f->inv_sigma_u, f->inv_sigma_t,
                                f->inv_sigma_y_px, f->rho_px, f->inv_sigma_v, 0.0f, 0.0f, l->ramp_x_px, l->ramp_y_px};
            memcpy(p, v, sizeof v);
            put_screen(p, &screen);
            for (int c = LR_BAND_NARROW; c < LR_BAND_CLASSES; ++c) {
                p[LP_BAND + c - 1] = -1.0f;
                if (!(classes >> c & 1u) || !lr_band_screen(cfg, l, c, &screen, &band, &band_filter)) continue;
                if ((size_t)records >= lr->lpc_cap) {
                    size_t cap = lr->lpc_cap ? 2 * lr->lpc_cap : 64;
                    float *grown = realloc(lr->lpc, sizeof(float) * LP_STRIDE * cap);
                    if (!grown) return -1;
                    lr->lpc = grown, lr->lpc_cap = cap;
                }
                float *q = lr->lpc + (size_t)records * LP_STRIDE;
                memset(q, 0, sizeof(float) * LP_STRIDE);
                q[2] = band_filter.inv_sigma_x_px; /* the extent AOV's */
                put_screen(q, &band);
                p[LP_BAND + c - 1] = (float)records++;
            }
        }
    }
    return records;
}

static bool set_args(cl_kernel k, const cl_int *ints, int nints, const cl_mem *mems, int nmems, Diag *d)
{
    cl_int err = CL_SUCCESS;
    for (int i = 0; i < nints; ++i) err |= clSetKernelArg(k, (cl_uint)i, sizeof(cl_int), &ints[i]);
    for (int i = 0; i < nmems; ++i) err |= clSetKernelArg(k, (cl_uint)(nints + i), sizeof(cl_mem), &mems[i]);
    return cl_ok(err, "arguments", d);
}

/* Downloads the pixels inside the band (lr_reconstruct.h: the band keeps what the caller has)
 * of an image of `floats` per pixel. */
static bool read_inner(cl_command_queue q, cl_mem buf, float *host, int floats, const LrSamples *img, int band, Diag *d)
{
    size_t px_bytes = sizeof(float) * (size_t)floats, pitch = px_bytes * (size_t)img->width;
    size_t origin[3] = {px_bytes * (size_t)band, (size_t)band, 0};
    size_t region[3] = {px_bytes * (size_t)(img->width - 2 * band), (size_t)(img->height - 2 * band), 1};
    return cl_ok(clEnqueueReadBufferRect(q, buf, CL_TRUE, origin, origin, region, pitch, 0, pitch, 0, host, 0, NULL, NULL), "download", d);
}

bool lr_cl_run(LrCl *lr, const LrSamples *img, const LrConfig *cfg, LrOutput *out, double *kernel_seconds, Diag *d)
{
    ClRuntime *rt = lr->rt;
    cl_command_queue q = rt->queue;
    if (cfg->tile_px > cfg->window_px) { /* lr.cl's rows of a tile fit a window's (LR_ROW_MAX) */
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "LR tile of %d px is larger than its window (%d px)", cfg->tile_px, cfg->window_px);
        return false;
    }
    if (cfg->tile_px > TILE_MAX) { /* lr_tile_filter keeps a tile's pixels in private arrays (LR_TILE_MAX) */
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "LR tile of %d px is larger than the kernels allow (%d)", cfg->tile_px, TILE_MAX);
        return false;
    }
    if (cfg->window_px / 2 > LR_MAX_RADIUS_PX || cfg->window_px > 255) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "LR window of %d px is larger than the kernels allow (64)", cfg->window_px);
        return false;
    }
    int ntx, nty;
    lr_tile_count(img, cfg, &ntx, &nty);
    int ntiles = ntx * nty;
    out->nonfinite = 0;
    if (ntiles <= 0) return true; /* nothing inside the band */
    size_t npix = (size_t)img->width * img->height, nsamples = npix * (size_t)img->spp;
    size_t wcells = (size_t)cfg->window_px * cfg->window_px;
    if ((size_t)ntiles > lr->tiles_cap) {
        free(lr->tb), free(lr->st), free(lr->tl), free(lr->tiles);
        lr->tb = malloc(sizeof(float) * TB_STRIDE * (size_t)ntiles);
        lr->st = malloc(sizeof(float) * ST_STRIDE * (LR_MAX_LAYERS + 1) * (size_t)ntiles);
        lr->tl = malloc(sizeof(int) * TL_STRIDE * (size_t)ntiles);
        lr->tiles = malloc(sizeof(LrTile) * (size_t)ntiles);
        lr->tiles_cap = lr->tb && lr->st && lr->tl && lr->tiles ? (size_t)ntiles : 0;
        if (!lr->tiles_cap) {
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory (LR partitions)");
            return false;
        }
    }
    /* the farthest a sample's film position lies from its pixel's centre, and the non-finite
     * radiances: measured by the caller while it wrote the samples, or here */
    float film_dev_px = cfg->samples_scanned ? cfg->film_dev_px : 0.0f;
    out->nonfinite = cfg->samples_scanned ? cfg->samples_nonfinite : 0;
    const LrPlace *si = img->place; /* pixel by pixel: no division per sample */
    for (int py = 0; !cfg->samples_scanned && py < img->height; ++py)
        for (int px = 0; px < img->width; ++px)
            for (int k = 0; k < img->spp; ++k, ++si) lr_scan_sample(si, px, py, &out->nonfinite, &film_dev_px);
    /* the reprojection's slack on the source rows beyond a sample's own half pixel: 2 covers
     * the box and pbrt's gaussian, mitchell and triangle filters; a sinc of radius 4 needs 4 */
    float slack = ceilf(film_dev_px - 0.5f);
    cl_int film_slack_px = slack > 2.0f ? (slack < (float)img->height ? (cl_int)slack : (cl_int)img->height) : 2;

    /* The samples' three arrays are read in place (on a CPU device PoCL uses the host
     * memory); the rest lives in the grow-only buffers. */
    double t0 = clock_wall_seconds();
    cl_int err = CL_SUCCESS, err_k = CL_SUCCESS, err_b = CL_SUCCESS;
    cl_mem b_s = clCreateBuffer(rt->context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, sizeof(LrPlace) * nsamples, (void *)img->place, &err);
    cl_mem b_k = clCreateBuffer(rt->context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, sizeof(LrKey) * nsamples, (void *)img->key, &err_k);
    cl_mem b_b = clCreateBuffer(rt->context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, sizeof(float) * nsamples, (void *)img->bright, &err_b);
    bool ok = cl_ok(err, "buffer allocation", d) && cl_ok(err_k, "buffer allocation", d) && cl_ok(err_b, "buffer allocation", d);
    size_t st_bytes = sizeof(float) * ST_STRIDE * (LR_MAX_LAYERS + 1) * (size_t)ntiles;
    ok = ok && grow(rt, &lr->b_cb, sizeof(float) * (LR_GAP_BINS - 1), CL_MEM_READ_ONLY, d) &&
         grow(rt, &lr->b_st, st_bytes, CL_MEM_READ_WRITE, d) &&
         grow(rt, &lr->b_tb, sizeof(float) * TB_STRIDE * (size_t)ntiles, CL_MEM_READ_WRITE, d) &&
         grow(rt, &lr->b_ids, (size_t)ntiles * wcells * (size_t)img->spp, CL_MEM_READ_WRITE, d) &&
         grow(rt, &lr->b_order, sizeof(cl_uint) * (size_t)ntiles * wcells * (size_t)img->spp, CL_MEM_READ_WRITE, d) &&
         grow(rt, &lr->b_ls, sizeof(cl_int) * LS_STRIDE * (size_t)ntiles, CL_MEM_READ_WRITE, d) &&
         grow(rt, &lr->b_still, (size_t)ntiles, CL_MEM_READ_ONLY, d);
    /* Partition statistics on the device (one work-item per tile), the rest on the host. */
    LrTile shape;
    lr_tile_bounds(cfg, 0.0f, 0.0f, &shape); /* the CoC bounds, the same for every tile */
    float edges[LR_GAP_BINS - 1];
    lr_gap_edges(edges); /* with cfg->gap_slabs: the histogram's bins instead */
    cl_int gap_slabs = lr_config_gap_slabs(cfg), still_slabs = lr_config_still_gap_slabs(cfg);
    cl_int uniform = lr_config_uniform_layers(cfg);
    cl_int W = img->width, H = img->height, S = img->spp, T = cfg->tile_px, N = cfg->window_px, NX = ntx, NT = ntiles;
    cl_int inset = cfg->inset_px;
    cl_event ev[4] = {NULL, NULL, NULL, NULL};
    /* Every window a union of whole 8x8 blocks (its corner, or the image's edge, on the block
     * grid): lr_block_stats bins each sample once and lr_tile_stats adds the blocks. */
    int margin = (cfg->window_px - cfg->tile_px) / 2;
    cl_int blocks = (cfg->inset_px - margin) % BLOCK_PX == 0 && cfg->tile_px % BLOCK_PX == 0 && cfg->window_px % BLOCK_PX == 0;
    cl_int NBX = (W + BLOCK_PX - 1) / BLOCK_PX, NBY = (H + BLOCK_PX - 1) / BLOCK_PX;
    ok = ok && grow(rt, &lr->b_bh, blocks ? sizeof(cl_int) * BH_STRIDE * (size_t)NBX * NBY : 1, CL_MEM_READ_WRITE, d) &&
         grow(rt, &lr->b_bz, blocks ? sizeof(float) * 2 * (size_t)NBX * NBY : 1, CL_MEM_READ_WRITE, d);
    if (ok) {
        cl_int ints[11] = {W, H, S, T, N, NX, NT, uniform, shape.n_coc, inset, gap_slabs};
        cl_mem m[8] = {lr->b_cb.mem, b_k, lr->b_tb.mem, lr->b_st.mem, lr->b_ids.mem, lr->b_order.mem, lr->b_ls.mem, lr->b_still.mem};
        cl_int count_moving = lr_config_counts_moving(cfg);
        cl_int bints[7] = {W, H, S, NBX, NBY, gap_slabs, count_moving};
        cl_mem bm[4] = {lr->b_cb.mem, b_k, lr->b_bh.mem, lr->b_bz.mem};
        ok = cl_ok(clEnqueueWriteBuffer(q, lr->b_cb.mem, CL_FALSE, 0, gap_slabs > 0 ? sizeof edges : sizeof(float) * LR_MAX_COC_BOUNDS, gap_slabs > 0 ? (const float *)edges : shape.coc_bound_px, 0, NULL, NULL), "upload", d) &&
             (!blocks || (set_args(lr->blocks, bints, 7, bm, 4, d) && cl_launch_2d(rt, lr->blocks, (size_t)NBX, (size_t)NBY, &ev[1], d))) &&
             cl_ok(clSetKernelArg(lr->stats, 19, sizeof(cl_int), &blocks) | clSetKernelArg(lr->stats, 20, sizeof(cl_int), &NBX) |
                       clSetKernelArg(lr->stats, 21, sizeof(cl_mem), &lr->b_bh.mem) | clSetKernelArg(lr->stats, 22, sizeof(cl_mem), &lr->b_bz.mem) |
                       clSetKernelArg(lr->stats, 23, sizeof(cl_mem), &b_b) | clSetKernelArg(lr->stats, 24, sizeof(cl_mem), &b_s) |
                       clSetKernelArg(lr->stats, 25, sizeof(cl_int), &still_slabs) |
                       clSetKernelArg(lr->stats, 26, sizeof(cl_int), &cfg->still_moving_permille),
                   "arguments", d) &&
             /* the still-tile mask, or zeros when the config has none */
             (cfg->still_tiles ? cl_ok(clEnqueueWriteBuffer(q, lr->b_still.mem, CL_FALSE, 0, (size_t)ntiles, cfg->still_tiles, 0, NULL, NULL), "upload", d)
                               : cl_ok(clEnqueueFillBuffer(q, lr->b_still.mem, &(cl_uchar){0}, 1, 0, (size_t)ntiles, 0, NULL, NULL), "fill", d)) &&
             set_args(lr->stats, ints, 11, m, 8, d) && cl_launch_serial_2d(rt, lr->stats, (size_t)ntiles, 1, &ev[0], d) &&
             cl_ok(clEnqueueReadBuffer(q, lr->b_st.mem, CL_TRUE, 0, st_bytes, lr->st, 0, NULL, NULL), "download", d) &&
             cl_ok(clEnqueueReadBuffer(q, lr->b_tb.mem, CL_TRUE, 0, sizeof(float) * TB_STRIDE * (size_t)ntiles, lr->tb, 0, NULL, NULL), "download", d);
    }
    int L = ok ? finish_tiles(lr, cfg, ntiles) : 1;
    size_t nparts = (size_t)ntiles * L;
    if (ok && nparts > lr->parts_cap) {
        free(lr->lp);
        lr->lp = malloc(sizeof(float) * LP_STRIDE * nparts);
        lr->parts_cap = lr->lp ? nparts : 0;
        if (!lr->lp) {
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory (LR partitions)");
            ok = false;
        }
    }
    long band_records = 0;
    if (ok) {
        memset(lr->lp, 0, sizeof(float) * LP_STRIDE * nparts);
        band_records = flatten_params(lr, img, cfg, ntx, ntiles, L);
        if (band_records < 0) {
            diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory (LR band classes)");
            ok = false;
        }
    }
    double t_part = clock_wall_seconds() - t0;
    /* The filter (lr_tile_filter) a batch of tile rows at a time: its copy of the samples and
     * its grids are per tile of the batch only, and a batch's are reused by the next.
     * The whole frame's were fresh memory in a one-frame render (docs/benchmarks.md, LR third
     * round; "LR's reconstruction cost"); 16 tiles (one row of tiles at 256 px) against 32 kept
     * more of the batch's copy in the shared cache ("LR's warm filter on the hard scene", lr25).
     * The grids are a tile's, not a (tile, layer)'s: its layers reuse them one after the other. */
    int batch_rows = ntx >= BATCH_TILES ? 1 : BATCH_TILES / ntx, batch_tiles = batch_rows * ntx;
    int nbatches = (nty + batch_rows - 1) / batch_rows;
    size_t grid_bytes = (size_t)(batch_tiles < ntiles ? batch_tiles : ntiles) * wcells * CH * sizeof(float);
    /* The parameter table is read in place as the samples are (4 MB at 256x192: uploaded, it
     * was a copy into fresh device memory a frame) */
    cl_int err_lp = CL_SUCCESS;
    cl_mem b_lp = ok ? clCreateBuffer(rt->context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, sizeof(float) * LP_STRIDE * nparts,
                                      lr->lp, &err_lp)
                     : NULL;
    ok = ok && cl_ok(err_lp, "buffer allocation", d);
    /* the band classes' records, read in place too (at least one record: a buffer of none is
     * not allowed), and the class map; the kernels read both only for a layer with records */
    if (ok && !lr->lpc) {
        lr->lpc = calloc(LP_STRIDE, sizeof(float));
        lr->lpc_cap = lr->lpc ? 1 : 0;
    }
    cl_int err_lpc = CL_SUCCESS;
    cl_mem b_lpc = ok && lr->lpc ? clCreateBuffer(rt->context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR,
                                                  sizeof(float) * LP_STRIDE * (band_records > 0 ? (size_t)band_records : 1), lr->lpc, &err_lpc)
                                 : NULL;
    if (ok && !lr->lpc) diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory (LR band classes)");
    ok = ok && b_lpc && cl_ok(err_lpc, "buffer allocation", d);
    ok = ok && grow(rt, &lr->b_cls, band_records > 0 ? npix : 1, CL_MEM_READ_ONLY, d) &&
         grow(rt, &lr->b_p1c, band_records > 0 ? 2 * grid_bytes : 1, CL_MEM_READ_WRITE, d);
    if (ok && band_records > 0)
        ok = cl_ok(clEnqueueWriteBuffer(q, lr->b_cls.mem, CL_FALSE, 0, npix, cfg->band_class, 0, NULL, NULL), "upload", d);
    ok = ok && grow(rt, &lr->b_tl, sizeof(int) * TL_STRIDE * (size_t)ntiles, CL_MEM_READ_ONLY, d) &&
         grow(rt, &lr->b_pack, sizeof(float) * PACK_FIELDS * (size_t)(batch_tiles < ntiles ? batch_tiles : ntiles) * wcells * (size_t)img->spp,
              CL_MEM_READ_WRITE, d) &&
         grow(rt, &lr->b_g, grid_bytes, CL_MEM_READ_WRITE, d) && grow(rt, &lr->b_p1, grid_bytes, CL_MEM_READ_WRITE, d) &&
         grow(rt, &lr->b_rgb, sizeof(float) * 3 * npix, CL_MEM_WRITE_ONLY, d) &&
         grow(rt, &lr->b_l, sizeof(float) * npix, CL_MEM_WRITE_ONLY, d) && grow(rt, &lr->b_e, sizeof(float) * npix, CL_MEM_WRITE_ONLY, d);
    if (ok)
        ok = cl_ok(clEnqueueWriteBuffer(q, lr->b_tl.mem, CL_FALSE, 0, sizeof(int) * TL_STRIDE * (size_t)ntiles, lr->tl, 0, NULL, NULL), "upload", d);

    cl_int LL = L;
    double batch_s = 0.0;
    for (int b = 0; ok && b < nbatches; ++b) {
        cl_int tile0 = b * batch_tiles;
        int tiles = ntiles - tile0 < batch_tiles ? ntiles - tile0 : batch_tiles;
        cl_int tile1 = tile0 + tiles;
        cl_event ev_filter = NULL;
        { /* Algorithms 1 and 2 and eq. 17, one work-item per tile */
            cl_int ints[11] = {W, H, S, T, N, NX, tile1, LL, tile0, film_slack_px, inset};
            cl_mem m[14] = {b_s, lr->b_pack.mem, lr->b_order.mem, lr->b_ls.mem, lr->b_tl.mem, b_lp, lr->b_g.mem, lr->b_p1.mem,
                            lr->b_rgb.mem, lr->b_l.mem, lr->b_e.mem, b_lpc, lr->b_cls.mem, lr->b_p1c.mem};
            ok = set_args(lr->filter, ints, 11, m, 14, d) && cl_launch_serial_2d(rt, lr->filter, (size_t)tiles, 1, &ev_filter, d);
        }
        /* the queue is in order, so the next batch starts after this one is done with the
         * buffers; waiting here only lets the batch's time be read */
        if (ok) ok = cl_ok(clWaitForEvents(1, &ev_filter), "kernel", d);
        batch_s += ok ? cl_event_seconds(ev_filter) : 0.0;
        if (ev_filter) clReleaseEvent(ev_filter);
    }
    float *aov_l = out->layers, *aov_e = out->extent_px;
    if (ok)
        ok = read_inner(q, lr->b_rgb.mem, out->rgb, 3, img, cfg->inset_px, d) && (!aov_l || read_inner(q, lr->b_l.mem, aov_l, 1, img, cfg->inset_px, d)) &&
             (!aov_e || read_inner(q, lr->b_e.mem, aov_e, 1, img, cfg->inset_px, d));
    clFinish(q);
    /* the statistics' time includes the blocks' (lr_block_stats) */
    double ks = lr->last.kernel_s[0] = ok ? cl_event_seconds(ev[0]) + (ev[1] ? cl_event_seconds(ev[1]) : 0.0) : 0.0;
    ks += lr->last.kernel_s[1] = ok ? batch_s : 0.0;
    lr->last.kernel_s[2] = lr->last.kernel_s[3] = 0.0;
    if (ok && kernel_seconds) *kernel_seconds = ks;
    lr->last.partitions = nparts;
    lr->last.max_layers = L;
    lr->last.partition_s = t_part;
    for (int i = 0; i < 4; ++i)
        if (ev[i]) clReleaseEvent(ev[i]);
    if (b_lp) clReleaseMemObject(b_lp);
    if (b_lpc) clReleaseMemObject(b_lpc);
    if (b_s) clReleaseMemObject(b_s);
    if (b_k) clReleaseMemObject(b_k);
    if (b_b) clReleaseMemObject(b_b);
    return ok;
}
