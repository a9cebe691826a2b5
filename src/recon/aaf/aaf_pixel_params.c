/* Per-pixel AAF parameter maps (see aaf_pixel_params.h). */
#include "recon/aaf/aaf_pixel_params.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "recon/recon_parallel.h"

/* Box averages of up to three per-pixel quantities over the pixels flagged valid, via summed
 * area tables: O(1) per pixel whatever the radius. Double precision keeps the table exact
 * enough for 4K images of world distances. */
typedef struct {
    int w, h;
    double *sum[3]; /* (w+1) x (h+1) tables */
    double *count;
} BoxAverager;

typedef struct {
    BoxAverager *b;
    const bool *valid;
    const float *q[3];
} BoxBuild;

/* Table t (0..2: sum of q[t], 3: count) by the summed-area recurrence. */
static void box_build_table(BoxBuild *bb, int t)
{
    BoxAverager *b = bb->b;
    int w = b->w, h = b->h;
    double *tab = t == 3 ? b->count : b->sum[t];
    const float *q = t == 3 ? NULL : bb->q[t];
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            size_t o = (size_t)(y + 1) * (size_t)(w + 1) + (size_t)(x + 1);
            size_t up = o - (size_t)(w + 1), left = o - 1, diag = up - 1;
            double v = t == 3 ? (bb->valid[i] ? 1.0 : 0.0) : ((bb->valid[i] && q) ? (double)q[i] : 0.0);
            tab[o] = v + tab[up] + tab[left] - tab[diag];
        }
    }
}

/* The four tables are independent: two per core. */
static void box_build_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    for (size_t t = begin; t < end; ++t) box_build_table(ctx, (int)t);
}

static bool box_init(BoxAverager *b, int w, int h, const bool *valid, const float *q0, const float *q1,
                     const float *q2)
{
    size_t n = (size_t)(w + 1) * (size_t)(h + 1);
    b->w = w;
    b->h = h;
    /* calloc: row 0 and column 0 of every table stay 0 */
    b->count = calloc(n, sizeof(double));
    for (int k = 0; k < 3; ++k) b->sum[k] = calloc(n, sizeof(double));
    if (!b->count || !b->sum[0] || !b->sum[1] || !b->sum[2]) return false;
    BoxBuild bb = {b, valid, {q0, q1, q2}};
    recon_parallel_for_work(4, (size_t)w * (size_t)h, box_build_range, &bb);
    return true;
}

static void box_free(BoxAverager *b)
{
    free(b->count);
    for (int k = 0; k < 3; ++k) free(b->sum[k]);
}

static double box_query(const BoxAverager *b, const double *t, int x0, int y0, int x1, int y1)
{
    size_t W = (size_t)(b->w + 1);
    return t[(size_t)(y1 + 1) * W + (size_t)(x1 + 1)] - t[(size_t)y0 * W + (size_t)(x1 + 1)] -
           t[(size_t)(y1 + 1) * W + (size_t)x0] + t[(size_t)y0 * W + (size_t)x0];
}

/* Averages over the valid pixels in the (2r+1)^2 window around (x, y) without the centre
 * pixel's own values (self, when it is valid): the "leave one out" statistics of a pixel,
 * independent of its own samples. False when no other pixel there is valid. */
static bool box_average_others(const BoxAverager *b, int x, int y, int r, bool self_valid, const float self[3],
                               float out[3])
{
    int x0 = x - r < 0 ? 0 : x - r, y0 = y - r < 0 ? 0 : y - r;
    int x1 = x + r >= b->w ? b->w - 1 : x + r, y1 = y + r >= b->h ? b->h - 1 : y + r;
    double c = box_query(b, b->count, x0, y0, x1, y1) - (self_valid ? 1.0 : 0.0);
    if (c < 0.5) return false;
    for (int k = 0; k < 3; ++k)
        out[k] = (float)((box_query(b, b->sum[k], x0, y0, x1, y1) - (self_valid ? (double)self[k] : 0.0)) / c);
    return true;
}

static float at_or(const float *a, size_t i, float fallback) { return a ? a[i] : fallback; }
static bool pixel_hit(const AafPixelStats *st, size_t i) { return st->hit ? st->hit[i] != 0 : true; }

/* Chebyshev distance (pixels) from (x, y) to the nearest pixel flagged valid in the box, searched
 * from first_r up to max_r; max_r + 1 when there is none that close. O(1) per ring (one box
 * query), so a far pixel costs at most max_r - first_r queries. */
static int box_nearest_valid(const BoxAverager *b, int x, int y, int first_r, int max_r)
{
    for (int r = first_r; r <= max_r; ++r) {
        int x0 = x - r < 0 ? 0 : x - r, y0 = y - r < 0 ? 0 : y - r;
        int x1 = x + r >= b->w ? b->w - 1 : x + r, y1 = y + r >= b->h ? b->h - 1 : y + r;
        if (box_query(b, b->count, x0, y0, x1, y1) > 0.5) return r;
    }
    return max_r + 1;
}

/* Width for a pixel with no occluder (reflector) within the borrow radius, in world units:
 * far_beta_px, but narrowed so that the filter's taps (radius ceil(2 beta), aaf_filter.h) end
 * before the nearest pixel that saw one: dist - 1 >= 2 beta. Visibility is 1 everywhere the
 * taps reach, so the width can grow with the distance to the nearest shadow. */
static float far_beta_world(const AafPixelStats *st, size_t i, const AafImageConfig *ic, const BoxAverager *box,
                            int x, int y)
{
    float beta_px = ic->far_beta_px;
    if (beta_px <= 0.0f) return 0.0f;
    int reach_px = (int)ceilf(2.0f * beta_px);
    int dist_px = box_nearest_valid(box, x, y, ic->borrow_radius_px + 1, reach_px);
    /* 0.999: beta travels in world units and back, and its rounding must not add a tap */
    if (dist_px <= reach_px) beta_px = fminf(beta_px, 0.4995f * (float)(dist_px - 1));
    float b = beta_px * at_or(st->pixel_world, i, 0.0f);
    return (b > 0.0f && isfinite(b)) ? b : 0.0f;
}

/* The per-pixel part of the two borrowing parameter maps, over a range of rows on one core. */
typedef struct {
    const AafPixelStats *st;
    const void *cfg;             /* AafShadowConfig or AafIndirectConfig */
    const AafImageConfig *ic;
    const BoxAverager *box;
    const bool *own_data;        /* the pixel's own rays saw an occluder / reflector */
    float scene_size_world;
    float *beta_world;
    int *spp;
    int filtered[RECON_PARTS];
} ParamsRows;

/* The statistics a pixel's parameters are derived from: the mean over the other pixels of its
 * 3 x 3 neighbourhood that have data, else over its borrow window (AAF-shadow Sec. 6, AAF-GI
 * Sec. 5: a 5-pixel radius), else its own when it has data; false when nothing is near (a far
 * pixel). Never the pixel's own when a neighbour has data: its own rays also made its pass-1
 * value, and choosing its sample count and width from them biases its mean (a pixel whose rays
 * hit a near occluder or bright reflector would get its value and its extra samples together;
 * measured 1-2% off by region for indirect light, docs/algorithms.md section 2.5). */
static bool neighbour_stats(const ParamsRows *pr, int x, int y, size_t i, const float own[3], float avg[3])
{
    bool self = pr->own_data[i];
    if (box_average_others(pr->box, x, y, 1, self, own, avg) ||
        box_average_others(pr->box, x, y, pr->ic->borrow_radius_px, self, own, avg))
        return true;
    for (int k = 0; k < 3; ++k) avg[k] = own[k];
    return self;
}

/* A far pixel's width and count. */
static int far_params(const ParamsRows *pr, int x, int y, size_t i)
{
    pr->beta_world[i] = far_beta_world(pr->st, i, pr->ic, pr->box, x, y);
    if (pr->ic->far_spp > pr->spp[i]) pr->spp[i] = pr->ic->far_spp;
    return pr->beta_world[i] > 0.0f ? 1 : 0;
}

static void shadow_rows(void *ctx, size_t y0, size_t y1, int part)
{
    ParamsRows *pr = ctx;
    const AafPixelStats *st = pr->st;
    const AafShadowConfig *c = pr->cfg;
    const AafImageConfig *ic = pr->ic;
    int w = st->width, filtered = 0;
    for (int y = (int)y0; y < (int)y1; ++y) {
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            pr->beta_world[i] = 0.0f;
            pr->spp[i] = ic->spp_min;
            if (!pixel_hit(st, i)) continue;
            float own[3] = {0.0f, 0.0f, 0.0f}, avg[3];
            if (pr->own_data[i]) {
                own[0] = st->d1_world[i];
                own[1] = st->d2min_world[i];
                own[2] = st->d2max_world[i];
            }
            if (!neighbour_stats(pr, x, y, i, own, avg)) {
                filtered += far_params(pr, x, y, i);
                continue;
            }
            float d1 = avg[0], d2min = avg[1], d2max = avg[2];
            float s1, s2;
            aaf_shadow_slopes(d1, d2min, d2max, &s1, &s2); /* AAF-shadow eq. 4 */
            float sigma = at_or(st->sigma_light_world, i, 0.0f);
            float d = at_or(st->pixel_world, i, 0.0f);
            pr->beta_world[i] = aaf_shadow_beta_world(s2, sigma, d, c);                    /* eq. 13 */
            pr->spp[i] = aaf_clamp_spp(aaf_shadow_spp(s1, s2, sigma, d, c), ic->spp_min, ic->spp_cap); /* eq. 21 */
            if (pr->beta_world[i] > 0.0f) ++filtered;
        }
    }
    pr->filtered[part] = filtered;
}

/* Shared by the two borrowing maps: averages the statistics q0..q2 over the pixels marked in
 * own_data (the borrow box), runs `rows` over the image on both cores and frees own_data.
 * Out of memory (own_data NULL included): every pixel falls back to unfiltered Monte Carlo. */
static int run_param_rows(const AafPixelStats *st, const void *cfg, const AafImageConfig *ic, bool *own_data,
                          const float *q0, const float *q1, const float *q2, float scene_size_world,
                          void (*rows)(void *ctx, size_t y0, size_t y1, int part), float *beta_world, int *spp)
{
    int w = st->width, h = st->height;
    size_t n = (size_t)w * (size_t)h;
    BoxAverager box = {0};
    int filtered = 0;
    if (own_data && box_init(&box, w, h, own_data, q0, q1, q2)) {
        ParamsRows pr = {st, cfg, ic, &box, own_data, scene_size_world, beta_world, spp, {0}};
        recon_parallel_for_work((size_t)h, n, rows, &pr);
        for (int p = 0; p < RECON_PARTS; ++p) filtered += pr.filtered[p];
    } else {
        for (size_t i = 0; i < n; ++i) {
            beta_world[i] = 0.0f;
            spp[i] = ic->spp_min;
        }
    }
    box_free(&box);
    free(own_data);
    return filtered;
}

int aaf_shadow_params_image(const AafPixelStats *st, const AafShadowConfig *c, const AafImageConfig *ic,
                            float *beta_world, int *spp)
{
    size_t n = (size_t)st->width * (size_t)st->height;
    bool *occluded = calloc(n ? n : 1, sizeof(bool));
    for (size_t i = 0; occluded && i < n; ++i)
        occluded[i] = pixel_hit(st, i) && st->d2max_world && st->d2max_world[i] > 0.0f &&
                      isfinite(st->d2max_world[i]) && isfinite(st->d1_world[i]);
    return run_param_rows(st, c, ic, occluded, st->d1_world, st->d2min_world, st->d2max_world, 0.0f, shadow_rows,
                          beta_world, spp);
}

static void indirect_rows(void *ctx, size_t y0, size_t y1, int part)
{
    ParamsRows *pr = ctx;
    const AafPixelStats *st = pr->st;
    const AafIndirectConfig *c = pr->cfg;
    const AafImageConfig *ic = pr->ic;
    int w = st->width, filtered = 0;
    float scene_size_world = pr->scene_size_world;
    for (int y = (int)y0; y < (int)y1; ++y) {
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            pr->beta_world[i] = 0.0f;
            pr->spp[i] = ic->spp_min;
            if (!pixel_hit(st, i)) continue;
            float own[3] = {0.0f, 0.0f, 0.0f}, avg[3];
            if (pr->own_data[i]) {
                own[0] = st->zmin_world[i];
                own[1] = st->zmax_world[i];
            }
            if (!neighbour_stats(pr, x, y, i, own, avg)) {
                filtered += far_params(pr, x, y, i);
                continue;
            }
            float zmin = avg[0], zmax = avg[1];
            float m = at_or(st->blinn_phong_m, i, 0.0f);
            float omega_h = m > 0.0f ? aaf_indirect_omega_h_glossy(m) : aaf_indirect_omega_h_diffuse();
            float gamma = m > 0.0f ? aaf_indirect_gamma_glossy(m) : aaf_indirect_gamma_diffuse();
            float d = at_or(st->pixel_world, i, 0.0f);
            /* eqs. 15, 16 with the measured zmin (a floor of 0: only a NaN or non-positive
             * value is made tiny): eq. 15's pixel term alpha / d already keeps the width at
             * least 2 d / (mu alpha) as zmin -> 0 (corners stay filtered) */
            pr->beta_world[i] = aaf_indirect_beta_world(aaf_indirect_clamp_zmin(zmin, 0.0f, 0.0f), omega_h, d, c);
            /* AAF-GI Sec. 5: zmin at least 2% of the scene for the sample count */
            zmin = aaf_indirect_clamp_zmin(zmin, scene_size_world, c->zmin_clamp_frac);
            /* eq. 21, under our cap (its own, not the image's 100 mu: aaf_params.h) */
            pr->spp[i] = aaf_clamp_spp(aaf_indirect_spp(zmin, zmax, omega_h, gamma, d, c), ic->spp_min, aaf_indirect_spp_cap(c));
            if (pr->beta_world[i] > 0.0f) ++filtered;
        }
    }
    pr->filtered[part] = filtered;
}

int aaf_far_spp(int pass1, float mu)
{
    float grow = mu > 2.0f ? 0.5f * mu : 1.0f; /* also NaN -> 1 */
    return aaf_clamp_spp((float)pass1 * grow * grow * grow, pass1, FLT_MAX);
}

int aaf_indirect_params_image(const AafPixelStats *st, const AafIndirectConfig *c, const AafImageConfig *ic,
                              float scene_size_world, float *beta_world, int *spp)
{
    size_t n = (size_t)st->width * (size_t)st->height;
    bool *reflected = calloc(n ? n : 1, sizeof(bool));
    for (size_t i = 0; reflected && i < n; ++i)
        reflected[i] = pixel_hit(st, i) && st->zmin_world && isfinite(st->zmin_world[i]) &&
                       isfinite(st->zmax_world[i]) && st->zmax_world[i] >= st->zmin_world[i];
    return run_param_rows(st, c, ic, reflected, st->zmin_world, st->zmax_world, NULL, scene_size_world, indirect_rows,
                          beta_world, spp);
}

int aaf_defocus_params_image(const AafPixelStats *st, const AafDefocusConfig *c, const AafImageConfig *ic,
                             float *beta_px, int *spp)
{
    size_t n = (size_t)st->width * (size_t)st->height;
    int filtered = 0;
    for (size_t i = 0; i < n; ++i) {
        beta_px[i] = 0.0f;
        spp[i] = ic->spp_min;
        if (!st->coc_min_px || !st->coc_max_px) continue;
        float smin = st->coc_min_px[i], smax = st->coc_max_px[i];
        if (!(smin <= smax)) continue; /* no primary hit recorded: nothing to size a filter by */
        beta_px[i] = aaf_defocus_beta_px(smin, smax, c);
        /* Only escaped rays so far, and they see black: the light field is zero wherever pass 1
         * looked, an empty spectrum that needs no further samples (as for the pixels without
         * a surface in the shadow and indirect maps), and nothing to gather either: a width
         * here pulled the neighbours' light into a pixel that none reaches, which around a
         * bright out-of-focus emitter is a halo over the black (bokeh_bright: relMSE 2.1 ->
         * 0.36 at 16 spp; the defocus bench scene's sky unchanged, docs/algorithms.md 3.2). */
        if (c->black_background && !pixel_hit(st, i)) {
            beta_px[i] = 0.0f;
            continue;
        }
        if (beta_px[i] > 0.0f) ++filtered;
        spp[i] = aaf_clamp_spp(aaf_defocus_spp(smin, smax, c), ic->spp_min, ic->spp_cap);
    }
    return filtered;
}
