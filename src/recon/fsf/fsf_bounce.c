/* FSF's v-plane coordinates, slopes and per-pixel parameters for indirect light (fsf_bounce.h). */
#include "recon/fsf/fsf_bounce.h"

#include <math.h>
#include <stdlib.h>

#include "recon/fsf/fsf_band.h"
#include "recon/fsf/fsf_screen_axes.h"
#include "recon/fsf/fsf_slope_window.h"
#include "recon/recon_parallel.h"

bool fsf_bounce_frame(vec3 jx, vec3 n, FsfBounceFrame *f)
{
    vec3 t1 = v3_madd(jx, n, -v3_dot(jx, n));
    float len = v3_length(t1);
    /* a Jacobian column along the normal: a surface seen edge-on */
    if (!(len > 1e-6f * v3_length(jx))) return false;
    f->t[0] = v3_scale(t1, 1.0f / len);
    f->t[1] = v3_cross(n, f->t[0]);
    f->n = n;
    return true;
}

static float clamp_rim(float v)
{
    return v > FSF_BOUNCE_V_RIM ? FSF_BOUNCE_V_RIM : v < -FSF_BOUNCE_V_RIM ? -FSF_BOUNCE_V_RIM : v;
}

void fsf_bounce_coord(const FsfBounceFrame *f, vec3 d, float v[2])
{
    float dn = v3_dot(d, f->n), d1 = v3_dot(d, f->t[0]), d2 = v3_dot(d, f->t[1]);
    if (!(dn > 0.0f)) { /* no direction (0), or at or below the tangent plane: the rim */
        float m = fmaxf(fabsf(d1), fabsf(d2));
        v[0] = m > 0.0f ? clamp_rim(FSF_BOUNCE_V_RIM * d1 / m) : 0.0f;
        v[1] = m > 0.0f ? clamp_rim(FSF_BOUNCE_V_RIM * d2 / m) : 0.0f;
        return;
    }
    v[0] = clamp_rim(d1 / dn), v[1] = clamp_rim(d2 / dn); /* clamp_rim(inf) is finite */
}

float fsf_bounce_slope(vec3 n, vec3 d, float t_hit_m)
{
    float dn = v3_dot(d, n);
    if (!(dn > 0.0f) || !(t_hit_m > 0.0f)) return NAN;
    if (isinf(t_hit_m)) return 0.0f; /* a miss: the environment at infinity, no parallax */
    return 1.0f / (t_hit_m * dn);
}

float fsf_bounce_reach_sq(int samples) { return 1.0f / fsf_band_threshold(samples) - 1.0f; }

FsfGrid fsf_bounce_grid(void)
{
    return fsf_grid_nodes(FSF_BOUNCE_V_HALF, FSF_BOUNCE_V_HALF, FSF_BOUNCE_SHIFT_NODES);
}

/* Pixel i's frame from its guides, and the screen Jacobian it was built from. */
static bool pixel_frame(const GBuffer *g, size_t i, FsfBounceFrame *f, vec3 *jx, vec3 *jy)
{
    int x = (int)(i % (size_t)g->width), y = (int)(i / (size_t)g->width);
    if (!g->hit[i] || !fsf_pixel_jacobian(g, x, y, jx, jy)) return false;
    return fsf_bounce_frame(*jx, v3(g->nrm4[4 * i], g->nrm4[4 * i + 1], g->nrm4[4 * i + 2]), f);
}

bool fsf_bounce_coords(const GBuffer *g, const SampleStore *st, const float *value4, unsigned char *usable, float *y,
                       int *count)
{
    const float *bounce = sample_store_field(st, SAMPLE_FIELD_BOUNCE);
    if (!bounce) return false;
    int cap = sample_store_capacity(st);
    size_t n = (size_t)g->width * (size_t)g->height;
    for (size_t i = 0; i < n; ++i) {
        int cnt = sample_store_count(st, i);
        count[i] = cnt;
        FsfBounceFrame f;
        vec3 jx, jy;
        bool framed = pixel_frame(g, i, &f, &jx, &jy);
        usable[i] = framed && cnt > 0 && !g->mixed[i] && (!value4 || value4[4 * i + 3] > 0.0f);
        for (int k = 0; y && k < cnt; ++k) {
            size_t slot = i * (size_t)cap + (size_t)k;
            const float *b = bounce + 4 * slot;
            if (framed) fsf_bounce_coord(&f, v3(b[0], b[1], b[2]), y + 2 * slot);
            else y[2 * slot] = y[2 * slot + 1] = 0.0f;
        }
    }
    return true;
}

/* sample_slope's context: the bounce field, the samples' v and the pixels' normals, found once;
 * the reach per sample count. */
typedef struct {
    const float *bounce, *y, *nrm4;
    size_t cap;
    float k_max;
    const SampleStore *store;
    const float *reach_sq; /* fsf_bounce_reach_sq per count, 0 .. cap */
} SlopeCtx;

static float sample_slope(const void *ctx, size_t slot)
{
    const SlopeCtx *c = ctx;
    size_t pixel = slot / c->cap;
    const float *b = c->bounce + 4 * slot, *nr = c->nrm4 + 4 * pixel, *y = c->y + 2 * slot;
    if (!(fabsf(y[0]) < FSF_BOUNCE_V_RIM && fabsf(y[1]) < FSF_BOUNCE_V_RIM)) return NAN; /* on the rim */
    /* beyond the reach: light below the band's threshold (fsf_bounce_reach_sq) */
    if (y[0] * y[0] + y[1] * y[1] > c->reach_sq[sample_store_count(c->store, pixel)]) return NAN;
    float k = fsf_bounce_slope(v3(nr[0], nr[1], nr[2]), v3(b[0], b[1], b[2]), b[3]);
    return k > c->k_max ? c->k_max : k; /* NaN stays NaN */
}

typedef struct {
    const FsfBounceIn *in;
    FsfSlopeWindows wnd;
    FsfPixel *px;
    float *k_lo, *k_hi;
    const float *sigma_v; /* fsf_bounce_sigma_v per sample count, 0 .. the store's capacity */
} Job;

/* FSF eq. 4 in pixel steps for a slope spread (infinite for one slope). */
static float sigma_steps(float mu, float sigma_v, float spread, float step_m)
{
    float sigma_m = spread > 0.0f ? sigma_v / spread : INFINITY;
    return sigma_m / (mu * step_m);
}

typedef struct {
    float mu, sigma_v, step_m[2];
} StepCtx;
static float sigma_both(const void *ctx, float spread)
{
    const StepCtx *c = ctx;
    return fminf(sigma_steps(c->mu, c->sigma_v, spread, c->step_m[0]),
                 sigma_steps(c->mu, c->sigma_v, spread, c->step_m[1]));
}

/* One pixel's parameters from its frame f and screen axes ax. */
static void pixel_params(Job *j, size_t i, const FsfBounceFrame *f, const FsfScreenAxes *ax)
{
    const FsfBounceIn *in = j->in;
    FsfPixel *pp = &j->px[i];
    /* the band narrows the filter as the pixel's samples grow */
    StepCtx sc = {in->mu, j->sigma_v[sample_store_count(in->store, i)], {ax->step_m[0], ax->step_m[1]}};
    FsfSlopePick pick = fsf_slope_pick(&j->wnd, i, sigma_both, &sc);
    bool known = pick.lo <= pick.hi;
    float k_mean = known ? 0.5f * (pick.lo + pick.hi) : 0.0f, spread = known ? pick.hi - pick.lo : 0.0f;
    if (known) j->k_lo[i] = pick.lo, j->k_hi[i] = pick.hi;
    for (int a = 0; a < 2; ++a) {
        pp->dir[a][0] = ax->dir[a][0], pp->dir[a][1] = ax->dir[a][1];
        /* fsf_filter.h: seen from x, the neighbour t steps away has v' + eta t */
        pp->eta_m[a] = k_mean * v3_dot(ax->step_world[a], f->t[a]);
        float sigma_px = known ? sigma_steps(in->mu, sc.sigma_v, spread, ax->step_m[a]) : pick.cap_px;
        /* the parallax bound: taps (2 sigma) move the nearest hits by at most parallax_v */
        if (known && pick.hi > 0.0f)
            sigma_px = fminf(sigma_px, in->parallax_v / (FSF_RADIUS_SIGMAS * pick.hi * ax->step_m[a]));
        pp->sigma_px[a] = sigma_px < pick.cap_px ? sigma_px : pick.cap_px;
    }
}

/* The pixels in blocks: their frames, then the block's screen axes side by side
 * (fsf_screen_axes_block), then each pixel's parameters (none where it has no axes). */
static void params_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    const FsfBounceIn *in = j->in;
    FsfAxesBlock blk;
    FsfBounceFrame f[FSF_AXES_BLOCK]; /* lane k's */
    for (size_t i = begin; i < end;) {
        for (blk.count = 0; i < end && blk.count < FSF_AXES_BLOCK; ++i) {
            j->px[i] = fsf_pixel_left_out();
            j->k_lo[i] = j->k_hi[i] = 0.0f;
            vec3 jx, jy;
            if (in->usable[i] && pixel_frame(in->g, i, &f[blk.count], &jx, &jy))
                fsf_axes_lane(&blk, i, jx, jy, f[blk.count].n, f[blk.count].t);
        }
        fsf_screen_axes_block(&blk);
        for (int k = 0; k < blk.count; ++k)
            if (blk.ok[k]) pixel_params(j, blk.at[k], &f[k], &blk.out[k]);
    }
}

bool fsf_bounce_params(const FsfBounceIn *in, FsfPixel *px, float *k_lo, float *k_hi)
{
    const float *bounce = sample_store_field(in->store, SAMPLE_FIELD_BOUNCE);
    if (!bounce) return false;
    size_t n = (size_t)in->g->width * (size_t)in->g->height;
    Job j = {0};
    j.in = in, j.px = px, j.k_lo = k_lo, j.k_hi = k_hi;
    float h_floor_m = in->h_min_frac * in->g->scene_size_world;
    /* the band and the reach per sample count, found once (a root of W K1(W) each) */
    size_t cap = (size_t)sample_store_capacity(in->store);
    float *sigma_v = cap > 0 ? malloc((cap + 1) * sizeof *sigma_v) : NULL;
    float *reach_sq = cap > 0 ? malloc((cap + 1) * sizeof *reach_sq) : NULL;
    for (size_t c = 0; sigma_v && reach_sq && c <= cap; ++c)
        sigma_v[c] = fsf_bounce_sigma_v((int)c), reach_sq[c] = fsf_bounce_reach_sq((int)c);
    SlopeCtx sc = {bounce, in->y, in->g->nrm4, cap, h_floor_m > 0.0f ? 1.0f / h_floor_m : INFINITY, in->store, reach_sq};
    j.sigma_v = sigma_v;
    /* only the centre's object: the filter takes light from no other surface */
    bool ok = sigma_v && reach_sq && fsf_slope_windows_per_object(in->store, in->g, sample_slope, &sc, &j.wnd);
    if (ok) recon_parallel_for(n, params_range, &j);
    fsf_slope_windows_free(&j.wnd);
    free(sigma_v);
    free(reach_sq);
    return ok;
}
