/* FSF's lens inputs and per-pixel parameters for defocus (fsf_lens.h). */
#include "recon/fsf/fsf_lens.h"

#include <math.h>
#include <stdlib.h>

#include "recon/fsf/fsf_band.h"
#include "recon/fsf/fsf_slope_window.h"
#include "recon/recon_parallel.h"

FsfGrid fsf_lens_grid(void)
{
    FsfGrid g = fsf_grid_default(1.0f, 1.0f);
    g.profile_half[0] = g.profile_half[1] = FSF_LENS_PROFILE_HALF;
    g.reach_sigmas = FSF_REACH_SIGMAS_NARROW;
    return g;
}

float fsf_lens_slope(const ReconCamera *cam, float depth_cam)
{
    float c = recon_coc_slope_px(cam, depth_cam);
    /* in the focal plane (or a pinhole) no neighbour shares a lens ray: the largest slope */
    if (!(fabsf(c) > 1.0f / FSF_LENS_K_MAX)) return FSF_LENS_K_MAX;
    return 1.0f / c;
}

bool fsf_lens_samples(const SampleStore *st, int width, int height, const float *value4, unsigned char *usable,
                      float *y, float *v, int *count, long long *nonfinite)
{
    const float *lens = sample_store_field(st, SAMPLE_FIELD_LENS), *rad = sample_store_field(st, SAMPLE_FIELD_RADIANCE);
    if (!lens || !rad) return false;
    int cap = sample_store_capacity(st);
    size_t n = (size_t)width * (size_t)height;
    for (size_t i = 0; i < n; ++i) {
        int cnt = sample_store_count(st, i);
        count[i] = cnt;
        usable[i] = cnt > 0 && value4[4 * i + 3] > 0.0f;
        float scale[3];
        fsf_match_pixel(value4 + 4 * i, rad + i * (size_t)cap * 3, cnt, scale);
        for (int k = 0; k < cnt; ++k) {
            size_t slot = i * (size_t)cap + (size_t)k;
            fsf_lens_coord(lens[2 * slot], lens[2 * slot + 1], y + 2 * slot);
        }
        *nonfinite += fsf_scale_samples(rad + i * (size_t)cap * 3, cnt, scale, v + i * (size_t)cap * 3);
    }
    return true;
}

typedef struct {
    const FsfLensIn *in;
    FsfSlopeWindows wnd;
    FsfPixel *px;
    float *k_lo, *k_hi;
} Job;

/* sample_slope's context: the store's depth field found once, not per sample */
typedef struct {
    const ReconCamera *cam;
    const float *depth;
} SlopeCtx;

/* A sample's slope (every sample has one: a miss has depth +inf and a finite slope). */
static float sample_slope(const void *ctx, size_t slot)
{
    const SlopeCtx *c = ctx;
    return fsf_lens_slope(c->cam, c->depth[slot]);
}

/* FSF eq. 4 for the unit disk at the pixel's sample count (fsf_lens_sigma_u), in pixels
 * (infinite for one slope). */
typedef struct {
    float mu, sigma_u;
} WidthCtx;
static float sigma_of_spread(const void *ctx, float spread)
{
    const WidthCtx *c = ctx;
    return spread > 0.0f ? c->sigma_u / (spread * c->mu) : INFINITY;
}

static void params_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    const FsfLensIn *in = j->in;
    const float reach_sigmas = fsf_lens_grid().reach_sigmas; /* the lens taps' reach, for the border cap */
    for (size_t i = begin; i < end; ++i) {
        FsfPixel *pp = &j->px[i];
        *pp = fsf_pixel_left_out();
        j->k_lo[i] = j->k_hi[i] = 0.0f;
        if (!in->usable[i]) continue;
        /* Every sample escaped to a black background: the light field is zero wherever this
         * pixel looked, and a filter would only gather its neighbours' light into it, a square
         * halo round a bright defocused emitter over the sky (as AAF's lens, 3.2; its own black
         * samples still reach its neighbours' filters) */
        if (in->black_background && !in->g->hit[i]) continue;
        /* the band narrows the filter as the pixel's samples grow */
        WidthCtx wc = {in->mu, fsf_lens_sigma_u(sample_store_count(in->store, i))};
        FsfSlopePick pick = fsf_slope_pick(&j->wnd, i, sigma_of_spread, &wc);
        if (!(pick.lo <= pick.hi)) continue; /* no samples around: nothing to filter with */
        j->k_lo[i] = pick.lo, j->k_hi[i] = pick.hi;
        float eta, sigma;
        if (fsf_lens_straddles(pick.lo, pick.hi)) {
            /* straddles the focal plane: the axis-aligned fallback (FSF section 5), with the
             * paper's fixed sigma_u = 1/2, not the band: narrower, it left out the straddlers
             * of a moving defocused object, whose motion noise this filter was the only one to
             * average (docs/algorithms.md section 10, "The band of the lens and of the v-plane") */
            eta = 0.0f;
            sigma = FSF_LENS_STRADDLE_SIGMA_U / (fmaxf(-pick.lo, pick.hi) * in->mu);
        } else {
            eta = -0.5f * (pick.lo + pick.hi);
            sigma = sigma_of_spread(&wc, pick.hi - pick.lo);
        }
        /* taps stay inside the image: the density correction (fsf_density) counts every tap
         * of the radius, and a side cut off by the border would shift the aperture the
         * filter sees (a synthetic plane's border pixels had 10x the inside's error). The
         * taps reach the lens grid's 1.5 sigma (fsf_lens_grid), so the cap is edge / 1.5: at
         * edge / 2 (2-sigma taps) the border pixels' taps stopped at 0.75 of the room there */
        int x = (int)(i % (size_t)in->g->width), y = (int)(i / (size_t)in->g->width);
        int edge = x < y ? x : y;
        edge = edge < in->g->width - 1 - x ? edge : in->g->width - 1 - x;
        edge = edge < in->g->height - 1 - y ? edge : in->g->height - 1 - y;
        sigma = fminf(fminf(sigma, pick.cap_px), (float)edge / reach_sigmas);
        /* Left out (its mean kept): a filter that reaches no neighbour, too narrow for its
         * first taps to matter or sheared so far that a neighbour one step away lands off the
         * lens (|eta| > 2: in focus, c < 1/2 px), would only drop the own samples outside the
         * profile square */
        if (sigma < FSF_LENS_SIGMA_MIN_PX || fabsf(eta) > 2.0f) sigma = 0.0f;
        pp->eta_m[0] = pp->eta_m[1] = eta;
        pp->sigma_px[0] = pp->sigma_px[1] = sigma;
    }
}

bool fsf_lens_params(const FsfLensIn *in, FsfPixel *px, float *k_lo, float *k_hi)
{
    if (!sample_store_field(in->store, SAMPLE_FIELD_DEPTH)) return false;
    size_t n = (size_t)in->g->width * (size_t)in->g->height;
    Job j = {0};
    j.in = in, j.px = px, j.k_lo = k_lo, j.k_hi = k_hi;
    /* over every object: a defocused object's samples reach any neighbour */
    SlopeCtx sc = {&in->g->cam, sample_store_field(in->store, SAMPLE_FIELD_DEPTH)};
    bool ok = fsf_slope_windows(in->store, in->g->width, in->g->height, sample_slope, &sc, NULL, &j.wnd);
    if (ok) recon_parallel_for(n, params_range, &j);
    fsf_slope_windows_free(&j.wnd);
    return ok;
}
