/* FSF per-pixel parameters (fsf_params.h). */
#include "recon/fsf/fsf_params.h"

#include <math.h>
#include <stdlib.h>

#include "core/vectorise.h"
#include "recon/fsf/fsf_screen_axes.h"
#include "recon/fsf/fsf_slope_window.h"
#include "recon/recon_parallel.h"

typedef struct {
    const FsfParamsIn *in;
    FsfSlopeWindows wnd;
    FsfPixel *px;
    float *k_lo, *k_hi;
    float *axis4;        /* per pixel: receiver metres per step along each light axis (the shear
                          * per unit slope) and the metres of a step (the width's divisor) */
    float *row_lo, *row_hi; /* the footprint's first pass: the range over each pixel's taps along dir[0] */
    FsfGuides gd;        /* the filter's neighbour test */
    float reach_sigmas;  /* the filter's taps (fsf_light_grid) */
    int *sloped_sat;     /* (w + 1) x (h + 1) summed-area table of the pixels with a slope of their
                          * own: a footprint whose bounding square holds none is skipped */
} Job;

float fsf_light_sigma_y_m(float half_m, int samples)
{
    /* the band's edge where the box's spectrum envelope 1 / (W L) meets the threshold
     * e^-2 sqrt(16 / n): Omega_y = e^2 sqrt(n / 16) / L, sigma_y = 2 / Omega_y */
    return 2.0f * fsf_band_threshold(samples) * half_m;
}

/* FSF eq. 4 in pixel steps for a slope spread, before the cap (infinite for one slope). */
static float sigma_steps(const FsfParamsIn *in, int axis, float spread, float step_m, int samples)
{
    float sigma_m = spread > 0.0f ? fsf_light_sigma_y_m(in->light->half_m[axis], samples) / spread : INFINITY;
    return sigma_m / (in->mu * step_m);
}

/* An occluded sample's slope k = (d_light - d_occ) / d_occ; NaN for an unoccluded one. ctx:
 * the store's light field (found once, not per sample). */
static float sample_slope(const void *ctx, size_t slot)
{
    const float *s = (const float *)ctx + 5 * slot;
    float d_light = s[3], d_occ = s[4];
    if (!(d_occ > 0.0f && d_occ < d_light && isfinite(d_occ))) return NAN;
    return (d_light - d_occ) / d_occ;
}

/* The narrower of the two axes' widths for a spread (fsf_slope_pick's measure). */
typedef struct {
    const FsfParamsIn *in;
    float step_m[2];
    int samples;
} StepCtx;
static float sigma_both(const void *ctx, float spread)
{
    const StepCtx *c = ctx;
    return fminf(sigma_steps(c->in, 0, spread, c->step_m[0], c->samples),
                 sigma_steps(c->in, 1, spread, c->step_m[1], c->samples));
}

/* One pixel's parameters from its screen axes (pixel i usable, its Jacobian found). */
static void pixel_params(Job *j, size_t i, const FsfScreenAxes *ax)
{
    const FsfParamsIn *in = j->in;
    FsfPixel *pp = &j->px[i];
    const float *step_m = ax->step_m;
    const vec3 *Dm = ax->step_world; /* receiver metres per step */
    /* The slope range must cover the samples under the whole footprint, not only the
     * pixel's own (a neighbour's samples reprojected with another occluder's shear land
     * on the wrong light point). Each window (radius 2: FSF section 5's 5 x 5 slope
     * smoothing, which also gives unoccluded pixels their neighbours' slopes; then 4, 8,
     * 16) gives a width that is safe up to its radius: the range's width (none in a
     * window without occluders: every sample there is lit), capped so that the taps
     * (2 sigma) stay inside the window. The widest safe one wins, with its range. */
    /* the band narrows the filter as the pixel's samples grow (fsf_light_sigma_y_m) */
    StepCtx sc = {in, {step_m[0], step_m[1]}, sample_store_count(in->store, i)};
    FsfSlopePick pick = fsf_slope_pick(&j->wnd, i, sigma_both, &sc);
    float lo = pick.lo, hi = pick.hi, cap_px = pick.cap_px;
    bool known = lo <= hi;
    float k_mean = known ? 0.5f * (lo + hi) : 0.0f, spread = known ? hi - lo : 0.0f;
    if (known) j->k_lo[i] = lo, j->k_hi[i] = hi;
    float *a4 = j->axis4 + 4 * i;
    for (int a = 0; a < 2; ++a) {
        a4[a] = v3_dot(Dm[a], in->light->axis_world[a]), a4[2 + a] = step_m[a];
        pp->dir[a][0] = ax->dir[a][0], pp->dir[a][1] = ax->dir[a][1];
        pp->eta_m[a] = k_mean * v3_dot(Dm[a], in->light->axis_world[a]);
        /* FSF eq. 4; one slope: no limit but the cap */
        float sigma_px = known ? sigma_steps(in, a, spread, step_m[a], sc.samples) : cap_px;
        pp->sigma_px[a] = sigma_px < cap_px ? sigma_px : cap_px;
    }
}

/* The pixels in blocks: their Jacobians, then the block's screen axes side by side
 * (fsf_screen_axes_block), then each pixel's parameters. */
static void params_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    const FsfParamsIn *in = j->in;
    const GBuffer *g = in->g;
    int w = g->width;
    FsfAxesBlock blk;
    for (size_t i = begin; i < end;) {
        for (blk.count = 0; i < end && blk.count < FSF_AXES_BLOCK; ++i) {
            j->px[i] = fsf_pixel_left_out();
            j->k_lo[i] = j->k_hi[i] = 0.0f;
            vec3 jx, jy;
            if (in->usable[i] && fsf_pixel_jacobian(g, (int)(i % (size_t)w), (int)(i / (size_t)w), &jx, &jy))
                fsf_axes_lane(&blk, i, jx, jy, v3(g->nrm4[4 * i], g->nrm4[4 * i + 1], g->nrm4[4 * i + 2]),
                              in->light->axis_world);
        }
        fsf_screen_axes_block(&blk);
        for (int k = 0; k < blk.count; ++k) {
            if (blk.ok[k]) {
                pixel_params(j, blk.at[k], &blk.out[k]);
                continue;
            }
            FsfPixel *pp = &j->px[blk.at[k]]; /* no axes: passed through */
            pp->sigma_px[0] = pp->sigma_px[1] = 0.0f;
            pp->eta_m[0] = pp->eta_m[1] = 0.0f;
        }
    }
}

/* The footprint's slope range (docs/algorithms.md 10, "FSF's biases on held-out scenes"). The
 * windows are squares joined to the centre by a row then a column on its object; the filter's
 * taps run along the light's screen directions, which may be diagonal, and take any pixel of
 * the centre's plane, also one that another object separates from it on the screen (the ground
 * behind a block). A sample whose slope the range missed is reprojected with no shear or the
 * wrong one (a shadowed one placed on the lit light). So each pixel's range is also taken over
 * the pixels its taps reach as the factored passes gather them: pass 1b's along dir[0] of each
 * intermediate pixel, at its own radius (footprint_rows), then pass 2b's along dir[1]
 * (footprint_cols), both to the shadows' grid's reach (fsf_light_grid: the taps the filter
 * gathers) and through fsf_accept. Where that range is wider than the window's, the pixel's
 * shear and width follow the union: the width only narrows, so the taps stay inside the
 * footprint the range was taken over. */
/* min and max without libm's calls (fminf, fmaxf): the ranges hold no NaN (fsf_slope_window.c) */
static inline float min_f(float a, float b) { return b < a ? b : a; }
static inline float max_f(float a, float b) { return b > a ? b : a; }

static void sloped_table(Job *j)
{
    int w = j->in->g->width, h = j->in->g->height;
    int *S = j->sloped_sat;
    for (int x = 0; x <= w; ++x) S[x] = 0;
    for (int y = 0; y < h; ++y) {
        int run = 0, *row = S + (size_t)(y + 1) * (size_t)(w + 1), *above = row - (w + 1);
        row[0] = 0;
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            run += j->wnd.own_lo[i] <= j->wnd.own_hi[i];
            row[x + 1] = above[x + 1] + run;
        }
    }
}

/* Whether some pixel within r (Chebyshev) of (x, y) has a slope of its own: a tap t steps along
 * a unit direction lands within |t| of its pixel on either axis. */
static inline bool sloped_near(const Job *j, int x, int y, int r)
{
    int w = j->in->g->width, h = j->in->g->height;
    int x0 = x - r < 0 ? 0 : x - r, y0 = y - r < 0 ? 0 : y - r;
    int x1 = x + r >= w ? w - 1 : x + r, y1 = y + r >= h ? h - 1 : y + r;
    const int *S = j->sloped_sat;
    size_t W1 = (size_t)w + 1;
    int sum = S[(size_t)(y1 + 1) * W1 + (size_t)(x1 + 1)] - S[(size_t)y0 * W1 + (size_t)(x1 + 1)] -
              S[(size_t)(y1 + 1) * W1 + (size_t)x0] + S[(size_t)y0 * W1 + (size_t)x0];
    return sum > 0;
}

static WEDGE_VECTORISED void footprint_rows(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    int w = j->in->g->width, h = j->in->g->height;
    for (size_t i = begin; i < end; ++i) {
        float lo = INFINITY, hi = -INFINITY;
        const FsfPixel *pp = &j->px[i];
        int r = j->in->usable[i] ? fsf_radius_reach(pp->sigma_px[0], j->reach_sigmas) : -1;
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        if (r >= 0 && !sloped_near(j, x, y, r)) r = -1; /* no slope in reach: the empty range */
        for (int t = -r; t <= r; ++t) {
            int q = fsf_step_pixel(w, h, x, y, pp->dir[0], (float)t);
            if (q < 0) continue;
            /* a tap without a slope of its own (the empty range INFINITY, -INFINITY) leaves the
             * range as it is whether accepted or not: the guides' test only for the others */
            float q_lo = j->wnd.own_lo[q], q_hi = j->wnd.own_hi[q];
            if (!(q_lo <= q_hi) || !fsf_accept(&j->gd, (int)i, q)) continue;
            lo = min_f(lo, q_lo), hi = max_f(hi, q_hi);
        }
        j->row_lo[i] = lo, j->row_hi[i] = hi;
    }
}

static WEDGE_VECTORISED void footprint_cols(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    const FsfParamsIn *in = j->in;
    int w = in->g->width, h = in->g->height;
    for (size_t i = begin; i < end; ++i) {
        FsfPixel *pp = &j->px[i];
        if (!in->usable[i] || !(pp->sigma_px[0] > 0.0f || pp->sigma_px[1] > 0.0f)) continue;
        int r = fsf_radius_reach(pp->sigma_px[1], j->reach_sigmas);
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        /* the rows' taps reach at most FSF_RADIUS_CAP_PX further */
        if (!sloped_near(j, x, y, r + FSF_RADIUS_CAP_PX)) continue;
        float lo = INFINITY, hi = -INFINITY;
        for (int t = -r; t <= r; ++t) {
            int q = fsf_step_pixel(w, h, x, y, pp->dir[1], (float)t);
            if (q < 0) continue;
            float q_lo = j->row_lo[q], q_hi = j->row_hi[q]; /* empty: as in footprint_rows */
            if (!(q_lo <= q_hi) || !fsf_accept(&j->gd, (int)i, q)) continue;
            lo = min_f(lo, q_lo), hi = max_f(hi, q_hi);
        }
        if (!(lo <= hi)) continue; /* every sample reached is lit */
        /* slopes are positive (d_occ < d_light): k_lo = k_hi = 0 is the window without any */
        bool window_had = !(j->k_lo[i] == 0.0f && j->k_hi[i] == 0.0f);
        if (window_had && lo >= j->k_lo[i] && hi <= j->k_hi[i]) continue; /* the window held them */
        if (window_had) lo = fminf(lo, j->k_lo[i]), hi = fmaxf(hi, j->k_hi[i]);
        j->k_lo[i] = lo, j->k_hi[i] = hi;
        const float *a4 = j->axis4 + 4 * i;
        int samples = sample_store_count(in->store, i);
        for (int a = 0; a < 2; ++a) {
            pp->eta_m[a] = 0.5f * (lo + hi) * a4[a];
            float sigma_px = sigma_steps(in, a, hi - lo, a4[2 + a], samples);
            pp->sigma_px[a] = sigma_px < pp->sigma_px[a] ? sigma_px : pp->sigma_px[a];
        }
    }
}

bool fsf_shadow_windows(const GBuffer *g, const SampleStore *st, FsfSlopeWindows *out)
{
    /* only the centre's object: the filter takes light from no other surface */
    return fsf_slope_windows_per_object(st, g, sample_slope, sample_store_field(st, SAMPLE_FIELD_LIGHT), out);
}

bool fsf_pixel_params(const FsfParamsIn *in, FsfPixel *px, float *k_lo, float *k_hi)
{
    size_t n = (size_t)in->g->width * (size_t)in->g->height;
    Job j = {0};
    j.in = in, j.px = px, j.k_lo = k_lo, j.k_hi = k_hi;
    bool ok = true;
    if (in->windows) j.wnd = *in->windows;
    else ok = fsf_shadow_windows(in->g, in->store, &j.wnd);
    float *scratch = ok ? malloc(sizeof(float) * n * 6) : NULL;
    int *sat = ok ? malloc(sizeof(int) * ((size_t)in->g->width + 1) * ((size_t)in->g->height + 1)) : NULL;
    ok = ok && scratch && sat;
    if (ok) {
        j.axis4 = scratch, j.row_lo = scratch + 4 * n, j.row_hi = scratch + 5 * n, j.sloped_sat = sat;
        sloped_table(&j);
        j.gd = fsf_guides_default(in->g->pos4, in->g->nrm4, in->usable);
        j.reach_sigmas = fsf_light_grid(in->light).reach_sigmas;
        recon_parallel_for(n, params_range, &j);
        recon_parallel_for(n, footprint_rows, &j);
        recon_parallel_for(n, footprint_cols, &j);
    }
    free(scratch);
    free(sat);
    if (!in->windows) fsf_slope_windows_free(&j.wnd);
    return ok;
}
