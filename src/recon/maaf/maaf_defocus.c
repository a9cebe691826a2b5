/* Defocus MAAF: lens-factor tables for the disk aperture, signed per-pixel filters, screen
 * guides (see maaf_defocus.h; derivation in docs/algorithms.md 9.8). */
#include "recon/maaf/maaf_defocus.h"

#include "core/vectorise.h"
#include "recon/maaf/maaf_shadow.h" /* maaf_pixel_param: the x-filter of one wedge */

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI_D 3.14159265358979323846
/* Simpson intervals over the disk's polar angle (u' = sin t, half chord cos t: smooth in t) and
 * trapezoid steps of the antiderivative of one band's primal component over [-2, 2]. */
#define ANGLE_STEPS 128
#define ANTIDERIV_STEPS 8192

typedef struct {
    double re, im;
} Cplx;


float maaf_lens_band_centre(const MaafLens *l, int q) { return l->omega_u_max * 2.0f * (float)q / (2.0f * l->pairs - 1.0f); }
float maaf_lens_band_std(const MaafLens *l) { return l->omega_u_max / (2.0f * l->pairs - 1.0f); }

void maaf_lens_free(MaafLens *l)
{
    free(l->table);
    memset(l, 0, sizeof *l);
}

/* One table row of the stored quadrant, acc(iv) = sum_k r_k ct(k, iv) (complex; ct the chords
 * transposed, MAAF_LENS_ROWS doubles a k): each cell adds its terms in k order, the loop over
 * iv vectorises. Out of line in AVX copies (WEDGE_VECTORISED): 4 or 8 doubles a step instead
 * of the baseline's 2, the same products and sums per cell, so the same table; the frame's
 * table build is ~2% of a defocus frame at 6 spp. */
static WEDGE_VECTORISED void table_row(const Cplx *restrict r, int k_count, const double *restrict ct_re,
                                       const double *restrict ct_im, double *restrict acc_re, double *restrict acc_im)
{
    for (int iv = 0; iv < MAAF_LENS_ROWS; ++iv) acc_re[iv] = acc_im[iv] = 0.0;
    for (int k = 0; k < k_count; ++k) {
        double rr = r[k].re, ri = r[k].im;
        const double *cr = ct_re + (size_t)k * MAAF_LENS_ROWS, *ci = ct_im + (size_t)k * MAAF_LENS_ROWS;
        for (int iv = 0; iv < MAAF_LENS_ROWS; ++iv) {
            acc_re[iv] += rr * cr[iv] - ri * ci[iv];
            acc_im[iv] += rr * ci[iv] + ri * cr[iv];
        }
    }
}

/* One band's primal component exp(j C t) g(t; s) (maaf_design.h's conventions) from its envelope
 * g (band_envelope: one for every band, which share s); the central band (C t = +-0) without
 * the cosine and sine, which give exactly 1 and C t there. */
static Cplx band_oscillate(double g, double C, double t)
{
    double x = C * t;
    if (x == 0.0) return (Cplx){g, g * x};
    return (Cplx){g * cos(x), g * sin(x)};
}

/* The envelope g(t; s) of every band's primal component. */
static double band_envelope(double s, double t) { return s * 0.3989422804014327 * exp(-0.5 * s * s * t * t); }

bool maaf_lens_design(float kappa, int pairs, MaafLens *l)
{
    memset(l, 0, sizeof *l);
    int n = pairs < 1 ? 1 : pairs > MAAF_PAIRS_MAX ? MAAF_PAIRS_MAX : pairs, bands = 2 * n - 1;
    l->pairs = n;
    l->comps = maaf_component_count(n);
    l->omega_u_max = 2.0f * kappa / MAAF_LENS_SIGMA;
    /* only the stored quadrant's rows and columns (iu, iv < MAAF_LENS_ROWS) are made: the rest
     * of the 129 x 129 grid is never stored (maaf_lens_store) */
    enum { T = MAAF_LENS_TABLE, R = MAAF_LENS_ROWS, K = ANGLE_STEPS + 1, E = ANTIDERIV_STEPS + 1 };
    l->table = calloc((size_t)l->comps * MAAF_LENS_ROWS * MAAF_LENS_ROWS * 2, sizeof(float));
    maaf_lens_flips(l);
    Cplx *rows = malloc((size_t)n * R * K * sizeof(Cplx));         /* [p][iu][k] */
    Cplx *chords = malloc((size_t)bands * R * K * sizeof(Cplx));   /* [q + n - 1][iv][k] */
    Cplx *anti = malloc((size_t)E * sizeof(Cplx));
    double *env = malloc((size_t)E * sizeof(double));             /* the antiderivative's envelope */
    double cos_t[K], sin_t[K];                                     /* the disk's polar angle steps */
    bool ok = l->table && rows && chords && anti && env;
    double s = maaf_lens_band_std(l), dt = PI_D / ANGLE_STEPS, de = 4.0 / ANTIDERIV_STEPS;
    for (int k = 0; k < K; ++k) {
        double t = -0.5 * PI_D + k * dt;
        cos_t[k] = cos(t), sin_t[k] = sin(t);
    }
    /* outer factor, Simpson weight and Jacobian cos t included; one envelope for all bands */
    for (int iu = 0; ok && iu < R; ++iu)
        for (int k = 0; k < K; ++k) {
            double u = -1.0 + 2.0 * iu / (T - 1.0), x = sin_t[k] - u;
            double wk = (k == 0 || k == K - 1 ? 1.0 : (k & 1) ? 4.0 : 2.0) * dt / 3.0 * cos_t[k], g = band_envelope(s, x);
            for (int p = 0; p < n; ++p) {
                Cplx e = band_oscillate(g, maaf_lens_band_centre(l, p), x);
                rows[((size_t)p * R + iu) * K + k] = (Cplx){wk * e.re, wk * e.im};
            }
        }
    for (int e = 0; ok && e < E; ++e) env[e] = band_envelope(s, -2.0 + e * de);
    /* bands q >= 0; band -q's centre is -C (maaf_lens_band_centre: an exact negation), its
     * cosines the same and its sines negated, so its antiderivative and chords are band q's
     * conjugates, float for float: copied below */
    for (int q = 0; ok && q < n; ++q) {
        /* antiderivative A(t) = int_{-2}^{t} exp(j C t') g(t') dt' (trapezoid), then the chord
         * integral int_{-h}^{h} e(v' - v) dv' = A(h - v) - A(-h - v) */
        double C = maaf_lens_band_centre(l, q);
        anti[0] = (Cplx){0.0, 0.0};
        Cplx prev = band_oscillate(env[0], C, -2.0);
        for (int e = 1; e < E; ++e) {
            Cplx cur = band_oscillate(env[e], C, -2.0 + e * de);
            anti[e] = (Cplx){anti[e - 1].re + 0.5 * de * (prev.re + cur.re), anti[e - 1].im + 0.5 * de * (prev.im + cur.im)};
            prev = cur;
        }
        for (int iv = 0; iv < R; ++iv)
            for (int k = 0; k < K; ++k) {
                double v = -1.0 + 2.0 * iv / (T - 1.0), h = cos_t[k];
                Cplx a[2];
                double ends[2] = {h - v, -h - v};
                for (int b = 0; b < 2; ++b) {
                    double x = (ends[b] + 2.0) / de;
                    int e = (int)x;
                    if (e < 0) e = 0;
                    if (e > E - 2) e = E - 2;
                    double f = x - e;
                    a[b] = (Cplx){anti[e].re + f * (anti[e + 1].re - anti[e].re), anti[e].im + f * (anti[e + 1].im - anti[e].im)};
                }
                chords[((size_t)(q + n - 1) * R + iv) * K + k] = (Cplx){a[0].re - a[1].re, a[0].im - a[1].im};
            }
    }
    for (int q = -(n - 1); ok && q < 0; ++q)
        for (size_t j = 0; j < (size_t)R * K; ++j) {
            Cplx ch = chords[(size_t)(-q + n - 1) * R * K + j];
            chords[(size_t)(q + n - 1) * R * K + j] = (Cplx){ch.re, -ch.im};
        }
    /* table(iu, iv) = sum_k rows(iu, k) chords(iv, k): per iu, the sums of all iv at once with
     * the chords transposed to [k][iv] (each cell still adds its terms in k order, as one sum
     * per cell did; the loop over iv vectorises), over the stored quadrant only (below) */
    double *ct_re = malloc((size_t)K * R * sizeof(double)), *ct_im = malloc((size_t)K * R * sizeof(double));
    double *acc_re = malloc((size_t)R * sizeof(double)), *acc_im = malloc((size_t)R * sizeof(double));
    ok = ok && ct_re && ct_im && acc_re && acc_im;
    int c = 0;
    for (int p = 0; ok && p < n; ++p)
        for (int q = -(n - 1); q < n; ++q) {
            if (p == 0 && q < 0) continue;
            for (int iv = 0; iv < R; ++iv)
                for (int k = 0; k < K; ++k) {
                    Cplx ch = chords[((size_t)(q + n - 1) * R + iv) * K + k];
                    ct_re[(size_t)k * R + iv] = ch.re;
                    ct_im[(size_t)k * R + iv] = ch.im;
                }
            for (int iu = 0; iu < R; ++iu) {
                table_row(rows + ((size_t)p * R + iu) * K, K, ct_re, ct_im, acc_re, acc_im);
                for (int iv = 0; iv < R; ++iv) maaf_lens_store(l, c, iu, iv, (float)acc_re[iv], (float)acc_im[iv]);
            }
            ++c;
        }
    free(ct_re);
    free(ct_im);
    free(acc_re);
    free(acc_im);
    free(rows);
    free(chords);
    free(anti);
    free(env);
    if (!ok) maaf_lens_free(l);
    return ok;
}

void maaf_lens_store(MaafLens *l, int c, int iu, int iv, float re, float im)
{
    if (iu >= MAAF_LENS_ROWS || iv >= MAAF_LENS_ROWS) return;
    float *o = l->table + (((size_t)iu * MAAF_LENS_ROWS + iv) * l->comps + c) * 2;
    o[0] = re, o[1] = im;
}

void maaf_lens_flips(MaafLens *l)
{
    int n = l->pairs, c = 0;
    for (int p = 0; p < n; ++p)
        for (int q = -(n - 1); q < n; ++q) {
            if (p == 0 && q < 0) continue;
            /* (p, -q) in the half set's order: p = 0 holds q >= 0 (n of them), each p > 0 all
             * 2n - 1 values of q from -(n - 1) */
            l->vflip[c] = p == 0 ? (signed char)(-1 - c) : (signed char)(n + (p - 1) * (2 * n - 1) + (-q + n - 1));
            ++c;
        }
}

/* Table cell of (u, v) and its bilinear weights, for u, v <= 0 (the stored quadrant; the callers
 * fold the others onto it). */
static inline size_t lens_cell(float u, float v, float *a, float *b)
{
    enum { T = MAAF_LENS_TABLE };
    float fu = (u + 1.0f) * 0.5f * (T - 1), fv = (v + 1.0f) * 0.5f * (T - 1);
    if (!(fu > 0.0f)) fu = 0.0f; /* NaN too */
    if (!(fv > 0.0f)) fv = 0.0f;
    if (fu > T - 1) fu = T - 1;
    if (fv > T - 1) fv = T - 1;
    int iu = (int)fu, iv = (int)fv;
    if (iu > T - 2) iu = T - 2;
    if (iv > T - 2) iv = T - 2;
    *a = fu - (float)iu, *b = fv - (float)iv;
    return (size_t)iu * MAAF_LENS_ROWS + (size_t)iv;
}

/* The quadrant's values of (u, v) for every component (2 comps floats) after the folds: u > 0
 * reads (-u, -v) conjugated (the disk is point-symmetric and each band's primal component at -t
 * is the conjugate of that at t), then v > 0 reads (u, -v) of component (p, -q) (the disk is
 * symmetric in v and band -q's component at -t is band q's at t; at p = 0, (0, -q) is the
 * conjugate of (0, q)). */
typedef struct {
    bool conj, flip;
    size_t cell;
    float a, b;
} LensFold;

static inline LensFold lens_fold(float u, float v)
{
    LensFold f = {u > 0.0f, false, 0, 0.0f, 0.0f};
    if (f.conj) u = -u, v = -v;
    f.flip = v > 0.0f;
    if (f.flip) v = -v;
    f.cell = lens_cell(u, v, &f.a, &f.b);
    return f;
}

void maaf_lens_factor(const MaafLens *l, int c, float u, float v, float out[2])
{
    LensFold f = lens_fold(u, v);
    int src = c, sign = 1;
    if (f.flip) src = l->vflip[c] >= 0 ? l->vflip[c] : c, sign = l->vflip[c] >= 0 ? 1 : -1;
    size_t step = (size_t)l->comps * 2, row = (size_t)MAAF_LENS_ROWS * step;
    const float *t00 = l->table + f.cell * step + 2 * src, *t01 = t00 + step, *t10 = t00 + row, *t11 = t10 + step;
    for (int k = 0; k < 2; ++k)
        out[k] = (1.0f - f.a) * ((1.0f - f.b) * t00[k] + f.b * t01[k]) + f.a * ((1.0f - f.b) * t10[k] + f.b * t11[k]);
    if (sign < 0) out[1] = -out[1];
    if (f.conj) out[1] = -out[1];
}

void maaf_lens_factors(const MaafLens *l, float u, float v, float *w)
{
    LensFold f = lens_fold(u, v);
    size_t step = (size_t)l->comps * 2, row = (size_t)MAAF_LENS_ROWS * step;
    const float *t00 = l->table + f.cell * step, *t01 = t00 + step, *t10 = t00 + row, *t11 = t10 + step;
    float w00 = (1.0f - f.a) * (1.0f - f.b), w01 = (1.0f - f.a) * f.b, w10 = f.a * (1.0f - f.b), w11 = f.a * f.b;
    float q[2 * MAAF_COMPS_MAX], *o = f.flip ? q : w;
    /* one contiguous loop over every component's (re, im): it vectorises, and the per-component
     * loop of the sums then needs no shuffles */
    for (size_t k = 0; k < step; ++k) o[k] = w00 * t00[k] + w01 * t01[k] + w10 * t10[k] + w11 * t11[k];
    if (f.flip)
        for (int c = 0; c < l->comps; ++c) {
            int src = l->vflip[c];
            w[2 * c] = src >= 0 ? q[2 * src] : q[2 * c];
            w[2 * c + 1] = src >= 0 ? q[2 * src + 1] : -q[2 * c + 1];
        }
    if (f.conj)
        for (size_t k = 1; k < step; k += 2) w[k] = -w[k];
}

void maaf_lens_accumulate(const MaafLens *l, float u, float v, const float f4[4], float *ysum)
{
    float w[2 * MAAF_COMPS_MAX];
    maaf_lens_factors(l, u, v, w);
    maaf_factors_accumulate(l->comps, w, f4, ysum);
}

float maaf_pixel_param_signed(float s_min, float s_max, float omega_u_max, int pairs, float *param)
{
    memset(param, 0, MAAF_PARAM_STRIDE * sizeof(float));
    if (!(s_min == s_min) || !(s_max == s_max)) return 0.0f;
    if (s_min > s_max) {
        float t = s_min;
        s_min = s_max;
        s_max = t;
    }
    float std_px;
    if (s_min > 0.0f) {
        std_px = maaf_pixel_param(s_min, s_max, omega_u_max, pairs, 1.0f, 1.0f, param);
    } else {
        if (!(s_max < 0.0f)) return 0.0f; /* straddles the focal plane: the wedge holds the Omega_x axis */
        /* s -> -s mirrors the wedge through the Omega_u axis (Omega_x -> -Omega_x): the same
         * boxes with C_x negated */
        std_px = maaf_pixel_param(-s_max, -s_min, omega_u_max, pairs, 1.0f, 1.0f, param);
        for (int p = 0; p < MAAF_PAIRS_MAX; ++p) param[2 + 3 * p] = -param[2 + 3 * p];
    }
    if (std_px > 0.0f) param[0] = fminf(ceilf(MAAF_DEFOCUS_RADIUS_STD * std_px), (float)MAAF_RADIUS_CAP_PX);
    return std_px;
}

static bool has_range(const float *coc_min, const float *coc_max, size_t j)
{
    return coc_min[j] <= coc_max[j] && isfinite(coc_min[j]) && isfinite(coc_max[j]);
}

void maaf_coc_pool(const float *coc_min, const float *coc_max, int width, int height, float *pool_min, float *pool_max)
{
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            size_t i = (size_t)y * (size_t)width + (size_t)x;
            float lo = coc_min[i], hi = coc_max[i];
            static const int step[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
            if (has_range(coc_min, coc_max, i))
                for (int k = 0; k < 4; ++k) {
                    int xx = x + step[k][0], yy = y + step[k][1];
                    if (xx < 0 || yy < 0 || xx >= width || yy >= height) continue;
                    size_t j = (size_t)yy * (size_t)width + (size_t)xx;
                    if (!has_range(coc_min, coc_max, j)) continue;
                    lo = fminf(lo, coc_min[j]);
                    hi = fmaxf(hi, coc_max[j]);
                }
            pool_min[i] = lo, pool_max[i] = hi;
        }
}

float maaf_defocus_pixel(const float *coc_min, const float *coc_max, const float *pool_min, const float *pool_max,
                         int width, int height, int x, int y, float omega_u_max, int pairs, float *param, float *side)
{
    memset(param, 0, MAAF_PARAM_STRIDE * sizeof(float));
    *side = 0.0f;
    size_t i = (size_t)y * (size_t)width + (size_t)x;
    if (!(coc_min[i] * coc_max[i] > 0.0f)) return 0.0f; /* straddles (or touches) the focal plane */
    double lo = 0.0, hi = 0.0;
    int count = 0;
    for (int yy = y - MAAF_DEFOCUS_WINDOW_PX; yy <= y + MAAF_DEFOCUS_WINDOW_PX; ++yy)
        for (int xx = x - MAAF_DEFOCUS_WINDOW_PX; xx <= x + MAAF_DEFOCUS_WINDOW_PX; ++xx) {
            if (xx < 0 || yy < 0 || xx >= width || yy >= height) continue;
            size_t j = (size_t)yy * (size_t)width + (size_t)xx;
            if (!has_range(pool_min, pool_max, j)) continue;
            lo += pool_min[j];
            hi += pool_max[j];
            ++count;
        }
    if (!count) return 0.0f;
    /* s = -coc: the largest coc is the smallest slope */
    float s_min = (float)(-hi / count), s_max = (float)(-lo / count);
    float std_px = maaf_pixel_param_signed(s_min, s_max, omega_u_max, pairs, param);
    if (std_px > 0.0f) *side = s_max < 0.0f ? -1.0f : 1.0f;
    return std_px;
}

void maaf_defocus_add_light(const float *value4, float factor, const float mean3[3], const float *rest, const float *alb,
                            size_t per, float *o)
{
    /* per (re, im) half of a component its rgb; the weight channel (the fourth) is left as it is */
    if (value4 && value4[3] != 0.0f) { /* filtered */
        float k[3] = {factor * value4[0], factor * value4[1], factor * value4[2]};
        for (size_t c = 0; c < per; c += 4)
            for (int ch = 0; ch < 3; ++ch) o[c + ch] += k[ch] * alb[c + ch];
    } else {
        const float *v = value4 ? value4 : mean3;
        for (size_t c = 0; c < per; c += 4)
            for (int ch = 0; ch < 3; ++ch) o[c + ch] += v[ch] * rest[c + 3];
    }
}

void maaf_screen_guides(int x, int y, float side, bool usable, float pos4[4], float nrm4[4], float frame4[4],
                        float axis2[4])
{
    pos4[0] = (float)x + 0.5f, pos4[1] = (float)y + 0.5f, pos4[2] = 0.0f, pos4[3] = 1.0f;
    nrm4[0] = 0.0f, nrm4[1] = 0.0f, nrm4[2] = 1.0f, nrm4[3] = side;
    frame4[0] = 1.0f, frame4[1] = 0.0f, frame4[2] = 0.0f, frame4[3] = usable ? 1.0f : 0.0f;
    axis2[0] = 0.0f, axis2[1] = 1.0f, axis2[2] = 0.0f, axis2[3] = 0.0f;
}
