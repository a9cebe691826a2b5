/* FSF on the host: the brute-force oracle and the factored four-pass filter (fsf_filter.h). */
#include "recon/fsf/fsf_filter.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vectorise.h"
#include "recon/recon_parallel.h"

FsfGrid fsf_grid_default(float half_u_m, float half_v_m)
{
    /* FSF section 5: 16 bins (about 4 l for l = 4 samples along an axis). With 8 the
     * single-occluder test scene (recon_test_util.h, 128x128) had 1.6x the error (1.59e-4
     * against 1.01e-4); the soft-shadow bench scene did not tell them apart (4.1e-4, 4.3e-4)
     * and 8 takes 0.65 of the device time. The filters of the bench scenes take their own
     * counts (fsf_light_grid, fsf_bounce_grid; docs/algorithms.md section 10, "Coarser shift
     * grids") */
    return fsf_grid_nodes(half_u_m, half_v_m, 17);
}

FsfGrid fsf_grid_nodes(float half_u_m, float half_v_m, int shift_nodes)
{
    FsfGrid g;
    g.half_m[0] = half_u_m;
    g.half_m[1] = half_v_m;
    g.profile_half[0] = half_u_m;
    g.profile_half[1] = half_v_m;
    g.shift_nodes = shift_nodes;
    g.reach_sigmas = FSF_RADIUS_SIGMAS;
    g.y2_bins = g.shift_nodes - 1;
    g.ramp_m[0] = g.ramp_m[1] = 0.0f;
    return g;
}

FsfGuides fsf_guides_unguided(const unsigned char *usable) { return fsf_guides_default(NULL, NULL, usable); }

FsfGuides fsf_guides_default(const float *pos4, const float *nrm4, const unsigned char *usable)
{
    FsfGuides gd;
    gd.pos4 = pos4;
    gd.nrm4 = nrm4;
    gd.usable = usable;
    gd.cos_normal_min = FSF_NEIGHBOUR_COS_MIN;
    gd.plane_tol_rel = 0.05f;
    gd.geo = NULL;
    return gd;
}

int fsf_radius_reach(float sigma_px, float reach_sigmas)
{
    if (!(sigma_px > 0.0f)) return 0;
    float r = ceilf(reach_sigmas * sigma_px);
    return r < (float)FSF_RADIUS_CAP_PX ? (int)r : FSF_RADIUS_CAP_PX;
}

int fsf_tap_radius(const FsfGrid *g, float sigma_px) { return fsf_radius_reach(sigma_px, g->reach_sigmas); }

int fsf_y2_bin(const FsfGrid *g, float y2_m)
{
    float f = (y2_m + g->half_m[1]) / (2.0f * g->half_m[1]) * (float)g->y2_bins;
    int b = (int)floorf(f);
    return b < 0 ? 0 : b >= g->y2_bins ? g->y2_bins - 1 : b;
}

bool fsf_sample_on_light(const float y_m[2], const float half_m[2])
{
    /* the light point's projection on the light's axes rounds a little past the edge */
    return fabsf(y_m[0]) <= half_m[0] * (1.0f + FSF_ON_LIGHT_SLACK) &&
           fabsf(y_m[1]) <= half_m[1] * (1.0f + FSF_ON_LIGHT_SLACK);
}

/* The factors over the samples on the light (y_m, half_m), or over every sample when y_m is
 * NULL or none is on it: both sums in one pass. */
static void match_pixel_over(const float *value4, const float *sample_rgb, const float *y_m, const float *half_m,
                             int count, float scale[3])
{
    double all[3] = {0, 0, 0}, on[3] = {0, 0, 0};
    int on_count = 0;
    for (int k = 0; k < count; ++k) {
        bool on_light = y_m && fsf_sample_on_light(y_m + 2 * (size_t)k, half_m);
        on_count += on_light;
        for (int ch = 0; ch < 3; ++ch) {
            double c = sample_rgb[3 * (size_t)k + (size_t)ch];
            all[ch] += c;
            if (on_light) on[ch] += c;
        }
    }
    const double *sum = on_count > 0 ? on : all;
    int taken = on_count > 0 ? on_count : count;
    for (int ch = 0; ch < 3; ++ch) {
        double s = sum[ch] > 0.0 ? value4[ch] * (double)taken / sum[ch] : 0.0;
        scale[ch] = isfinite(s) ? (float)s : 0.0f;
    }
}

void fsf_match_pixel(const float *value4, const float *sample_rgb, int count, float scale[3])
{
    match_pixel_over(value4, sample_rgb, NULL, NULL, count, scale);
}

void fsf_match_pixel_on_light(const float *value4, const float *sample_rgb, const float *y_m, const float half_m[2],
                              int count, float scale[3])
{
    match_pixel_over(value4, sample_rgb, y_m, half_m, count, scale);
}

void fsf_fill_dark_channels(const float *value4, const float *sample_rgb, int count, float *out)
{
    for (int ch = 0; ch < 3; ++ch) {
        double sum = 0.0;
        for (int k = 0; k < count; ++k) sum += sample_rgb[3 * (size_t)k + (size_t)ch];
        float v = value4[ch];
        if (sum > 0.0 || !(v > 0.0f) || !isfinite(v)) continue; /* the scale carried it, or nothing to carry */
        for (int k = 0; k < count; ++k) out[3 * (size_t)k + (size_t)ch] = v;
    }
}

/* A sample's channels side by side and quiet compares (isless: false for NaN, as isfinite),
 * no branch: gcc vectorises it (e % 3 per element did not; 6 ns a sample before) */
WEDGE_VECTORISED long long fsf_scale_samples(const float *restrict sample_rgb, int count, const float scale[3],
                                             float *restrict out)
{
    long long nonfinite = 0;
    float s0 = scale[0], s1 = scale[1], s2 = scale[2];
    for (int k = 0; k < count; ++k) {
        const float *in = sample_rgb + 3 * (size_t)k;
        float v0 = in[0] * s0, v1 = in[1] * s1, v2 = in[2] * s2;
        bool f0 = isless(fabsf(v0), INFINITY), f1 = isless(fabsf(v1), INFINITY), f2 = isless(fabsf(v2), INFINITY);
        nonfinite += !f0 + !f1 + !f2;
        out[3 * (size_t)k] = f0 ? v0 : 0.0f, out[3 * (size_t)k + 1] = f1 ? v1 : 0.0f, out[3 * (size_t)k + 2] = f2 ? v2 : 0.0f;
    }
    return nonfinite;
}

/* Spacing of the shift grid along axis a: shift_nodes nodes over [-2 L, 2 L] (beyond 2 L the
 * box I(y - Y) misses every sample on the light). */
static float node_step(const FsfGrid *g, int a) { return 4.0f * g->half_m[a] / (float)(g->shift_nodes - 1); }

/* The box profile along axis a (the uniform light; the lens' equal-variance square). */
static inline float box(const FsfGrid *g, int a, float y) { return fabsf(y) <= g->profile_half[a] ? 1.0f : 0.0f; }

static inline float gauss(float t, float sigma) { return sigma > 0.0f ? expf(-0.5f * t * t / (sigma * sigma)) : 1.0f; }

void fsf_tap_prefix(float sigma_px, int r, float *cum)
{
    cum[0] = 0.0f;
    for (int t = -r; t <= r; ++t) cum[t + r + 1] = cum[t + r] + gauss((float)t, sigma_px);
}

void fsf_tap_prefix_mean(const FsfGrid *g, const FsfPixel *p, float *cum)
{
    int r = fsf_tap_radius(g, p->sigma_px[0]);
    fsf_tap_prefix(p->sigma_px[0], r, cum);
    float inv_mean = 1.0f / fsf_density_mean(g, 0, p->eta_m[0], p->sigma_px[0]);
    for (int e = 0; e < 2 * r + 2; ++e) cum[e] *= inv_mean;
}

float fsf_density(float z_m, float eta_m, float half_m, int r, const float *cum)
{
    /* the taps t with |z - eta t| <= L, a run of integers */
    float lo = -(float)r, hi = (float)r;
    if (eta_m != 0.0f) {
        float inv_eta = 1.0f / eta_m; /* the kernels' products (fsf_density8): the same floats */
        float a = (z_m - half_m) * inv_eta, b = (z_m + half_m) * inv_eta;
        lo = fmaxf(lo, ceilf(fminf(a, b))), hi = fminf(hi, floorf(fmaxf(a, b)));
    } else if (!(fabsf(z_m) <= half_m)) {
        return 0.0f;
    }
    if (hi < lo) return 0.0f;
    return cum[(int)hi + r + 1] - cum[(int)lo + r];
}

float fsf_swept_profile(float z_m, float half_m, float ramp_m)
{
    float t = (half_m - fabsf(z_m)) / ramp_m;
    return t >= 1.0f ? 1.0f : t > 0.0f ? t : 0.0f;
}

float fsf_density_swept(float z_m, float eta_m, float half_m, float ramp_m, int r, const float *cum)
{
    /* every tap: T is not constant over the run where it is positive (its ramps) */
    float sum = 0.0f;
    for (int t = -r; t <= r; ++t) {
        float w = cum[t + r + 1] - cum[t + r];
        sum += w * fsf_swept_profile(z_m - eta_m * (float)t, half_m, ramp_m);
    }
    return sum;
}

float fsf_swept_weight(float z_m, float eta_m, float half_m, float ramp_m, int r, const float *cum)
{
    float prof = fsf_swept_profile(z_m, half_m, ramp_m);
    if (!(prof > 0.0f)) return 0.0f;
    float rho = fsf_density_swept(z_m, eta_m, half_m, ramp_m, r, cum);
    return rho > 0.0f ? prof / rho : 0.0f;
}

float fsf_density_mean(const FsfGrid *g, int axis, float eta_m, float sigma_px)
{
    /* the mean over |z| <= h of rho(z) = sum_t w(t) [|z - eta t| <= L]: each tap's weight times
     * the share of the box its interval [eta t - L, eta t + L] covers */
    int r = fsf_tap_radius(g, sigma_px);
    float h = g->profile_half[axis], L = g->half_m[axis], sum = 0.0f;
    for (int t = -r; t <= r; ++t) {
        float c = eta_m * (float)t, lo = fmaxf(-h, c - L), hi = fminf(h, c + L);
        if (hi > lo) sum += gauss((float)t, sigma_px) * (hi - lo);
    }
    return sum / (2.0f * h);
}

/* ---- the oracle ---- */

typedef struct {
    const FsfSamples *s;
    const FsfGrid *g;
    const FsfPixel *px;
    const FsfGuides *gd;
    float *out4, *P, *G, *Q;
    FsfTap *taps;
    float *cum1;
    int bin, axis;
} Job;

/* The oracle's density along axis a: fsf_density for a box profile; for a swept light its
 * density over its profile (the sample's weight is their inverse: T(z) / rho(z)), 0 where the
 * profile is 0. */
static float swept_over_rho(const FsfGrid *g, int a, float z, float eta, int r, const float *cum)
{
    if (!(g->ramp_m[a] > 0.0f)) return fsf_density(z, eta, g->half_m[a], r, cum);
    float w = fsf_swept_weight(z, eta, g->half_m[a], g->ramp_m[a], r, cum);
    return w > 0.0f ? 1.0f / w : 0.0f;
}

static void add_own(const FsfSamples *s, size_t i, float acc[4])
{
    for (int k = 0; k < s->count[i]; ++k) {
        const float *v = s->value + 3 * (i * (size_t)s->capacity + (size_t)k);
        acc[0] += v[0], acc[1] += v[1], acc[2] += v[2], acc[3] += 1.0f;
    }
}

static void brute_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const Job *j = ctx;
    const FsfSamples *s = j->s;
    int w = s->width, h = s->height;
    for (size_t i = begin; i < end; ++i) {
        float acc[4] = {0, 0, 0, 0};
        const FsfPixel *pp = &j->px[i];
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        if (!j->gd->usable[i]) { /* nobody's neighbour, its result unused: 0 (fsf_filter.h) */
            memcpy(j->out4 + 4 * i, acc, sizeof acc);
            continue;
        }
        if (!(pp->sigma_px[0] > 0.0f || pp->sigma_px[1] > 0.0f)) {
            add_own(s, i, acc);
            memcpy(j->out4 + 4 * i, acc, sizeof acc);
            continue;
        }
        int r1 = fsf_tap_radius(j->g, pp->sigma_px[0]), r2 = fsf_tap_radius(j->g, pp->sigma_px[1]);
        float cum1[2 * FSF_RADIUS_CAP_PX + 2], cum2[2 * FSF_RADIUS_CAP_PX + 2];
        fsf_tap_prefix(pp->sigma_px[0], r1, cum1);
        fsf_tap_prefix(pp->sigma_px[1], r2, cum2);
        for (int t2 = -r2; t2 <= r2; ++t2) {
            float w2 = gauss((float)t2, pp->sigma_px[1]);
            for (int t1 = -r1; t1 <= r1; ++t1) {
                /* the neighbour at t1 dir1 + t2 dir2, rounded once */
                float fx = (float)t1 * pp->dir[0][0] + (float)t2 * pp->dir[1][0];
                float fy = (float)t1 * pp->dir[0][1] + (float)t2 * pp->dir[1][1];
                int qx = x + (int)floorf(fx + 0.5f), qy = y + (int)floorf(fy + 0.5f);
                if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                int q = qy * w + qx;
                if (!fsf_accept(j->gd, (int)i, q)) continue;
                float wx = w2 * gauss((float)t1, pp->sigma_px[0]);
                for (int k = 0; k < s->count[q]; ++k) {
                    size_t slot = (size_t)q * (size_t)s->capacity + (size_t)k;
                    /* the light coordinate the sample has seen from this pixel (y' + eta t) */
                    float z1 = s->y_m[2 * slot] + pp->eta_m[0] * (float)t1;
                    float z2 = s->y_m[2 * slot + 1] + pp->eta_m[1] * (float)t2;
                    if (box(j->g, 0, z1) == 0.0f || box(j->g, 1, z2) == 0.0f) continue;
                    /* divided by the density of reprojected samples at (z1, z2); a moving
                     * light's profile over it along each axis that ramps (swept_over_rho) */
                    float rho = swept_over_rho(j->g, 0, z1, pp->eta_m[0], r1, cum1) *
                                swept_over_rho(j->g, 1, z2, pp->eta_m[1], r2, cum2);
                    if (!(rho > 0.0f)) continue;
                    float wk = wx / rho, f_rgb, f_w;
                    /* form 4 along the first axis, as pass 1a, then the second, as pass 2a
                     * (fsf_geo_term.h) */
                    fsf_geo_factors(j->gd->geo, j->gd->pos4, j->gd->nrm4, (size_t)q, s->y_m[2 * slot],
                                    s->y_m[2 * slot + 1], z1, &f_rgb, &f_w);
                    wk *= fsf_geo_factor2(j->gd->geo, j->gd->pos4, j->gd->nrm4, (size_t)q, j->g->half_m[0],
                                          s->y_m[2 * slot + 1], z2);
                    const float *v = s->value + 3 * slot;
                    float wv = wk * f_rgb;
                    acc[0] += wv * v[0], acc[1] += wv * v[1], acc[2] += wv * v[2], acc[3] += wk * f_w;
                }
            }
        }
        memcpy(j->out4 + 4 * i, acc, sizeof acc);
    }
}

void fsf_filter_brute(const FsfSamples *s, const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd, float *out4)
{
    Job j = {s, g, px, gd, out4, NULL, NULL, NULL, NULL, NULL, 0, 0};
    recon_parallel_for((size_t)s->width * (size_t)s->height, brute_range, &j);
}

/* ---- the four passes ---- */

void fsf_pass1a(const FsfSamples *s, const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd,
                const float *cum1, int bin, float *P, size_t begin, size_t end)
{
    const unsigned char *usable = gd->usable;
    int J = g->shift_nodes;
    float dY = node_step(g, 0), L1 = g->half_m[0], mid = 0.5f * (float)(J - 1), ramp1 = g->ramp_m[0];
    for (size_t i = begin; i < end; ++i) {
        float *Pi = P + (size_t)J * 4 * i;
        memset(Pi, 0, sizeof(float) * 4 * (size_t)J);
        if (!usable[i]) continue; /* no tap reads its nodes (fsf_taps) */
        /* the density of reprojected samples uses this pixel's filter for its gatherers'
         * (a smooth field: FSF section 4.2's approximation again), over its mean (cum1,
         * fsf_tap_prefix_mean), which each gatherer's taps replace with its own */
        int r = fsf_tap_radius(g, px[i].sigma_px[0]);
        const float *cum = cum1 + (size_t)FSF_CUM * i;
        for (int k = 0; k < s->count[i]; ++k) {
            size_t slot = i * (size_t)s->capacity + (size_t)k;
            if (fsf_y2_bin(g, s->y_m[2 * slot + 1]) != bin) continue;
            float y1 = s->y_m[2 * slot];
            const float *v = s->value + 3 * slot;
            /* the nodes Y with |y1 - Y| <= L1 (eq. 12 with the box profile) */
            int j0 = (int)ceilf((y1 - L1) / dY + mid), j1 = (int)floorf((y1 + L1) / dY + mid);
            if (j0 < 0) j0 = 0;
            if (j1 > J - 1) j1 = J - 1;
            for (int jj = j0; jj <= j1; ++jj) {
                float z = y1 - ((float)jj - mid) * dY; /* seen from the pixel at shift Y */
                if (box(g, 0, z) == 0.0f) continue;    /* rounding at the ends */
                float wk;
                if (ramp1 > 0.0f) { /* a swept light: T(z) / rho(z) (fsf_swept_weight) */
                    wk = fsf_swept_weight(z, px[i].eta_m[0], L1, ramp1, r, cum);
                    if (!(wk > 0.0f)) continue;
                } else {
                    float rho = fsf_density(z, px[i].eta_m[0], L1, r, cum);
                    if (!(rho > 0.0f)) continue;
                    wk = 1.0f / rho;
                }
                float *o = Pi + 4 * jj, f_rgb, f_w;
                /* form 4: the pixel's own term read at z rather than y1 (fsf_geo_term.h) */
                fsf_geo_factors(gd->geo, gd->pos4, gd->nrm4, i, y1, s->y_m[2 * slot + 1], z, &f_rgb, &f_w);
                float wv = wk * f_rgb;
                o[0] += wv * v[0], o[1] += wv * v[1], o[2] += wv * v[2], o[3] += wk * f_w;
            }
        }
    }
}

void fsf_taps(const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd, int width, int height, int axis,
              FsfTap *taps, size_t begin, size_t end)
{
    int J = g->shift_nodes;
    float inv_dY = 1.0f / node_step(g, axis), mid = 0.5f * (float)(J - 1);
    for (size_t i = begin; i < end; ++i) {
        const FsfPixel *pp = &px[i];
        FsfTap *ti = taps + (size_t)FSF_TAPS * i;
        int x = (int)(i % (size_t)width), y = (int)(i / (size_t)width);
        /* a pixel that is not usable gets no taps, not even its own: its result is 0 */
        int r = gd->usable[i] ? fsf_tap_radius(g, pp->sigma_px[axis]) : -1;
        /* along the first axis the neighbours' nodes hold samples over their own density
         * times its mean (pass 1a's cum1): this pixel's mean density stands in for theirs */
        float inv_mean = axis == 0 && r >= 0 ? 1.0f / fsf_density_mean(g, 0, pp->eta_m[0], pp->sigma_px[0]) : 1.0f;
        for (int t = -FSF_RADIUS_CAP_PX; t <= FSF_RADIUS_CAP_PX; ++t) {
            FsfTap *o = &ti[t + FSF_RADIUS_CAP_PX];
            o->node = -1, o->a0 = o->a1 = 0.0f;
            if (t < -r || t > r) continue;
            int q = fsf_step_pixel(width, height, x, y, pp->dir[axis], (float)t);
            if (q < 0 || (t != 0 && !fsf_accept(gd, (int)i, q))) continue;
            /* the shift Y = eta (x - x') = -eta t, between grid nodes j0 and j0 + 1 */
            float f = -pp->eta_m[axis] * (float)t * inv_dY + mid;
            if (!(f >= 0.0f && f <= (float)(J - 1))) continue;
            int j0 = (int)floorf(f);
            if (j0 > J - 2) j0 = J - 2;
            float b = f - (float)j0, wt = gauss((float)t, pp->sigma_px[axis]) * inv_mean;
            o->node = q * J + j0, o->a0 = wt * (1.0f - b), o->a1 = wt * b;
        }
    }
}

/* One pixel's gather: the sum over its taps of the interpolated node values (4 floats). */
static inline void gather_taps(const FsfTap *ti, const float *F, float acc[4])
{
    for (int t = 0; t < FSF_TAPS; ++t) {
        if (ti[t].node < 0) continue;
        const float *F0 = F + 4 * (size_t)ti[t].node;
        float a0 = ti[t].a0, a1 = ti[t].a1;
        for (int c = 0; c < 4; ++c) acc[c] += a0 * F0[c] + a1 * F0[4 + c];
    }
}

void fsf_pass1b(const FsfGrid *g, const FsfTap *taps1, int bin, const float *P, float *G, size_t begin, size_t end)
{
    for (size_t i = begin; i < end; ++i) {
        float acc[4] = {0, 0, 0, 0};
        gather_taps(taps1 + (size_t)FSF_TAPS * i, P, acc);
        memcpy(G + ((size_t)g->y2_bins * i + (size_t)bin) * 4, acc, sizeof acc);
    }
}

/* Pass 2a's density at the gathering pixel (issue 15, 2026-11-29): rho2 of the intermediate
 * pixel's filter is FSF section 4.2's approximation, and most of the factorisation's bias on
 * soft_shadows (docs/algorithms.md section 10, "Pass 2a's density at the gathering pixel").
 * So pass 2a only divides each bin by its form-4 marginal and keeps the marginals (Q: 5 B floats
 * per pixel, FSF_Q2_FLOATS), and pass 2b weights each tap's bins with its own 1 / rho2. */
void fsf_pass2a(const FsfGrid *g, const FsfGuides *gd, const float *G, float *Q, size_t begin, size_t end)
{
    int B = g->y2_bins;
    float L2 = g->half_m[1];
    for (size_t i = begin; i < end; ++i) {
        float *gs = Q + (size_t)FSF_Q2_FLOATS(B) * i, *gm = gs + 4 * (size_t)B;
        const float *Gi = G + (size_t)B * 4 * i;
        if (!gd->usable[i]) { /* no tap reads it (fsf_taps) */
            memset(gs, 0, sizeof(float) * (size_t)FSF_Q2_FLOATS(B));
            continue;
        }
        /* form 4 along the second axis (fsf_geo_term.h): the z1-marginals at the bin centres */
        bool geo = gd->geo && gd->geo->mean_g[i] > 0.0f;
        for (int b = 0; geo && b < B; ++b) {
            gm[b] = fsf_geo_marginal(gd->geo, gd->pos4 + 4 * i, gd->nrm4 + 4 * i, g->half_m[0],
                                     2.0f * L2 / (float)B * ((float)b + 0.5f - 0.5f * (float)B));
            geo = gm[b] > 0.0f;
        }
        /* the bins divided by their own marginal once (none: gm 1, the plain sums exactly) */
        for (int b = 0; b < B; ++b) {
            if (!geo) gm[b] = 1.0f;
            for (int k = 0; k < 4; ++k) gs[4 * b + k] = geo ? Gi[4 * b + k] / gm[b] : Gi[4 * b + k];
        }
    }
}

void fsf_pass2b(const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd, const FsfTap *taps2, const float *Q,
                float *out4, size_t begin, size_t end)
{
    int J = g->shift_nodes, B = g->y2_bins;
    float L2 = g->half_m[1];
    float cum[FSF_CUM], inv_rho[3 * FSF_MAX_Y2_BINS];
    for (size_t i = begin; i < end; ++i) {
        float acc[4] = {0, 0, 0, 0};
        if (gd->usable[i]) {
            int r = fsf_tap_radius(g, px[i].sigma_px[1]);
            fsf_tap_prefix(px[i].sigma_px[1], r, cum);
            /* With B = J - 1 the light coordinate seen at shift node j from bin b's centre,
             * z = c_b - Y_j = (2 L2 / B) (b - 2 j + B / 2 + 1/2), depends on m = b - 2 j only:
             * 3 B densities per pixel, of this pixel's filter */
            for (int m = -2 * B; m < B; ++m) {
                float z = 2.0f * L2 / (float)B * ((float)m + 0.5f * (float)B + 0.5f);
                if (g->ramp_m[1] > 0.0f) { /* a swept light: T(z) / rho(z) (fsf_swept_weight) */
                    inv_rho[m + 2 * B] =
                        box(g, 1, z) != 0.0f ? fsf_swept_weight(z, px[i].eta_m[1], L2, g->ramp_m[1], r, cum) : 0.0f;
                    continue;
                }
                float rho = box(g, 1, z) != 0.0f ? fsf_density(z, px[i].eta_m[1], L2, r, cum) : 0.0f;
                inv_rho[m + 2 * B] = rho > 0.0f ? 1.0f / rho : 0.0f;
            }
            const FsfTap *ti = taps2 + (size_t)FSF_TAPS * i;
            for (int t = 0; t < FSF_TAPS; ++t) {
                if (ti[t].node < 0) continue;
                int q = ti[t].node / J, j0 = ti[t].node % J;
                const float *gs = Q + (size_t)FSF_Q2_FLOATS(B) * (size_t)q, *gm = gs + 4 * (size_t)B;
                /* the two nodes' sums Q(Y_j) of eq. 14 interpolated, as one weight per bin: bin b
                 * is seen at node j from the centre c_{b - 2 j + B} (form 4's ratio of marginals;
                 * inside the light wherever the box leaves a nonzero 1 / rho) */
                for (int b = 0; b < B; ++b) {
                    int m0 = b - 2 * j0 + 2 * B, m1 = m0 - 2; /* nodes j0, j0 + 1; m1 >= b >= 0 */
                    float w0 = inv_rho[m0], w1 = inv_rho[m1], wk = 0.0f;
                    if (w0 == 0.0f && w1 == 0.0f) continue;
                    if (w0 != 0.0f) wk += ti[t].a0 * w0 * gm[m0 - B < 0 ? 0 : m0 - B >= B ? B - 1 : m0 - B];
                    if (w1 != 0.0f) wk += ti[t].a1 * w1 * gm[m1 - B < 0 ? 0 : m1 - B >= B ? B - 1 : m1 - B];
                    for (int k = 0; k < 4; ++k) acc[k] += gs[4 * b + k] * wk;
                }
            }
        }
        memcpy(out4 + 4 * i, acc, sizeof acc);
    }
}

static void range_taps(void *ctx, size_t b, size_t e, int part)
{
    (void)part;
    Job *j = ctx;
    fsf_taps(j->g, j->px, j->gd, j->s->width, j->s->height, j->axis, j->taps, b, e);
    if (j->axis == 0)
        for (size_t i = b; i < e; ++i) fsf_tap_prefix_mean(j->g, &j->px[i], j->cum1 + (size_t)FSF_CUM * i);
}
static void range_1a(void *ctx, size_t b, size_t e, int part)
{
    (void)part;
    Job *j = ctx;
    fsf_pass1a(j->s, j->g, j->px, j->gd, j->cum1, j->bin, j->P, b, e);
}
static void range_1b(void *ctx, size_t b, size_t e, int part)
{
    (void)part;
    Job *j = ctx;
    fsf_pass1b(j->g, j->taps, j->bin, j->P, j->G, b, e);
}
static void range_2a(void *ctx, size_t b, size_t e, int part)
{
    (void)part;
    Job *j = ctx;
    fsf_pass2a(j->g, j->gd, j->G, j->Q, b, e);
}
static void range_2b(void *ctx, size_t b, size_t e, int part)
{
    (void)part;
    Job *j = ctx;
    fsf_pass2b(j->g, j->px, j->gd, j->taps, j->Q, j->out4, b, e);
}

bool fsf_filter_factored(const FsfSamples *s, const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd, float *out4)
{
    if (g->y2_bins != g->shift_nodes - 1 || g->y2_bins > FSF_MAX_Y2_BINS) return false;
    size_t n = (size_t)s->width * (size_t)s->height, J = (size_t)g->shift_nodes, B = (size_t)g->y2_bins;
    /* pass 1 runs one y2 bin at a time: P holds one slice (FSF's p for that bin), so the
     * memory is n (J + B) * 4 floats rather than n J B * 4; each pixel's taps (neighbour and
     * interpolation weights) are found once per axis, not once per slice */
    size_t p_floats = 4 * J > (size_t)FSF_Q2_FLOATS(B) ? 4 * J : (size_t)FSF_Q2_FLOATS(B);
    float *P = malloc(sizeof(float) * p_floats * n), *G = malloc(sizeof(float) * 4 * B * n);
    FsfTap *taps = malloc(sizeof(FsfTap) * FSF_TAPS * n);
    float *cum1 = malloc(sizeof(float) * FSF_CUM * n);
    bool ok = P && G && taps && cum1;
    if (ok) {
        Job j = {s, g, px, gd, out4, P, G, NULL, taps, cum1, 0, 0};
        recon_parallel_for(n, range_taps, &j);
        for (j.bin = 0; j.bin < g->y2_bins; ++j.bin) {
            recon_parallel_for(n, range_1a, &j);
            recon_parallel_for(n, range_1b, &j);
        }
        j.Q = P; /* Q lives in P's memory (sized for both); P is no longer needed */
        recon_parallel_for(n, range_2a, &j);
        j.axis = 1;
        recon_parallel_for(n, range_taps, &j);
        recon_parallel_for(n, range_2b, &j);
    }
    free(P);
    free(G);
    free(taps);
    free(cum1);
    return ok;
}
