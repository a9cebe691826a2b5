/* Host side of lr.cl (see lr_cl.h). Buffers are reallocated per run: the partition count
 * depends on the image and its depth layers. */
#include "recon/lr/lr_cl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/cl/cl_runtime_internal.h"

enum { TB_STRIDE = 25, TL_STRIDE = 18, LP_STRIDE = 12, CH = 5 }; /* as in lr.cl */

_Static_assert(sizeof(LrSample) == 12 * sizeof(float), "lr.cl reads LrSample as 12 floats");
_Static_assert(LR_MAX_DEPTH_BOUNDS == 15 && LR_MAX_COC_BOUNDS == 8 && LR_MAX_LAYERS + 1 == 17,
               "lr.cl's tile layouts");

struct LrCl {
    ClRuntime *rt;
    cl_kernel reproject, along, across;
};

static bool cl_ok(cl_int err, const char *what, Diag *d)
{
    if (err == CL_SUCCESS) return true;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL %s (LR): %s", what, cl_error_name(err));
    return false;
}

LrCl *lr_cl_create(ClRuntime *rt, Diag *d)
{
    LrCl *lr = calloc(1, sizeof *lr);
    if (!lr) return NULL;
    lr->rt = rt;
    if (!(lr->reproject = cl_runtime_kernel(rt, "lr_reproject", d)) || !(lr->along = cl_runtime_kernel(rt, "lr_along", d)) ||
        !(lr->across = cl_runtime_kernel(rt, "lr_across_composite", d))) {
        lr_cl_destroy(lr);
        return NULL;
    }
    return lr;
}

void lr_cl_destroy(LrCl *lr)
{
    if (!lr) return;
    if (lr->reproject) clReleaseKernel(lr->reproject);
    if (lr->along) clReleaseKernel(lr->along);
    if (lr->across) clReleaseKernel(lr->across);
    free(lr);
}

static double event_seconds(cl_event ev)
{
    cl_ulong t0 = 0, t1 = 0;
    if (clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_START, sizeof t0, &t0, NULL) != CL_SUCCESS ||
        clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_END, sizeof t1, &t1, NULL) != CL_SUCCESS)
        return 0.0;
    return (double)(t1 - t0) * 1e-9;
}

/* Host partitions, flattened into the kernel layouts. */
static int flatten_tiles(const LrSamples *img, const LrConfig *cfg, int ntiles, int ntx, float *tb, int *tl,
                         LrTile *tiles)
{
    int max_layers = 1;
    for (int t = 0; t < ntiles; ++t) {
        LrTile *T = &tiles[t];
        lr_tile_partition(img, cfg, t % ntx, t / ntx, T);
        float *b = tb + (size_t)t * TB_STRIDE;
        memset(b, 0, sizeof(float) * TB_STRIDE);
        b[0] = (float)T->n_depth;
        b[1] = (float)T->n_coc;
        for (int i = 0; i < T->n_depth; ++i) b[2 + i] = T->depth_bound[i];
        for (int i = 0; i < T->n_coc; ++i) b[17 + i] = T->coc_bound_px[i];
        int *l = tl + (size_t)t * TL_STRIDE;
        l[0] = T->layer_count;
        for (int i = 0; i < LR_MAX_LAYERS + 1; ++i) l[1 + i] = T->compact[i];
        if (T->layer_count > max_layers) max_layers = T->layer_count;
    }
    return max_layers;
}

bool lr_cl_run(LrCl *lr, const LrSamples *img, const LrConfig *cfg, LrOutput *out, double *kernel_seconds, Diag *d)
{
    cl_context ctx = lr->rt->context;
    cl_command_queue q = lr->rt->queue;
    int ntx = (img->width + cfg->tile_px - 1) / cfg->tile_px, nty = (img->height + cfg->tile_px - 1) / cfg->tile_px;
    int ntiles = ntx * nty;
    size_t npix = (size_t)img->width * img->height, nsamples = npix * (size_t)img->spp;
    float *tb = malloc(sizeof(float) * TB_STRIDE * (size_t)ntiles);
    int *tl = malloc(sizeof(int) * TL_STRIDE * (size_t)ntiles);
    LrTile *tiles = malloc(sizeof(LrTile) * (size_t)ntiles);
    float *aov_l = out->layers ? NULL : malloc(sizeof(float) * npix), *aov_e = out->extent_px ? NULL : malloc(sizeof(float) * npix);
    bool ok = tb && tl && tiles && (out->layers || aov_l) && (out->extent_px || aov_e);
    if (!ok) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory (LR partitions)");
        free(tb), free(tl), free(tiles), free(aov_l), free(aov_e);
        return false;
    }
    int L = flatten_tiles(img, cfg, ntiles, ntx, tb, tl, tiles);
    size_t nparts = (size_t)ntiles * L;
    float *lp = calloc(nparts * LP_STRIDE, sizeof(float));
    out->nonfinite = 0;
    for (size_t i = 0; i < nsamples; ++i)
        if (!(isfinite(img->s[i].L[0]) && isfinite(img->s[i].L[1]) && isfinite(img->s[i].L[2]))) out->nonfinite++;
    for (int t = 0; lp && t < ntiles; ++t)
        for (int j = 0; j < tiles[t].layer_count; ++j) {
            const LrFilter *f = &tiles[t].layer[j].filter;
            float *p = lp + ((size_t)t * L + j) * LP_STRIDE;
            float v[LP_STRIDE] = {tiles[t].layer[j].cos_psi, tiles[t].layer[j].sin_psi, f->inv_sigma_x_px, f->eta_px, f->xi_px,
                                  f->inv_sigma_u, f->inv_sigma_t, f->inv_sigma_y_px, f->rho_px, f->inv_sigma_v,
                                  (float)lr_filter_radius_px(f->inv_sigma_x_px, cfg), (float)lr_filter_radius_px(f->inv_sigma_y_px, cfg)};
            memcpy(p, v, sizeof v);
        }
    free(tiles);
    cl_int err = lp ? CL_SUCCESS : CL_OUT_OF_HOST_MEMORY;
    size_t grid_bytes = nparts * (size_t)cfg->window_px * cfg->window_px * CH * sizeof(float);
    cl_mem b_s = NULL, b_tb = NULL, b_tl = NULL, b_lp = NULL, b_g = NULL, b_p1 = NULL, b_rgb = NULL, b_l = NULL, b_e = NULL;
    if (err == CL_SUCCESS) b_s = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(LrSample) * nsamples, (void *)img->s, &err);
    if (err == CL_SUCCESS) b_tb = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(float) * TB_STRIDE * (size_t)ntiles, tb, &err);
    if (err == CL_SUCCESS) b_tl = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(int) * TL_STRIDE * (size_t)ntiles, tl, &err);
    if (err == CL_SUCCESS) b_lp = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(float) * LP_STRIDE * nparts, lp, &err);
    if (err == CL_SUCCESS) b_g = clCreateBuffer(ctx, CL_MEM_READ_WRITE, grid_bytes, NULL, &err);
    if (err == CL_SUCCESS) b_p1 = clCreateBuffer(ctx, CL_MEM_READ_WRITE, grid_bytes, NULL, &err);
    if (err == CL_SUCCESS) b_rgb = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, sizeof(float) * 3 * npix, NULL, &err);
    if (err == CL_SUCCESS) b_l = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, sizeof(float) * npix, NULL, &err);
    if (err == CL_SUCCESS) b_e = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, sizeof(float) * npix, NULL, &err);
    ok = cl_ok(err, "buffer allocation", d);
    cl_event ev[3] = {NULL, NULL, NULL};
    cl_int W = img->width, H = img->height, S = img->spp, T = cfg->tile_px, N = cfg->window_px, NX = ntx, LL = L;
    if (ok) {
        cl_kernel k = lr->reproject;
        cl_int ints[7] = {W, H, S, T, N, NX, LL};
        err = 0;
        for (cl_uint i = 0; i < 7; ++i) err |= clSetKernelArg(k, i, sizeof(cl_int), &ints[i]);
        cl_mem m[5] = {b_s, b_tb, b_tl, b_lp, b_g};
        for (cl_uint i = 0; i < 5; ++i) err |= clSetKernelArg(k, 7 + i, sizeof(cl_mem), &m[i]);
        size_t g1 = nparts;
        ok = cl_ok(err, "arguments", d) && cl_ok(clEnqueueNDRangeKernel(q, k, 1, NULL, &g1, NULL, 0, NULL, &ev[0]), "reprojection", d);
    }
    cl_int ints6[6] = {W, H, T, N, NX, LL};
    if (ok) {
        cl_kernel k = lr->along;
        err = 0;
        for (cl_uint i = 0; i < 6; ++i) err |= clSetKernelArg(k, i, sizeof(cl_int), &ints6[i]);
        cl_mem m[4] = {b_tl, b_lp, b_g, b_p1};
        for (cl_uint i = 0; i < 4; ++i) err |= clSetKernelArg(k, 6 + i, sizeof(cl_mem), &m[i]);
        size_t g2[2] = {(size_t)N * N, nparts};
        ok = cl_ok(err, "arguments", d) && cl_ok(clEnqueueNDRangeKernel(q, k, 2, NULL, g2, NULL, 0, NULL, &ev[1]), "filter along", d);
    }
    if (ok) {
        cl_kernel k = lr->across;
        err = 0;
        for (cl_uint i = 0; i < 6; ++i) err |= clSetKernelArg(k, i, sizeof(cl_int), &ints6[i]);
        cl_mem m[6] = {b_tl, b_lp, b_p1, b_rgb, b_l, b_e};
        for (cl_uint i = 0; i < 6; ++i) err |= clSetKernelArg(k, 6 + i, sizeof(cl_mem), &m[i]);
        size_t g2[2] = {(size_t)W, (size_t)H};
        ok = cl_ok(err, "arguments", d) && cl_ok(clEnqueueNDRangeKernel(q, k, 2, NULL, g2, NULL, 0, NULL, &ev[2]), "filter across", d);
    }
    if (ok)
        ok = cl_ok(clEnqueueReadBuffer(q, b_rgb, CL_TRUE, 0, sizeof(float) * 3 * npix, out->rgb, 0, NULL, NULL), "download", d) &&
             cl_ok(clEnqueueReadBuffer(q, b_l, CL_TRUE, 0, sizeof(float) * npix, out->layers ? out->layers : aov_l, 0, NULL, NULL), "download", d) &&
             cl_ok(clEnqueueReadBuffer(q, b_e, CL_TRUE, 0, sizeof(float) * npix, out->extent_px ? out->extent_px : aov_e, 0, NULL, NULL), "download", d);
    clFinish(q);
    if (ok && kernel_seconds) *kernel_seconds = event_seconds(ev[0]) + event_seconds(ev[1]) + event_seconds(ev[2]);
    for (int i = 0; i < 3; ++i)
        if (ev[i]) clReleaseEvent(ev[i]);
    cl_mem all[9] = {b_s, b_tb, b_tl, b_lp, b_g, b_p1, b_rgb, b_l, b_e};
    for (int i = 0; i < 9; ++i)
        if (all[i]) clReleaseMemObject(all[i]);
    free(tb), free(tl), free(lp), free(aov_l), free(aov_e);
    return ok;
}
