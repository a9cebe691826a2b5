/* FSF per-pixel parameters (fsf_params.h). */
#include "recon/fsf/fsf_params.h"

#include <math.h>
#include <stdlib.h>

#include "recon/recon_parallel.h"

typedef struct {
    const FsfParamsIn *in;
    float *own_lo, *own_hi; /* the pixel's own range (+inf, -inf: none) */
    FsfPixel *px;
    float *k_lo, *k_hi;
} Job;

/* The slope range of the pixel's own occluded samples. */
static void own_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    const SampleStore *st = j->in->store;
    const float *lf = sample_store_field(st, SAMPLE_FIELD_LIGHT);
    int cap = sample_store_capacity(st);
    for (size_t i = begin; i < end; ++i) {
        float lo = INFINITY, hi = -INFINITY;
        for (int k = 0; k < sample_store_count(st, i); ++k) {
            const float *s = lf + 5 * (i * (size_t)cap + (size_t)k);
            float d_light = s[3], d_occ = s[4];
            if (!(d_occ > 0.0f && d_occ < d_light && isfinite(d_occ))) continue;
            float k_m = (d_light - d_occ) / d_occ;
            lo = fminf(lo, k_m), hi = fmaxf(hi, k_m);
        }
        j->own_lo[i] = lo, j->own_hi[i] = hi;
    }
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

static void params_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    Job *j = ctx;
    const FsfParamsIn *in = j->in;
    const GBuffer *g = in->g;
    int w = g->width, h = g->height;
    for (size_t i = begin; i < end; ++i) {
        FsfPixel *pp = &j->px[i];
        pp->dir[0][0] = 1.0f, pp->dir[0][1] = 0.0f, pp->dir[1][0] = 0.0f, pp->dir[1][1] = 1.0f;
        pp->eta_m[0] = pp->eta_m[1] = 0.0f;
        pp->sigma_px[0] = pp->sigma_px[1] = 0.0f;
        j->k_lo[i] = j->k_hi[i] = 0.0f;
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        float lo = j->own_lo[i], hi = j->own_hi[i];
        if (!(lo <= hi)) { /* slope smoothing: the window's range */
            for (int qy = y - FSF_BORROW_RADIUS_PX; qy <= y + FSF_BORROW_RADIUS_PX; ++qy)
                for (int qx = x - FSF_BORROW_RADIUS_PX; qx <= x + FSF_BORROW_RADIUS_PX; ++qx) {
                    if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                    size_t q = (size_t)qy * (size_t)w + (size_t)qx;
                    lo = fminf(lo, j->own_lo[q]), hi = fmaxf(hi, j->own_hi[q]);
                }
        }
        if (!in->usable[i]) continue;
        vec3 jx, jy;
        if (!jacobian_column(g, x, y, 0, &jx) || !jacobian_column(g, x, y, 1, &jy)) continue;
        vec3 n = v3(g->nrm4[4 * i], g->nrm4[4 * i + 1], g->nrm4[4 * i + 2]);
        bool known = lo <= hi;
        float k_mean = known ? 0.5f * (lo + hi) : 0.0f, spread = known ? hi - lo : 0.0f;
        if (known) j->k_lo[i] = lo, j->k_hi[i] = hi;
        /* J^T J for the least-squares screen direction of each light axis */
        float a11 = v3_dot(jx, jx), a12 = v3_dot(jx, jy), a22 = v3_dot(jy, jy), det = a11 * a22 - a12 * a12;
        if (!(det > 0.0f)) continue;
        for (int a = 0; a < 2; ++a) {
            vec3 axis = in->light->axis_world[a];
            vec3 ut = v3_madd(axis, n, -v3_dot(axis, n));
            float b1 = v3_dot(jx, ut), b2 = v3_dot(jy, ut);
            float sx = (a22 * b1 - a12 * b2) / det, sy = (a11 * b2 - a12 * b1) / det, len = sqrtf(sx * sx + sy * sy);
            if (!(len > 0.0f)) goto skip;
            sx /= len, sy /= len;
            vec3 D = v3_add(v3_scale(jx, sx), v3_scale(jy, sy)); /* receiver metres per step */
            float step_m = v3_length(D);
            if (!(step_m > 0.0f)) goto skip;
            pp->dir[a][0] = sx, pp->dir[a][1] = sy;
            pp->eta_m[a] = k_mean * v3_dot(D, axis);
            float sigma_px;
            if (!known) {
                sigma_px = FSF_FAR_RADIUS_PX / FSF_RADIUS_SIGMAS;
            } else {
                /* FSF eq. 4 in receiver metres; one slope: no limit but the cap */
                float sigma_m = spread > 0.0f ? 0.5f * in->light->half_m[a] / spread : INFINITY;
                sigma_px = sigma_m / (in->mu * step_m);
            }
            float cap = (float)FSF_RADIUS_CAP_PX / FSF_RADIUS_SIGMAS;
            pp->sigma_px[a] = sigma_px < cap ? sigma_px : cap;
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
    Job j = {in, malloc(n * sizeof(float)), malloc(n * sizeof(float)), px, k_lo, k_hi};
    bool ok = j.own_lo && j.own_hi;
    if (ok) {
        recon_parallel_for(n, own_range, &j);
        recon_parallel_for(n, params_range, &j);
    }
    free(j.own_lo);
    free(j.own_hi);
    return ok;
}
