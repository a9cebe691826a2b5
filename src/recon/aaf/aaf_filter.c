/* Host side of the AAF screen-space filter (see aaf_filter.h). */
#include "recon/aaf/aaf_filter.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/cl/cl_runtime_internal.h"

/* Below this width (pixels) the nearest neighbour's weight exp(-1/(2 beta^2)) is < 4e-4:
 * filtering would change nothing visible, so the pixel is skipped. */
#define MIN_BETA_PX 0.25f

/* ---- device buffers: padded float planes (layout in aaf/aaf.cl) ---- */

enum {
    PL_PX, PL_PY, PL_PZ, PL_DEPTH, PL_NX, PL_NY, PL_NZ, PL_ID, /* guides, set once per frame */
    PL_INV, PL_RADIUS,                                          /* per filter run */
    PL_IN_R, PL_IN_G, PL_IN_B, PL_IN_W,
    PL_TMP_R, PL_TMP_G, PL_TMP_B, PL_TMP_W,
    PL_OUT_R, PL_OUT_G, PL_OUT_B, PL_OUT_W,
    PL_LX, PL_LY, PL_LZ, PL_LW,                                 /* per-pixel filter plane */
    PL_COUNT
};

struct AafFilter {
    ClRuntime *rt;
    cl_kernel pass, unpack4, unpack_params, pack4;
    int width, height;      /* image */
    int pitch, rows, pad;   /* padded planes */
    bool have_guides;
    cl_mem planes[PL_COUNT];
    cl_mem raw4, raw2;      /* the host's interleaved layouts: float4 and float2 per pixel */
};

AafFilterRules aaf_filter_rules_default(int mode)
{
    AafFilterRules r;
    r.mode = mode;
    r.cos_normal_min = 0.96592583f; /* cos 15 deg: the papers use 10-20 degrees */
    r.depth_tol_rel = 0.05f;
    r.sharp_beta_ratio = 0.0f;
    return r;
}

void aaf_filter_make_params(int n, const float *beta, const float *pixel_world, float radius_sigmas,
                            int radius_cap_px, float *param_xy)
{
    for (int i = 0; i < n; ++i) {
        float b = beta[i];
        float d = pixel_world ? pixel_world[i] : 1.0f;
        float beta_px = (b > 0.0f && d > 0.0f) ? b / d : 0.0f; /* NaN compares false: 0 */
        float r = 0.0f, inv = 0.0f;
        if (beta_px >= MIN_BETA_PX && isfinite(beta_px)) {
            r = ceilf(radius_sigmas * beta_px);
            if (r > (float)radius_cap_px) r = (float)radius_cap_px;
            if (r < 1.0f) r = 1.0f;
            inv = 1.0f / (2.0f * b * b);
            if (!isfinite(inv)) inv = 0.0f; /* beta huge: a box over the capped radius */
        } else if (beta_px > 0.0f && !isfinite(beta_px)) {
            r = (float)radius_cap_px; /* infinite width: box over the capped radius */
            inv = 0.0f;
        }
        if (radius_cap_px <= 0) r = 0.0f;
        param_xy[2 * i] = inv;
        param_xy[2 * i + 1] = r;
    }
}

static void release_buffers(AafFilter *f)
{
    for (int p = 0; p < PL_COUNT; ++p)
        if (f->planes[p]) clReleaseMemObject(f->planes[p]);
    memset(f->planes, 0, sizeof f->planes);
    if (f->raw4) clReleaseMemObject(f->raw4);
    if (f->raw2) clReleaseMemObject(f->raw2);
    f->raw4 = f->raw2 = NULL;
    f->width = f->height = 0;
}

AafFilter *aaf_filter_create(ClRuntime *rt, Diag *d)
{
    AafFilter *f = calloc(1, sizeof *f);
    if (!f) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return NULL;
    }
    f->rt = rt;
    if (!(f->pass = cl_runtime_kernel(rt, "aaf_filter_pass", d)) || !(f->unpack4 = cl_runtime_kernel(rt, "aaf_unpack4", d)) ||
        !(f->unpack_params = cl_runtime_kernel(rt, "aaf_unpack_params", d)) || !(f->pack4 = cl_runtime_kernel(rt, "aaf_pack4", d))) {
        aaf_filter_destroy(f);
        return NULL;
    }
    return f;
}

void aaf_filter_destroy(AafFilter *f)
{
    if (!f) return;
    release_buffers(f);
    cl_kernel ks[4] = {f->pass, f->unpack4, f->unpack_params, f->pack4};
    for (int i = 0; i < 4; ++i)
        if (ks[i]) clReleaseKernel(ks[i]);
    free(f);
}

static bool cl_check(cl_int err, const char *what, Diag *d)
{
    if (err == CL_SUCCESS) return true;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL %s: %s", what, cl_error_name(err));
    return false;
}

static bool alloc_buffers(AafFilter *f, int width, int height, Diag *d)
{
    release_buffers(f);
    f->pad = AAF_FILTER_RADIUS_CAP_PX;
    f->pitch = ((width + 2 * f->pad + 8) + 7) / 8 * 8; /* 8-lane groups may overrun by 7 */
    f->rows = height + 2 * f->pad;
    size_t bytes = (size_t)f->pitch * (size_t)f->rows * sizeof(float);
    size_t n = (size_t)width * (size_t)height;
    cl_int err = CL_SUCCESS;
    const float zero = 0.0f;
    for (int p = 0; p < PL_COUNT && err == CL_SUCCESS; ++p) {
        f->planes[p] = clCreateBuffer(f->rt->context, CL_MEM_READ_WRITE, bytes, NULL, &err);
        /* the padding must read as "unusable, radius 0": zero everything once */
        if (err == CL_SUCCESS)
            err = clEnqueueFillBuffer(f->rt->queue, f->planes[p], &zero, sizeof zero, 0, bytes, 0, NULL, NULL);
    }
    if (err == CL_SUCCESS) f->raw4 = clCreateBuffer(f->rt->context, CL_MEM_READ_WRITE, n * 16, NULL, &err);
    if (err == CL_SUCCESS) f->raw2 = clCreateBuffer(f->rt->context, CL_MEM_READ_WRITE, n * 8, NULL, &err);
    if (!cl_check(err, "buffer allocation", d)) {
        release_buffers(f);
        return false;
    }
    f->width = width;
    f->height = height;
    return true;
}

static bool launch_2d(AafFilter *f, cl_kernel k, size_t gx, size_t gy, cl_event *ev, Diag *d)
{
    return cl_launch_2d(f->rt, k, gx, gy, ev, d);
}

/* Sets the (width, height, pitch, pad) arguments every kernel starts with. */
static cl_int set_dims(AafFilter *f, cl_kernel k)
{
    cl_int dims[4] = {f->width, f->height, f->pitch, f->pad}, err = 0;
    for (cl_uint i = 0; i < 4; ++i) err |= clSetKernelArg(k, i, sizeof(cl_int), &dims[i]);
    return err;
}

/* Uploads n float4 pixels (zeros when src is NULL) and scatters them into planes first..first+3. */
static bool upload4(AafFilter *f, const float *src, int first, Diag *d)
{
    size_t bytes = (size_t)f->width * (size_t)f->height * 16;
    cl_int err;
    if (src) {
        err = clEnqueueWriteBuffer(f->rt->queue, f->raw4, CL_FALSE, 0, bytes, src, 0, NULL, NULL);
    } else {
        const float zero = 0.0f;
        err = clEnqueueFillBuffer(f->rt->queue, f->raw4, &zero, sizeof zero, 0, bytes, 0, NULL, NULL);
    }
    err |= set_dims(f, f->unpack4);
    err |= clSetKernelArg(f->unpack4, 4, sizeof(cl_mem), &f->raw4);
    for (int c = 0; c < 4; ++c) err |= clSetKernelArg(f->unpack4, (cl_uint)(5 + c), sizeof(cl_mem), &f->planes[first + c]);
    return cl_check(err, "upload", d) && launch_2d(f, f->unpack4, (size_t)f->width, (size_t)f->height, NULL, d);
}

bool aaf_filter_reserve(AafFilter *f, int width, int height, Diag *d)
{
    if (width <= 0 || height <= 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "AAF filter: empty image %dx%d", width, height);
        return false;
    }
    if ((width != f->width || height != f->height) && !alloc_buffers(f, width, height, d)) return false;
    return cl_check(clFinish(f->rt->queue), "finish", d);
}

bool aaf_filter_set_guides(AafFilter *f, int width, int height, const float *pos4, const float *nrm4, Diag *d)
{
    if (width <= 0 || height <= 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "AAF filter: empty image %dx%d", width, height);
        return false;
    }
    if ((width != f->width || height != f->height) && !alloc_buffers(f, width, height, d)) return false;
    /* Pixel-mode filtering reads no guides: NULL uploads zeros. The host arrays must stay
     * valid until the copies are done: finish before returning. */
    bool ok = upload4(f, pos4, PL_PX, d) && upload4(f, nrm4, PL_NX, d);
    ok = cl_check(clFinish(f->rt->queue), "finish", d) && ok;
    f->have_guides = ok && pos4 && nrm4;
    return ok;
}

static bool run_pass(AafFilter *f, int axis, const AafFilterRules *rules, bool plane_given, int in0, int out0,
                     cl_event *ev, Diag *d)
{
    cl_kernel k = f->pass;
    cl_int err = set_dims(f, k);
    cl_int ints[2] = {axis, rules->mode};
    cl_int plane_mode = plane_given ? 1 : 0;
    cl_uint a = 4;
    for (int i = 0; i < 2; ++i) err |= clSetKernelArg(k, a++, sizeof(cl_int), &ints[i]);
    err |= clSetKernelArg(k, a++, sizeof(float), &rules->cos_normal_min);
    err |= clSetKernelArg(k, a++, sizeof(float), &rules->depth_tol_rel);
    float r = rules->sharp_beta_ratio;
    float sharp_inv_factor = (r > 0.0f && rules->mode == AAF_DIST_WORLD) ? 1.0f / (r * r) : 0.0f;
    err |= clSetKernelArg(k, a++, sizeof(float), &sharp_inv_factor);
    err |= clSetKernelArg(k, a++, sizeof(cl_int), &plane_mode);
    for (int c = 0; c < 4; ++c) err |= clSetKernelArg(k, a++, sizeof(cl_mem), &f->planes[in0 + c]);
    for (int p = PL_PX; p <= PL_RADIUS; ++p) err |= clSetKernelArg(k, a++, sizeof(cl_mem), &f->planes[p]);
    for (int p = PL_LX; p <= PL_LZ; ++p) err |= clSetKernelArg(k, a++, sizeof(cl_mem), &f->planes[p]);
    for (int c = 0; c < 4; ++c) err |= clSetKernelArg(k, a++, sizeof(cl_mem), &f->planes[out0 + c]);
    if (!cl_check(err, "aaf_filter_pass arguments", d)) return false;
    return launch_2d(f, k, (size_t)(f->width + 7) / 8, (size_t)f->height, ev, d);
}

bool aaf_filter_run(AafFilter *f, const float *value4, const float *plane_normal4, const float *param_xy,
                    const AafFilterRules *rules, float *out4, double *kernel_seconds, Diag *d)
{
    if (kernel_seconds) *kernel_seconds = 0.0;
    if (f->width <= 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "AAF filter: guides not set");
        return false;
    }
    size_t n = (size_t)f->width * (size_t)f->height;
    /* In the plane of each pixel's own normal unless told otherwise; without guides (pixel
     * mode) the plane is irrelevant. */
    bool ok = upload4(f, value4, PL_IN_R, d);
    if (plane_normal4) ok = ok && upload4(f, plane_normal4, PL_LX, d);
    cl_int err = clEnqueueWriteBuffer(f->rt->queue, f->raw2, CL_FALSE, 0, n * 8, param_xy, 0, NULL, NULL);
    err |= set_dims(f, f->unpack_params);
    err |= clSetKernelArg(f->unpack_params, 4, sizeof(cl_mem), &f->raw2);
    err |= clSetKernelArg(f->unpack_params, 5, sizeof(cl_mem), &f->planes[PL_INV]);
    err |= clSetKernelArg(f->unpack_params, 6, sizeof(cl_mem), &f->planes[PL_RADIUS]);
    ok = ok && cl_check(err, "upload", d) && launch_2d(f, f->unpack_params, (size_t)f->width, (size_t)f->height, NULL, d);
    cl_event ev[2] = {NULL, NULL};
    ok = ok && run_pass(f, 0, rules, plane_normal4 != NULL, PL_IN_R, PL_TMP_R, &ev[0], d) &&
         run_pass(f, 1, rules, plane_normal4 != NULL, PL_TMP_R, PL_OUT_R, &ev[1], d);
    if (ok) {
        err = set_dims(f, f->pack4);
        for (int c = 0; c < 4; ++c) err |= clSetKernelArg(f->pack4, (cl_uint)(4 + c), sizeof(cl_mem), &f->planes[PL_OUT_R + c]);
        err |= clSetKernelArg(f->pack4, 8, sizeof(cl_mem), &f->raw4);
        ok = cl_check(err, "download", d) && launch_2d(f, f->pack4, (size_t)f->width, (size_t)f->height, NULL, d) &&
             cl_check(clEnqueueReadBuffer(f->rt->queue, f->raw4, CL_TRUE, 0, n * 16, out4, 0, NULL, NULL), "download", d);
    }
    if (!ok) clFinish(f->rt->queue); /* the host arrays must outlive any copy still queued */
    if (kernel_seconds && ok) *kernel_seconds = cl_event_seconds(ev[0]) + cl_event_seconds(ev[1]);
    for (int i = 0; i < 2; ++i)
        if (ev[i]) clReleaseEvent(ev[i]);
    return ok;
}
