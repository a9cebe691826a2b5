/* Host side and C reference of the MAAF image pass (see maaf_filter.h and maaf.cl). */
#include "recon/maaf/maaf_filter.h"

#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "recon/cl/cl_runtime_internal.h"

#define MIN_WEIGHT_FRACTION 0.2f /* MAAF_MIN_WEIGHT_FRACTION in maaf.cl */

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

void maaf_factors_accumulate(int comps, const float *w, const float f4[4], float *ysum)
{
    /* the value and the factor spread over a component's 8 sums: one loop of 8 per component,
     * which vectorises without shuffles (the compiler vectorised the plain re/im loop across
     * components instead: 1.4x slower in a micro-benchmark) */
    float f[8] = {f4[0], f4[1], f4[2], f4[3], f4[0], f4[1], f4[2], f4[3]};
    for (int c = 0; c < comps; ++c) {
        float wc[8] = {w[2 * c], w[2 * c], w[2 * c], w[2 * c], w[2 * c + 1], w[2 * c + 1], w[2 * c + 1], w[2 * c + 1]};
        float *y = ysum + 8 * c;
        for (int k = 0; k < 8; ++k) y[k] += wc[k] * f[k];
    }
}

float maaf_sharp_factor(const MaafFilterInput *in) { return in->sharp_factor > 0.0f ? in->sharp_factor : MAAF_SHARP_FACTOR_DEFAULT; }

/* One 1D pass (maaf.cl's maaf_rows for axis 0, maaf_cols for axis 1) for pixel (x, y); acc
 * receives 8 floats per component. */
static void pass_pixel(const MaafFilterInput *in, const float *src, int axis, int x, int y, float *acc)
{
    int w = in->width, h = in->height, pairs = in->pairs, comps = maaf_component_count(pairs);
    int i = y * w + x;
    const float *pr = in->param + (size_t)i * MAAF_PARAM_STRIDE;
    int radius = (int)pr[0];
    memset(acc, 0, (size_t)comps * 8 * sizeof(float));
    const float *t1 = in->frame4 + 4 * i, *t2 = in->axis2_4 + 4 * i;
    const float *cp = in->pos4 + 4 * i, *cn = in->nrm4 + 4 * i;
    float tol = in->depth_tol_rel * cp[3], sharp = maaf_sharp_factor(in);
    for (int k = -radius; k <= radius; ++k) {
        int nx = axis == 0 ? x + k : x, ny = axis == 0 ? y : y + k;
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        int j = ny * w + nx;
        if (in->frame4[4 * j + 3] == 0.0f) continue;
        const float *np = in->pos4 + 4 * j, *nn = in->nrm4 + 4 * j;
        float dlt[3] = {cp[0] - np[0], cp[1] - np[1], cp[2] - np[2]};
        if (nn[3] != cn[3] || dot3(cn, nn) < in->cos_normal_min || fabsf(dot3(cn, dlt)) > tol) continue;
        const float *pn = in->param + (size_t)j * MAAF_PARAM_STRIDE;
        if (pn[0] <= 0.0f || pn[3] > sharp * pr[3]) continue; /* maaf.cl's sharpness rule */
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

/* in's sums as one interleaved array: in->ysum, or written by in->fill into host planes of the
 * whole frame and gathered from them into *owned. */
static const float *input_sums(const MaafFilterInput *in, float **owned)
{
    *owned = NULL;
    if (in->ysum || !in->fill) return in->ysum;
    int per = 8 * maaf_component_count(in->pairs);
    size_t plane = (size_t)in->width + 2 * MAAF_PLANES_PAD, row = plane * (size_t)(per + 1);
    MaafPlanes pl = {calloc(row * (size_t)in->height, sizeof(float)), row, plane, in->width, in->height, per, 0, NULL};
    if (pl.base && (*owned = malloc((size_t)in->width * in->height * (size_t)per * sizeof(float)))) {
        in->fill(in->fill_ctx, &pl, 0, in->height);
        for (int y = 0; y < in->height; ++y)
            for (int x = 0; x < in->width; ++x) maaf_planes_get(&pl, x, y, *owned + ((size_t)y * in->width + x) * per);
    }
    free(pl.base);
    return *owned;
}

void maaf_filter_reference(const MaafFilterInput *in, float *out4)
{
    int w = in->width, h = in->height, pairs = in->pairs, comps = maaf_component_count(pairs);
    size_t n = (size_t)w * h, per = (size_t)comps * 8;
    float *tmp = malloc(n * per * sizeof(float));
    float *acc = malloc(per * sizeof(float));
    float *owned;
    const float *ysum = input_sums(in, &owned);
    if (!tmp || !acc || !ysum) {
        memset(out4, 0, 4 * n * sizeof(float)); /* nothing filtered */
        free(tmp);
        free(acc);
        free(owned);
        return;
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            if (in->frame4[4 * i + 3] == 0.0f || (int)in->param[i * MAAF_PARAM_STRIDE] <= 0)
                memcpy(tmp + i * per, ysum + i * per, per * sizeof(float));
            else
                pass_pixel(in, ysum, 0, x, y, tmp + i * per);
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
                    /* without amplitude it adds nothing, non-finite sums included (maaf_cols) */
                    if (m != 0.0f)
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
    free(owned);
}

bool maaf_filter_dump(const MaafFilterInput *in, const char *path)
{
    float *owned;
    const float *ysum = input_sums(in, &owned);
    FILE *fp = ysum ? fopen(path, "wb") : NULL;
    if (!fp) {
        free(owned);
        return false;
    }
    size_t n = (size_t)in->width * (size_t)in->height, per = (size_t)maaf_component_count(in->pairs) * 8;
    int dims[3] = {in->width, in->height, in->pairs};
    float rules[2] = {in->cos_normal_min, in->depth_tol_rel};
    const float *part[6] = {ysum, in->pos4, in->nrm4, in->frame4, in->axis2_4, in->param};
    size_t count[6] = {n * per, 4 * n, 4 * n, 4 * n, 4 * n, n * MAAF_PARAM_STRIDE};
    bool ok = fwrite(MAAF_DUMP_MAGIC, 1, 8, fp) == 8 && fwrite(dims, sizeof(int), 3, fp) == 3 &&
              fwrite(rules, sizeof(float), 2, fp) == 2;
    for (int k = 0; k < 6 && ok; ++k) ok = fwrite(part[k], sizeof(float), count[k], fp) == count[k];
    free(owned);
    return fclose(fp) == 0 && ok;
}

/* ---- OpenCL ---- */

/* maaf.cl's layout: 8 pixels per work item, GUIDES guide planes, rows padded by PAD pixels
 * (MAAF_GUIDES and MAAF_PAD there). */
#define LANES 8
#define GUIDES 11
#define PAD MAAF_PLANES_PAD

enum { BUF_POS, BUF_NRM, BUF_FRAME, BUF_AXIS2, BUF_PARAM, BUF_GUIDE, BUF_YP, BUF_TP, BUF_OUT, BUF_NEED, BUF_COUNT };
enum { K_UNPACK, K_ROWS, K_COLS, K_COUNT };
static const char *const KERNEL_NAMES[K_COUNT] = {"maaf_unpack", "maaf_rows", "maaf_cols"};

struct MaafFilter {
    ClRuntime *rt;
    cl_int *need; /* row_needs's flags, host side */
    size_t need_count;
    unsigned char *full; /* a band's rows: which pixels have every plane read (MaafPlanes.full) */
    size_t full_count;
    cl_kernel k[K_COUNT];
    cl_mem buf[BUF_COUNT];
    size_t bytes[BUF_COUNT];
    double seconds[K_COUNT]; /* the last run's */
};

MaafFilter *maaf_filter_create(ClRuntime *rt, Diag *d)
{
    MaafFilter *f = calloc(1, sizeof *f);
    if (!f) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return NULL;
    }
    f->rt = rt;
    for (int k = 0; k < K_COUNT; ++k)
        if (!(f->k[k] = cl_runtime_kernel(rt, KERNEL_NAMES[k], d))) {
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
    for (int k = 0; k < K_COUNT; ++k)
        if (f->k[k]) clReleaseKernel(f->k[k]);
    free(f->need);
    free(f->full);
    free(f);
}

static bool cl_ok(cl_int err, const char *what, Diag *d)
{
    if (err == CL_SUCCESS) return true;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL %s: %s", what, cl_error_name(err));
    return false;
}

/* (Re)creates work buffer b with at least bytes (kept for the next run). */
static bool buffer(MaafFilter *f, int b, size_t bytes, Diag *d)
{
    cl_int err = CL_SUCCESS;
    if (f->bytes[b] < bytes) {
        if (f->buf[b]) clReleaseMemObject(f->buf[b]);
        f->buf[b] = clCreateBuffer(f->rt->context, CL_MEM_READ_WRITE, bytes, NULL, &err);
        f->bytes[b] = err == CL_SUCCESS ? bytes : 0;
    }
    return cl_ok(err, "buffer allocation", d);
}

/* Buffer b on the caller's array for this run (CL_MEM_USE_HOST_PTR): a CPU device reads it in
 * place, where an upload copied 27 MB at 256x256 into memory touched for the first time; other
 * devices copy it as before. release_inputs drops it before the array can go away. */
static bool host_buffer(MaafFilter *f, int b, size_t bytes, const void *src, Diag *d)
{
    cl_int err = CL_SUCCESS;
    if (f->buf[b]) clReleaseMemObject(f->buf[b]);
    f->buf[b] = clCreateBuffer(f->rt->context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, bytes, (void *)src, &err);
    f->bytes[b] = 0; /* never reused by buffer() */
    if (err != CL_SUCCESS) f->buf[b] = NULL;
    return cl_ok(err, "input buffer", d);
}

static void release_inputs(MaafFilter *f)
{
    for (int b = BUF_POS; b <= BUF_PARAM; ++b)
        if (f->buf[b]) {
            clReleaseMemObject(f->buf[b]);
            f->buf[b] = NULL;
        }
}

/* Floats between one plane and the next: whole 4 KiB pages plus one cache line, so that a
 * tap's reads of the same pixel in 100 planes fall into different cache sets (a whole number
 * of pages apart they all map to one set of an 8-way L1 and evict each other: measured 2x). */
static size_t plane_stride(size_t floats) { return (floats + 1023) / 1024 * 1024 + 16; }
/* The same within a row of the sums: an odd number of cache lines. */
static size_t line_stride(size_t floats) { return ((floats + 15) / 16 | 1) * 16; }

void maaf_filter_kernel_seconds(const MaafFilter *f, double seconds[MAAF_FILTER_KERNELS])
{
    for (int k = 0; k < K_COUNT; ++k) seconds[k] = f->seconds[k];
}

/* Sets kernel k's arguments: ints, then floats, then buffers, in that order. */
static bool set_args(MaafFilter *f, int k, const cl_int *ints, int ni, const float *floats, int nf, const int *bufs,
                     int nb, const cl_int *ints2, int ni2, Diag *d)
{
    cl_int err = CL_SUCCESS;
    cl_uint a = 0;
    for (int i = 0; i < ni; ++i) err |= clSetKernelArg(f->k[k], a++, sizeof(cl_int), &ints[i]);
    for (int i = 0; i < nf; ++i) err |= clSetKernelArg(f->k[k], a++, sizeof(float), &floats[i]);
    for (int i = 0; i < ni2; ++i) err |= clSetKernelArg(f->k[k], a++, sizeof(cl_int), &ints2[i]);
    for (int i = 0; i < nb; ++i) err |= clSetKernelArg(f->k[k], a++, sizeof(cl_mem), &f->buf[bufs[i]]);
    return cl_ok(err, KERNEL_NAMES[k], d);
}

/* Which row-pass work items (8 pixels of a row, need[y * tblocks + x / 8]) must sum every
 * component: those that a column-pass work item with amplitude beyond band 0 in some lane
 * reads, i.e. one in the same 8 columns within *reach rows. The others' column readers use the
 * central component alone (maaf_cols skips components without amplitude), so the row pass sums
 * only that one: the shadows' plain pixels (AAF's far rule). *reach: the largest radius a work
 * item of either pass can take (the kernels' integer radius, capped), which bounds the column
 * pass's taps; a window of the cap instead (as until 2026-11-29) marked twice the work items
 * of the combined bench's shadow pass (34% against 17% at 7 spp; its lens pass 98% against 88%). */
static bool row_needs(MaafFilter *f, const MaafFilterInput *in, int tblocks, int *reach)
{
    int w = in->width, h = in->height;
    size_t count = (size_t)h * (size_t)tblocks;
    if (f->need_count < count) {
        free(f->need);
        f->need_count = 0;
        if (!(f->need = malloc(count * sizeof(cl_int)))) return false;
        f->need_count = count;
    }
    unsigned char *amp = calloc(count, 1);
    if (!amp) return false;
    float most = 0.0f;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float *pr = in->param + ((size_t)y * w + x) * MAAF_PARAM_STRIDE;
            for (int p = 1; p < in->pairs; ++p)
                if (pr[1 + 3 * p] != 0.0f) amp[(size_t)y * tblocks + x / LANES] = 1;
            /* as centre_load: fmin(trunc(radius), cap), NaN reads as the cap */
            float r = pr[0] < (float)MAAF_RADIUS_CAP_PX ? truncf(pr[0]) : (float)MAAF_RADIUS_CAP_PX;
            if (r > most) most = r;
        }
    int r = *reach = (int)most;
    for (int b = 0; b < tblocks; ++b) { /* a sliding window of 2 reach + 1 rows per column of blocks */
        int inside = 0;
        for (int y = 0; y < r && y < h; ++y) inside += amp[(size_t)y * tblocks + b];
        for (int y = 0; y < h; ++y) {
            int enter = y + r, leave = y - r - 1;
            if (enter < h) inside += amp[(size_t)enter * tblocks + b];
            if (leave >= 0) inside -= amp[(size_t)leave * tblocks + b];
            f->need[(size_t)y * tblocks + b] = inside > 0;
        }
    }
    free(amp);
    return true;
}

/* maaf.cl's planes: the width rounded up to whole work items, the guides' and the sums' rows
 * padded, the row pass's output in blocks of 8 pixels; one flag plane after the sums. The sums
 * hold one band of yrows image rows (image row y in row y mod yrows), the row pass's output a
 * ring of trows: a band and the column pass's reach (the run's largest radius) on either side
 * (9.16). */
typedef struct {
    size_t w8, gpitch, rows, gplane, ystride, yfloats, tfloats, yrows, trows;
    int per;
} Layout;

static bool layout(int width, int height, int pairs, int reach, Layout *o, Diag *d)
{
    o->per = 8 * maaf_component_count(pairs);
    o->w8 = ((size_t)width + LANES - 1) / LANES * LANES, o->gpitch = o->w8 + 2 * PAD, o->rows = (size_t)height;
    size_t ring = MAAF_BAND_ROWS + 2 * (size_t)reach;
    o->yrows = o->rows < MAAF_BAND_ROWS ? o->rows : MAAF_BAND_ROWS;
    o->trows = o->rows < ring ? o->rows : ring;
    o->gplane = plane_stride(o->gpitch * o->rows), o->ystride = line_stride(o->gpitch);
    o->yfloats = o->ystride * (size_t)(o->per + 1) * o->yrows, o->tfloats = o->trows * o->w8 * (size_t)(o->per + 1);
    if (o->yfloats > (size_t)INT32_MAX || o->tfloats > (size_t)INT32_MAX || o->gplane * GUIDES > (size_t)INT32_MAX) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "MAAF filter: a %dx%d image is too large for its planes", width, height);
        return false;
    }
    return true;
}

/* MaafPlanes.full for image rows [y0, y1): a pixel is read in every plane only by the row-pass
 * work items that sum every component (row_needs), and those read the pixels of their row up to
 * reach away from their 8 (the kernels' integer radius, capped); the other work items read the
 * central component and the flag. NULL (every pixel full) when out of memory. */
static const unsigned char *band_full(MaafFilter *f, int width, int tblocks, int reach, int y0, int y1)
{
    size_t count = (size_t)width * MAAF_BAND_ROWS;
    if (f->full_count < count) {
        free(f->full);
        f->full_count = (f->full = malloc(count)) ? count : 0;
        if (!f->full) return NULL;
    }
    for (int y = y0; y < y1; ++y) {
        unsigned char *row = f->full + (size_t)(y - y0) * width;
        memset(row, 0, (size_t)width);
        for (int b = 0; b < tblocks; ++b) {
            if (!f->need[(size_t)y * tblocks + b]) continue;
            int x0 = b * LANES - reach < 0 ? 0 : b * LANES - reach, x1 = b * LANES + LANES - 1 + reach;
            if (x1 > width - 1) x1 = width - 1;
            if (x0 <= x1) memset(row + x0, 1, (size_t)(x1 - x0 + 1));
        }
    }
    return f->full;
}

/* Image rows [y0, y1) of the sums into BUF_YP (mapped: on a CPU device its own memory, no
 * copy), each plane's row padded with zeros; from in->fill, or from in->ysum where a pixel is
 * usable (zeros elsewhere). The blocking map waits for the row pass of the band before. */
static bool write_band(MaafFilter *f, const MaafFilterInput *in, const Layout *L, int tblocks, int reach, int y0, int y1,
                       Diag *d)
{
    size_t row = L->ystride * (size_t)(L->per + 1), bytes = row * (size_t)(y1 - y0) * sizeof(float);
    cl_int err = CL_SUCCESS;
    /* every float of the rows is written below: the old contents need not be read back (a copy
     * on devices with their own memory, nothing on a CPU) */
    float *base = clEnqueueMapBuffer(f->rt->queue, f->buf[BUF_YP], CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, bytes, 0,
                                     NULL, NULL, &err);
    if (!cl_ok(err, "map of the sums' planes", d)) return false;
    MaafPlanes pl = {base, row, L->ystride, in->width, in->height, L->per, y0, band_full(f, in->width, tblocks, reach, y0, y1)};
    for (int y = y0; y < y1; ++y)
        for (int k = 0; k <= L->per; ++k) {
            float *r = base + (size_t)(y - y0) * row + (size_t)k * L->ystride;
            memset(r, 0, PAD * sizeof(float));
            memset(r + PAD + in->width, 0, (L->gpitch - PAD - (size_t)in->width) * sizeof(float));
        }
    if (in->fill)
        in->fill(in->fill_ctx, &pl, y0, y1);
    else
        for (int y = y0; y < y1; ++y)
            for (int x = 0; x < in->width; ++x) {
                size_t i = (size_t)y * in->width + x;
                maaf_planes_put(&pl, x, y, in->frame4[4 * i + 3] != 0.0f ? in->ysum + i * (size_t)L->per : NULL);
            }
    return cl_ok(clEnqueueUnmapMemObject(f->rt->queue, f->buf[BUF_YP], base, 0, NULL, NULL), "unmap of the sums' planes", d);
}

bool maaf_planes_full(const MaafPlanes *pl, int x, int y)
{
    return !pl->full || pl->full[(size_t)(y - pl->y0) * (size_t)pl->width + (size_t)x];
}

void maaf_planes_put(const MaafPlanes *pl, int x, int y, const float *v)
{
    float *o = pl->base + (size_t)(y - pl->y0) * pl->row + PAD + (size_t)x;
    size_t plane = pl->plane;
    int per = pl->per, used = maaf_planes_full(pl, x, y) ? per : 8; /* else the central component's */
    if (!v) {
        for (int k = 0; k < used; ++k) o[(size_t)k * plane] = 0.0f;
        o[(size_t)per * plane] = 0.0f;
        return;
    }
    /* a non-finite float has every exponent bit set: one test over all of them (vectorised),
     * not a branch per float */
    uint32_t bad = 0;
    for (int k = 0; k < used; ++k) {
        uint32_t bits;
        memcpy(&bits, &v[k], sizeof bits);
        bad |= (bits & 0x7f800000u) == 0x7f800000u;
    }
    for (int k = 0; k < used; ++k) o[(size_t)k * plane] = v[k];
    o[(size_t)per * plane] = bad ? 1.0f : 0.0f;
}

void maaf_planes_get(const MaafPlanes *pl, int x, int y, float *v)
{
    const float *o = pl->base + (size_t)(y - pl->y0) * pl->row + PAD + (size_t)x;
    for (int k = 0; k < pl->per; ++k) v[k] = o[(size_t)k * pl->plane];
}

/* The image pass band by band (9.16): per band of MAAF_BAND_ROWS rows the host writes its sums,
 * the row pass filters them into the ring of row-pass output, and the column pass then filters
 * every row whose column reach (the run's largest radius) that output now covers. The queue runs
 * in order: a band's sums are rewritten only after the row pass of the band before has read
 * them, and a ring row only after the column pass that read it. Both passes run in work-groups
 * of one work-item (cl_launch_serial_2d): with cl_launch_2d's 64 items a group PoCL kept each
 * item's taps' factors (Taps: ~44 KB) in a slot of a per-group array. */
bool maaf_filter_run(MaafFilter *f, const MaafFilterInput *in, float *out4, double *kernel_seconds, Diag *d)
{
    if (kernel_seconds) *kernel_seconds = 0.0;
    for (int k = 0; k < K_COUNT; ++k) f->seconds[k] = 0.0;
    size_t n = (size_t)in->width * (size_t)in->height;
    int comps = maaf_component_count(in->pairs), reach = MAAF_RADIUS_CAP_PX;
    Layout L;
    if (!layout(in->width, in->height, in->pairs, reach, &L, d)) return false;
    if (!in->ysum && !in->fill) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "MAAF filter: no sums");
        return false;
    }
    if (!row_needs(f, in, (int)(L.w8 / LANES), &reach)) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return false;
    }
    layout(in->width, in->height, in->pairs, reach, &L, d); /* the ring for this run's reach */
    bool ok = host_buffer(f, BUF_POS, n * 16, in->pos4, d) && host_buffer(f, BUF_NRM, n * 16, in->nrm4, d) &&
              host_buffer(f, BUF_FRAME, n * 16, in->frame4, d) && host_buffer(f, BUF_AXIS2, n * 16, in->axis2_4, d) &&
              host_buffer(f, BUF_PARAM, n * MAAF_PARAM_STRIDE * sizeof(float), in->param, d) &&
              buffer(f, BUF_GUIDE, L.gplane * GUIDES * sizeof(float), d) && buffer(f, BUF_YP, L.yfloats * sizeof(float), d) &&
              buffer(f, BUF_TP, L.tfloats * sizeof(float), d) && buffer(f, BUF_OUT, n * 16, d) &&
              buffer(f, BUF_NEED, L.rows * (L.w8 / LANES) * sizeof(cl_int), d);
    cl_int w = in->width, h = in->height, gp = (cl_int)L.gpitch, gpl = (cl_int)L.gplane, ys = (cl_int)L.ystride;
    cl_int tb = (cl_int)(L.w8 / LANES), yrows = (cl_int)L.yrows, trows = (cl_int)L.trows;
    ok = ok && cl_ok(clEnqueueWriteBuffer(f->rt->queue, f->buf[BUF_NEED], CL_FALSE, 0, L.rows * (size_t)tb * sizeof(cl_int),
                                          f->need, 0, NULL, NULL),
                     "upload", d);
    float rules[3] = {in->cos_normal_min, in->depth_tol_rel, maaf_sharp_factor(in)};
    /* one event per launch: the guides, and a row and a column pass per band */
    int bands = (h + MAAF_BAND_ROWS - 1) / MAAF_BAND_ROWS, events = 0;
    cl_event *ev = calloc((size_t)(1 + 2 * bands), sizeof *ev);
    int *ev_kernel = calloc((size_t)(1 + 2 * bands), sizeof *ev_kernel);
    if (ok && (!ev || !ev_kernel)) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        ok = false;
    }
    if (ok) {
        cl_int ints[4] = {w, h, gp, gpl};
        int bufs[5] = {BUF_POS, BUF_NRM, BUF_FRAME, BUF_PARAM, BUF_GUIDE};
        ev_kernel[events] = K_UNPACK;
        ok = set_args(f, K_UNPACK, ints, 4, NULL, 0, bufs, 5, NULL, 0, d) &&
             cl_launch_2d(f->rt, f->k[K_UNPACK], L.gpitch, L.rows, &ev[events++], d);
    }
    int done = 0; /* rows [0, done) are filtered */
    for (int y0 = 0; ok && y0 < h; y0 += MAAF_BAND_ROWS) {
        int y1 = y0 + MAAF_BAND_ROWS < h ? y0 + MAAF_BAND_ROWS : h;
        ok = write_band(f, in, &L, tb, reach, y0, y1, d);
        if (ok) {
            cl_int ints[4] = {w, h, in->pairs, comps}, ints2[8] = {gp, gpl, ys, tb, y0, y1, yrows, trows};
            int bufs[7] = {BUF_GUIDE, BUF_FRAME, BUF_AXIS2, BUF_PARAM, BUF_YP, BUF_TP, BUF_NEED};
            ev_kernel[events] = K_ROWS;
            ok = set_args(f, K_ROWS, ints, 4, rules, 3, bufs, 7, ints2, 8, d) &&
                 cl_launch_serial_2d(f->rt, f->k[K_ROWS], L.w8 / LANES, (size_t)(y1 - y0), &ev[events++], d);
        }
        /* the rows whose column taps (up to reach away) now all have their row-pass output */
        int ready = y1 == h ? h : y1 - reach;
        if (ok && ready > done) {
            cl_int ints[4] = {w, h, in->pairs, comps}, ints2[6] = {gp, gpl, tb, done, ready, trows};
            int bufs[6] = {BUF_GUIDE, BUF_FRAME, BUF_AXIS2, BUF_PARAM, BUF_TP, BUF_OUT};
            ev_kernel[events] = K_COLS;
            ok = set_args(f, K_COLS, ints, 4, rules, 3, bufs, 6, ints2, 6, d) &&
                 cl_launch_serial_2d(f->rt, f->k[K_COLS], L.w8 / LANES, (size_t)(ready - done), &ev[events++], d);
            done = ready;
        }
    }
    ok = ok && cl_ok(clEnqueueReadBuffer(f->rt->queue, f->buf[BUF_OUT], CL_TRUE, 0, n * 16, out4, 0, NULL, NULL),
                     "download", d);
    if (!ok) clFinish(f->rt->queue); /* the host arrays must outlive any command still queued */
    release_inputs(f);
    for (int e = 0; e < events; ++e) {
        if (!ev[e]) continue;
        double s = ok ? cl_event_seconds(ev[e]) : 0.0;
        f->seconds[ev_kernel[e]] += s;
        if (kernel_seconds) *kernel_seconds += s;
        clReleaseEvent(ev[e]);
    }
    free(ev);
    free(ev_kernel);
    return ok;
}
