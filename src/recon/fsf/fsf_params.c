/* FSF per-pixel parameters (fsf_params.h). */
#include "recon/fsf/fsf_params.h"

#include <math.h>
#include <stdlib.h>

#include "recon/fsf/fsf_slope_window.h"
#include "recon/recon_parallel.h"

typedef struct {
    const FsfParamsIn *in;
    FsfSlopeWindows wnd;
    FsfPixel *px;
    float *k_lo, *k_hi;
} Job;

/* FSF eq. 4 in pixel steps for a slope spread, before the cap (infinite for one slope). */
static float sigma_steps(const FsfParamsIn *in, int axis, float spread, float step_m)
{
    float sigma_m = spread > 0.0f ? 0.5f * in->light->half_m[axis] / spread : INFINITY;
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

/* A surface neighbour for the Jacobian: hit, not mixed, facing the same way. */
static bool same_surface(const GBuffer *g, size_t i, size_t q)
{
    if (!g->hit[q] || g->mixed[q]) return false;
    const float *a = g->nrm4 + 4 * i, *b = g->nrm4 + 4 * q;
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0.9f;
}

/* dP per pixel step along screen x (axis 0) or y (axis 1): central, else one-sided. */
static bool jacobian_column(const GBuffer *g, int x, int y, int axis, vec3 *out)
{
    int w = g->width, h = g->height;
    size_t i = (size_t)y * (size_t)w + (size_t)x;
    int dx = axis == 0, dy = axis == 1;
    bool has_p = x + dx < w && y + dy < h && same_surface(g, i, i + (size_t)(dx + dy * w));
    bool has_m = x - dx >= 0 && y - dy >= 0 && same_surface(g, i, i - (size_t)(dx + dy * w));
    const float *c = g->pos4 + 4 * i;
    const float *p = has_p ? g->pos4 + 4 * (i + (size_t)(dx + dy * w)) : c;
    const float *m = has_m ? g->pos4 + 4 * (i - (size_t)(dx + dy * w)) : c;
    if (!has_p && !has_m) return false;
    float scale = has_p && has_m ? 0.5f : 1.0f;
    *out = v3((p[0] - m[0]) * scale, (p[1] - m[1]) * scale, (p[2] - m[2]) * scale);
    return true;
}

/* The narrower of the two axes' widths for a spread (fsf_slope_pick's measure). */
typedef struct {
    const FsfParamsIn *in;
    float step_m[2];
} StepCtx;
static float sigma_both(const void *ctx, float spread)
{
    const StepCtx *c = ctx;
    return fminf(sigma_steps(c->in, 0, spread, c->step_m[0]), sigma_steps(c->in, 1, spread, c->step_m[1]));
}

static void params_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    const FsfParamsIn *in = j->in;
    const GBuffer *g = in->g;
    int w = g->width;
    for (size_t i = begin; i < end; ++i) {
        FsfPixel *pp = &j->px[i];
        *pp = fsf_pixel_left_out();
        j->k_lo[i] = j->k_hi[i] = 0.0f;
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        if (!in->usable[i]) continue;
        vec3 jx, jy;
        if (!jacobian_column(g, x, y, 0, &jx) || !jacobian_column(g, x, y, 1, &jy)) continue;
        vec3 n = v3(g->nrm4[4 * i], g->nrm4[4 * i + 1], g->nrm4[4 * i + 2]);
        /* J^T J for the least-squares screen direction of each light axis */
        float a11 = v3_dot(jx, jx), a12 = v3_dot(jx, jy), a22 = v3_dot(jy, jy), det = a11 * a22 - a12 * a12;
        if (!(det > 0.0f)) continue;
        float step_m[2];
        vec3 Dm[2];
        float dir[2][2];
        for (int a = 0; a < 2; ++a) {
            vec3 axis = in->light->axis_world[a];
            vec3 ut = v3_madd(axis, n, -v3_dot(axis, n));
            float b1 = v3_dot(jx, ut), b2 = v3_dot(jy, ut);
            float sx = (a22 * b1 - a12 * b2) / det, sy = (a11 * b2 - a12 * b1) / det, len = sqrtf(sx * sx + sy * sy);
            if (!(len > 0.0f)) goto skip;
            sx /= len, sy /= len;
            Dm[a] = v3_add(v3_scale(jx, sx), v3_scale(jy, sy)); /* receiver metres per step */
            step_m[a] = v3_length(Dm[a]);
            if (!(step_m[a] > 0.0f)) goto skip;
            dir[a][0] = sx, dir[a][1] = sy;
        }
        /* The slope range must cover the samples under the whole footprint, not only the
         * pixel's own (a neighbour's samples reprojected with another occluder's shear land
         * on the wrong light point). Each window (radius 2: FSF section 5's 5 x 5 slope
         * smoothing, which also gives unoccluded pixels their neighbours' slopes; then 4, 8,
         * 16) gives a width that is safe up to its radius: the range's width (none in a
         * window without occluders: every sample there is lit), capped so that the taps
         * (2 sigma) stay inside the window. The widest safe one wins, with its range. */
        StepCtx sc = {in, {step_m[0], step_m[1]}};
        FsfSlopePick pick = fsf_slope_pick(&j->wnd, i, sigma_both, &sc);
        float lo = pick.lo, hi = pick.hi, cap_px = pick.cap_px;
        bool known = lo <= hi;
        float k_mean = known ? 0.5f * (lo + hi) : 0.0f, spread = known ? hi - lo : 0.0f;
        if (known) j->k_lo[i] = lo, j->k_hi[i] = hi;
        for (int a = 0; a < 2; ++a) {
            pp->dir[a][0] = dir[a][0], pp->dir[a][1] = dir[a][1];
            pp->eta_m[a] = k_mean * v3_dot(Dm[a], in->light->axis_world[a]);
            /* FSF eq. 4; one slope: no limit but the cap */
            float sigma_px = known ? sigma_steps(in, a, spread, step_m[a]) : cap_px;
            pp->sigma_px[a] = sigma_px < cap_px ? sigma_px : cap_px;
        }
        continue;
    skip:
        pp->sigma_px[0] = pp->sigma_px[1] = 0.0f;
        pp->eta_m[0] = pp->eta_m[1] = 0.0f;
    }
}

bool fsf_pixel_params(const FsfParamsIn *in, FsfPixel *px, float *k_lo, float *k_hi)
{
    size_t n = (size_t)in->g->width * (size_t)in->g->height;
    Job j = {0};
    j.in = in, j.px = px, j.k_lo = k_lo, j.k_hi = k_hi;
    float *obj = malloc(sizeof(float) * n); /* object id per pixel (gbuffer nrm4[3]) */
    bool ok = obj != NULL;
    if (ok) {
        for (size_t i = 0; i < n; ++i) obj[i] = in->g->nrm4[4 * i + 3];
        /* only the centre's object: the filter takes light from no other surface */
        ok = fsf_slope_windows(in->store, in->g->width, in->g->height, sample_slope,
                               sample_store_field(in->store, SAMPLE_FIELD_LIGHT), obj, &j.wnd);
        if (ok) recon_parallel_for(n, params_range, &j);
        fsf_slope_windows_free(&j.wnd);
    }
    free(obj);
    return ok;
}
