/* Host side and C reference of the MAAF image pass (see maaf_filter.h and maaf.cl). */
#include "recon/maaf/maaf_filter.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "recon/cl/cl_runtime_internal.h"

#define MIN_WEIGHT_FRACTION 0.2f /* MAAF_MIN_WEIGHT_FRACTION in maaf.cl */
#define SHARP_FACTOR 4.0f        /* MAAF_SHARP_FACTOR */

int maaf_component_count(int pairs)
{
    int bands = 2 * pairs - 1;
    return (bands * bands + 1) / 2;
}

static float dot3(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void maaf_basis(const float n_in[3], float t1[3], float t2[3])
{
    float n[3] = {n_in[0], n_in[1], n_in[2]};
    if (dot3(n, n) < 0.5f) n[0] = 0.0f, n[1] = 0.0f, n[2] = 1.0f;
    float a[3] = {0.0f, 0.0f, 0.0f};
    a[fabsf(n[0]) > 0.9f ? 1 : 0] = 1.0f;
    float c[3] = {a[1] * n[2] - a[2] * n[1], a[2] * n[0] - a[0] * n[2], a[0] * n[1] - a[1] * n[0]};
    float len = sqrtf(dot3(c, c));
    for (int k = 0; k < 3; ++k) t1[k] = c[k] / len;
    t2[0] = n[1] * t1[2] - n[2] * t1[1];
    t2[1] = n[2] * t1[0] - n[0] * t1[2];
    t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

/* One 1D pass of maaf.cl's maaf_pass for pixel (x, y); acc receives 8 floats per component. */
static void pass_pixel(const MaafFilterInput *in, const float *src, int axis, int x, int y, float *acc)
{
    int w = in->width, h = in->height, pairs = in->pairs, comps = maaf_component_count(pairs);
    int i = y * w + x;
    const float *pr = in->param + (size_t)i * MAAF_PARAM_STRIDE;
    int radius = (int)pr[0];
    memset(acc, 0, (size_t)comps * 8 * sizeof(float));
    const float *t1 = in->frame4 + 4 * i, *t2 = in->axis2_4 + 4 * i;
    const float *cp = in->pos4 + 4 * i, *cn = in->nrm4 + 4 * i;
    float tol = in->depth_tol_rel * cp[3];
    for (int k = -radius; k <= radius; ++k) {
        int nx = axis == 0 ? x + k : x, ny = axis == 0 ? y : y + k;
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        int j = ny * w + nx;
        if (in->frame4[4 * j + 3] == 0.0f) continue;
        const float *np = in->pos4 + 4 * j, *nn = in->nrm4 + 4 * j;
        float dlt[3] = {cp[0] - np[0], cp[1] - np[1], cp[2] - np[2]};
        if (nn[3] != cn[3] || dot3(cn, nn) < in->cos_normal_min || fabsf(dot3(cn, dlt)) > tol) continue;
        const float *pn = in->param + (size_t)j * MAAF_PARAM_STRIDE;
        if (pn[0] <= 0.0f || pn[3] > SHARP_FACTOR * pr[3]) continue; /* maaf.cl's sharpness rule */
        float d1 = dot3(dlt, t1), d2 = dot3(dlt, t2);
        float e1[MAAF_PAIRS_MAX][2], e2[MAAF_PAIRS_MAX][2];
        for (int p = 0; p < pairs; ++p) {
            float cx = pr[2 + 3 * p], hv = pr[3 + 3 * p];
            float g1 = expf(-hv * d1 * d1), g2 = expf(-hv * d2 * d2);
            e1[p][0] = g1 * cosf(cx * d1);
            e1[p][1] = g1 * sinf(cx * d1);
            e2[p][0] = g2 * cosf(cx * d2);
            e2[p][1] = g2 * sinf(cx * d2);
        }
        const float *yj = src + (size_t)j * comps * 8;
        int c = 0;
        for (int p = 0; p < pairs; ++p)
            for (int q = -(pairs - 1); q < pairs; ++q) {
                if (p == 0 && q < 0) continue;
                float br = q >= 0 ? e2[q][0] : e2[-q][0], bi = q >= 0 ? e2[q][1] : -e2[-q][1];
                float wr = e1[p][0] * br - e1[p][1] * bi, wi = e1[p][0] * bi + e1[p][1] * br;
                const float *yr = yj + 8 * c, *yi = yr + 4;
                float *ar = acc + 8 * c, *ai = ar + 4;
                for (int ch = 0; ch < 4; ++ch) {
                    ar[ch] += wr * yr[ch] - wi * yi[ch];
                    ai[ch] += wr * yi[ch] + wi * yr[ch];
                }
                ++c;
            }
    }
}

void maaf_filter_reference(const MaafFilterInput *in, float *out4)
{
    int w = in->width, h = in->height, pairs = in->pairs, comps = maaf_component_count(pairs);
    size_t n = (size_t)w * h, per = (size_t)comps * 8;
    float *tmp = malloc(n * per * sizeof(float));
    float *acc = malloc(per * sizeof(float));
    if (!tmp || !acc) {
        memset(out4, 0, 4 * n * sizeof(float)); /* nothing filtered */
        free(tmp);
        free(acc);
        return;
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            if (in->frame4[4 * i + 3] == 0.0f || (int)in->param[i * MAAF_PARAM_STRIDE] <= 0)
                memcpy(tmp + i * per, in->ysum + i * per, per * sizeof(float));
            else
                pass_pixel(in, in->ysum, 0, x, y, tmp + i * per);
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            const float *pr = in->param + i * MAAF_PARAM_STRIDE;
            float *o = out4 + 4 * i;
            memset(o, 0, 4 * sizeof(float));
            if (in->frame4[4 * i + 3] == 0.0f || (int)pr[0] <= 0) continue;
            pass_pixel(in, tmp, 1, x, y, acc);
            float sum[4] = {0, 0, 0, 0};
            int c = 0;
            for (int p = 0; p < pairs; ++p)
                for (int q = -(pairs - 1); q < pairs; ++q) {
                    if (p == 0 && q < 0) continue;
                    float m = (c == 0 ? 1.0f : 2.0f) * pr[1 + 3 * p] * pr[1 + 3 * (q < 0 ? -q : q)];
                    for (int ch = 0; ch < 4; ++ch) sum[ch] += m * acc[8 * c + ch];
                    ++c;
                }
            float amp0 = pr[1];
            if (sum[3] > MIN_WEIGHT_FRACTION * amp0 * amp0 * acc[3] && sum[3] > 0.0f) {
                for (int ch = 0; ch < 3; ++ch) o[ch] = sum[ch] / sum[3];
                o[3] = 1.0f;
            } else if (acc[3] > 0.0f) {
                for (int ch = 0; ch < 3; ++ch) o[ch] = acc[ch] / acc[3];
                o[3] = 2.0f;
            }
        }
    free(tmp);
    free(acc);
}

bool maaf_filter_dump(const MaafFilterInput *in, const char *path)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return false;
    size_t n = (size_t)in->width * (size_t)in->height, per = (size_t)maaf_component_count(in->pairs) * 8;
    int dims[3] = {in->width, in->height, in->pairs};
    float rules[2] = {in->cos_normal_min, in->depth_tol_rel};
    bool ok = fwrite(MAAF_DUMP_MAGIC, 1, 8, fp) == 8 && fwrite(dims, sizeof(int), 3, fp) == 3 &&
              fwrite(rules, sizeof(float), 2, fp) == 2 && fwrite(in->ysum, sizeof(float), n * per, fp) == n * per &&
              fwrite(in->pos4, sizeof(float), 4 * n, fp) == 4 * n && fwrite(in->nrm4, sizeof(float), 4 * n, fp) == 4 * n &&
              fwrite(in->frame4, sizeof(float), 4 * n, fp) == 4 * n && fwrite(in->axis2_4, sizeof(float), 4 * n, fp) == 4 * n &&
              fwrite(in->param, sizeof(float), n * MAAF_PARAM_STRIDE, fp) == n * MAAF_PARAM_STRIDE;
    return fclose(fp) == 0 && ok;
}

/* ---- OpenCL ---- */

enum { BUF_IN, BUF_TMP, BUF_POS, BUF_NRM, BUF_FRAME, BUF_AXIS2, BUF_PARAM, BUF_OUT, BUF_COUNT };

struct MaafFilter {
    ClRuntime *rt;
    cl_kernel pass;
    cl_mem buf[BUF_COUNT];
    size_t bytes[BUF_COUNT];
};

MaafFilter *maaf_filter_create(ClRuntime *rt, Diag *d)
{
    MaafFilter *f = calloc(1, sizeof *f);
    if (!f) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return NULL;
    }
    f->rt = rt;
    if (!(f->pass = cl_runtime_kernel(rt, "maaf_pass", d))) {
        maaf_filter_destroy(f);
        return NULL;
    }
    return f;
}

void maaf_filter_destroy(MaafFilter *f)
{
    if (!f) return;
    for (int b = 0; b < BUF_COUNT; ++b)
        if (f->buf[b]) clReleaseMemObject(f->buf[b]);
    if (f->pass) clReleaseKernel(f->pass);
    free(f);
}

static bool cl_ok(cl_int err, const char *what, Diag *d)
{
    if (err == CL_SUCCESS) return true;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL %s: %s", what, cl_error_name(err));
    return false;
}

/* (Re)creates buffer b with at least bytes and, when src is given, queues its upload. */
static bool buffer(MaafFilter *f, int b, size_t bytes, const void *src, Diag *d)
{
    cl_int err = CL_SUCCESS;
    if (f->bytes[b] < bytes) {
        if (f->buf[b]) clReleaseMemObject(f->buf[b]);
        f->buf[b] = clCreateBuffer(f->rt->context, CL_MEM_READ_WRITE, bytes, NULL, &err);
        f->bytes[b] = err == CL_SUCCESS ? bytes : 0;
        if (!cl_ok(err, "buffer allocation", d)) return false;
    }
    if (src) err = clEnqueueWriteBuffer(f->rt->queue, f->buf[b], CL_FALSE, 0, bytes, src, 0, NULL, NULL);
    return cl_ok(err, "upload", d);
}

static double event_seconds(cl_event e)
{
    cl_ulong t0 = 0, t1 = 0;
    if (!e || clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_START, sizeof t0, &t0, NULL) != CL_SUCCESS ||
        clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_END, sizeof t1, &t1, NULL) != CL_SUCCESS)
        return 0.0;
    return t1 > t0 ? (double)(t1 - t0) * 1e-9 : 0.0;
}

bool maaf_filter_run(MaafFilter *f, const MaafFilterInput *in, float *out4, double *kernel_seconds, Diag *d)
{
    if (kernel_seconds) *kernel_seconds = 0.0;
    size_t n = (size_t)in->width * (size_t)in->height;
    int comps = maaf_component_count(in->pairs);
    size_t ybytes = n * (size_t)comps * 8 * sizeof(float);
    bool ok = buffer(f, BUF_IN, ybytes, in->ysum, d) && buffer(f, BUF_TMP, ybytes, NULL, d) &&
              buffer(f, BUF_POS, n * 16, in->pos4, d) && buffer(f, BUF_NRM, n * 16, in->nrm4, d) &&
              buffer(f, BUF_FRAME, n * 16, in->frame4, d) && buffer(f, BUF_AXIS2, n * 16, in->axis2_4, d) &&
              buffer(f, BUF_PARAM, n * MAAF_PARAM_STRIDE * sizeof(float), in->param, d) &&
              buffer(f, BUF_OUT, n * 16, NULL, d);
    cl_event ev[2] = {NULL, NULL};
    for (int axis = 0; axis < 2 && ok; ++axis) {
        cl_int ints[5] = {in->width, in->height, axis, in->pairs, comps}, err = CL_SUCCESS;
        cl_uint a = 0;
        for (int k = 0; k < 5; ++k) err |= clSetKernelArg(f->pass, a++, sizeof(cl_int), &ints[k]);
        err |= clSetKernelArg(f->pass, a++, sizeof(float), &in->cos_normal_min);
        err |= clSetKernelArg(f->pass, a++, sizeof(float), &in->depth_tol_rel);
        err |= clSetKernelArg(f->pass, a++, sizeof(cl_mem), &f->buf[axis == 0 ? BUF_IN : BUF_TMP]);
        for (int b = BUF_POS; b <= BUF_PARAM; ++b) err |= clSetKernelArg(f->pass, a++, sizeof(cl_mem), &f->buf[b]);
        err |= clSetKernelArg(f->pass, a++, sizeof(cl_mem), &f->buf[BUF_TMP]);
        err |= clSetKernelArg(f->pass, a++, sizeof(cl_mem), &f->buf[BUF_OUT]);
        ok = cl_ok(err, "maaf_pass arguments", d) &&
             cl_launch_2d(f->rt, f->pass, (size_t)in->width, (size_t)in->height, &ev[axis], d);
    }
    ok = ok && cl_ok(clEnqueueReadBuffer(f->rt->queue, f->buf[BUF_OUT], CL_TRUE, 0, n * 16, out4, 0, NULL, NULL),
                     "download", d);
    if (!ok) clFinish(f->rt->queue); /* the host arrays must outlive any copy still queued */
    if (kernel_seconds && ok) *kernel_seconds = event_seconds(ev[0]) + event_seconds(ev[1]);
    for (int i = 0; i < 2; ++i)
        if (ev[i]) clReleaseEvent(ev[i]);
    return ok;
}
