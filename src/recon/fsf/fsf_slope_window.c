/* FSF's windowed slope ranges (fsf_slope_window.h). */
#include "recon/fsf/fsf_slope_window.h"

#include <math.h>
#include <stdlib.h>

#include "core/vectorise.h"
#include "recon/fsf/fsf_filter.h"
#include "core/huge_pages.h"
#include "recon/recon_parallel.h"

const int FSF_LEVEL_RADIUS_PX[FSF_LEVELS] = {2, 4, 8, FSF_RADIUS_CAP_PX};

typedef struct {
    int w, h, level;
    const float *own_lo, *own_hi, *obj;
    float *tmp_lo, *tmp_hi;
    FsfSlopeWindows *out;
} Job;

typedef struct {
    const SampleStore *st;
    float (*slope)(const void *ctx, size_t slot);
    const void *ctx;
    float *own_lo, *own_hi;
} OwnJob;

/* fminf / fmaxf for the window sums, inline (the ranges hold no NaN: own_range skips them;
 * gcc calls libm's fminf and fmaxf, which took more than half of the windows' time) */
static inline float min_f(float a, float b) { return b < a ? b : a; }
static inline float max_f(float a, float b) { return b > a ? b : a; }

static void own_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const OwnJob *j = ctx;
    size_t cap = (size_t)sample_store_capacity(j->st);
    for (size_t i = begin; i < end; ++i) {
        float lo = INFINITY, hi = -INFINITY;
        int count = sample_store_count(j->st, i); /* once: a call into another file per sample otherwise */
        for (int k = 0; k < count; ++k) {
            float s = j->slope(j->ctx, i * cap + (size_t)k);
            if (isnan(s)) continue;
            lo = min_f(lo, s), hi = max_f(hi, s);
        }
        j->own_lo[i] = lo, j->own_hi[i] = hi;
    }
}

/* One step of a sliding window, over a row of n pixels: out[x] takes in[x + dq]'s range
 * where the pixel x + dq is on out's centre object (obj_c[x] == obj_q[x + dq]; no object
 * ids: always). x innermost over contiguous memory, no branch: gcc vectorises it (the
 * windows ran one pixel at a time before, the columns' pass at a stride of a row per tap).
 * min and max are exact, so the order of the taps changes nothing. Inlined always: gcc does
 * not inline a default-target function into window_rows' and window_cols' AVX clones by itself,
 * and called from them it ran with SSE2 (2.1 of the plan's 9.4 ms CPU of windows at 256x256). */
static inline __attribute__((always_inline)) void window_step(int n, int dq, const float *restrict in_lo,
                                                              const float *restrict in_hi, const float *restrict obj_c,
                                                              const float *restrict obj_q, float *restrict lo,
                                                              float *restrict hi)
{
    int x0 = dq < 0 ? -dq : 0, x1 = dq > 0 ? n - dq : n;
    if (obj_c)
        for (int x = x0; x < x1; ++x) {
            /* another object's pixel gives the empty range, which changes nothing */
            float a = in_lo[x + dq], b = in_hi[x + dq];
            bool same = obj_q[x + dq] == obj_c[x];
            a = same ? a : INFINITY, b = same ? b : -INFINITY;
            lo[x] = min_f(lo[x], a), hi[x] = max_f(hi[x], b);
        }
    else
        for (int x = x0; x < x1; ++x) lo[x] = min_f(lo[x], in_lo[x + dq]), hi[x] = max_f(hi[x], in_hi[x + dq]);
}

static inline __attribute__((always_inline)) void window_init(int n, float *lo, float *hi)
{
    for (int x = 0; x < n; ++x) lo[x] = INFINITY, hi[x] = -INFINITY;
}

/* Sliding min / max of the own ranges along rows (own -> tmp) then columns (tmp -> level),
 * both a row of output at a time. With obj, only pixels joined to the centre by a row then a
 * column on its object count. Compiled for AVX2 and AVX-512 too (core/vectorise.h): min, max
 * and the id compares are exact in any width. */
static WEDGE_VECTORISED void window_rows(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    int w = j->w, r = FSF_LEVEL_RADIUS_PX[j->level];
    for (size_t y = begin; y < end; ++y) {
        size_t row = y * (size_t)w;
        const float *obj = j->obj ? j->obj + row : NULL;
        window_init(w, j->tmp_lo + row, j->tmp_hi + row);
        for (int dq = -r; dq <= r; ++dq)
            window_step(w, dq, j->own_lo + row, j->own_hi + row, obj, obj, j->tmp_lo + row, j->tmp_hi + row);
    }
}

static WEDGE_VECTORISED void window_cols(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    int w = j->w, h = j->h, r = FSF_LEVEL_RADIUS_PX[j->level];
    for (size_t y = begin; y < end; ++y) {
        size_t row = y * (size_t)w;
        float *lo = j->out->lo[j->level] + row, *hi = j->out->hi[j->level] + row;
        window_init(w, lo, hi);
        for (int q = (int)y - r; q <= (int)y + r; ++q) {
            if (q < 0 || q >= h) continue;
            size_t qrow = (size_t)q * (size_t)w;
            window_step(w, 0, j->tmp_lo + qrow, j->tmp_hi + qrow, j->obj ? j->obj + row : NULL,
                        j->obj ? j->obj + qrow : NULL, lo, hi);
        }
    }
}

bool fsf_slope_windows(const SampleStore *st, int width, int height, float (*slope)(const void *ctx, size_t slot),
                       const void *ctx, const float *obj, FsfSlopeWindows *out)
{
    size_t n = (size_t)width * (size_t)height;
    /* written once a frame: in 2 MB pages (huge_pages.h), freed with free() */
    out->block = huge_pages_alloc(sizeof(float) * n * (4 + 2 * FSF_LEVELS));
    if (!out->block) return false;
    for (int l = 0; l < FSF_LEVELS; ++l) out->lo[l] = out->block + 2 * (size_t)l * n, out->hi[l] = out->lo[l] + n;
    float *own_lo = out->block + (2 * FSF_LEVELS + 2) * n, *own_hi = own_lo + n;
    out->own_lo = own_lo, out->own_hi = own_hi;
    OwnJob oj = {st, slope, ctx, own_lo, own_hi};
    recon_parallel_for(n, own_range, &oj);
    Job j = {width, height, 0, own_lo, own_hi, obj, out->block + 2 * FSF_LEVELS * n, out->block + (2 * FSF_LEVELS + 1) * n,
             out};
    for (j.level = 0; j.level < FSF_LEVELS; ++j.level) {
        recon_parallel_for((size_t)height, window_rows, &j);
        recon_parallel_for((size_t)height, window_cols, &j);
    }
    return true;
}

void fsf_slope_windows_update(FsfSlopeWindows *w, int width, int height, const float *obj, int y0, int y1)
{
    size_t n = (size_t)width * (size_t)height;
    float *own_lo = w->block + (2 * FSF_LEVELS + 2) * n, *own_hi = own_lo + n;
    Job j = {width, height, 0, own_lo, own_hi, obj, w->block + 2 * FSF_LEVELS * n, w->block + (2 * FSF_LEVELS + 1) * n, w};
    for (j.level = 0; j.level < FSF_LEVELS; ++j.level) {
        /* a level's output row y reads the row sums of rows y - r .. y + r, and those read their own
         * row's ids: the rows within r of a changed one change, and their row sums are needed
         * within 2 r (the rows pass's scratch holds the last level's only) */
        int r = FSF_LEVEL_RADIUS_PX[j.level];
        int t0 = y0 - 2 * r < 0 ? 0 : y0 - 2 * r, t1 = y1 + 2 * r + 1 < height ? y1 + 2 * r + 1 : height;
        int o0 = y0 - r < 0 ? 0 : y0 - r, o1 = y1 + r + 1 < height ? y1 + r + 1 : height;
        window_rows(&j, (size_t)t0, (size_t)t1, 0);
        window_cols(&j, (size_t)o0, (size_t)o1, 0);
    }
}

bool fsf_slope_windows_per_object(const SampleStore *st, const GBuffer *g, float (*slope)(const void *ctx, size_t slot),
                                  const void *ctx, FsfSlopeWindows *out)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    float *obj = malloc(sizeof(float) * n); /* object id per pixel (gbuffer nrm4[3]) */
    if (!obj) return false;
    for (size_t i = 0; i < n; ++i) obj[i] = g->nrm4[4 * i + 3];
    bool ok = fsf_slope_windows(st, g->width, g->height, slope, ctx, obj, out);
    free(obj);
    return ok;
}

void fsf_slope_windows_free(FsfSlopeWindows *w)
{
    free(w->block);
    w->block = NULL;
}

FsfSlopePick fsf_slope_pick(const FsfSlopeWindows *w, size_t i, float (*sigma_of_spread)(const void *ctx, float spread),
                            const void *ctx)
{
    FsfSlopePick p = {INFINITY, -INFINITY, 0.0f};
    float best = -1.0f;
    for (int l = 0; l < FSF_LEVELS; ++l) {
        float ll = w->lo[l][i], hh = w->hi[l][i], r_cap = (float)FSF_LEVEL_RADIUS_PX[l] / FSF_RADIUS_SIGMAS;
        float sl = r_cap;
        if (ll <= hh) sl = fminf(sigma_of_spread(ctx, hh - ll), r_cap);
        if (sl > best) best = sl, p.lo = ll, p.hi = hh, p.cap_px = r_cap;
    }
    return p;
}
