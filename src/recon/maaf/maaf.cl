/* Multiple axis-aligned filters: the image-space pass of seeds/003 eq. 21 for the 4D soft-shadow
 * filter (a product of two orthogonal 2D designs, Sec. 6.1), run twice: along pixel rows
 * (maaf_rows), then along pixel columns (maaf_cols). OpenCL C 1.2, float only. The C reference
 * is maaf_filter_reference (maaf_filter.c), which computes the same sums in the same order;
 * docs/algorithms.md 9.6 has the derivation, 9.10 this layout.
 *
 * Components are indexed c = (p, q), p the band along light axis 1, q along axis 2, over the
 * half set {p > 0, or p = 0 and q >= 0}: the other half are complex conjugates and fold into a
 * factor 2 on the real part. For each c a pixel holds the complex sums Y_c (rgb of the
 * demodulated light, and w: the same sums of 1) of eq. 20, with the y-factors already applied.
 * This pass applies the x-factors,
 *     exp(j (C_x^p d1 + C_x^q d2)) exp(-(sx_p d1)^2/2 - (sx_q d2)^2/2),
 * (d1, d2) the world offset centre - neighbour projected on the centre's light axes: the
 * phase is exact across the two passes (offsets add), the Gaussian is separated like AAF's.
 *
 * Layout (as AAF's aaf.cl): one work item filters 8 consecutive pixels of a row in float8 lanes,
 * reading every per-pixel quantity from its own float plane, so that a tap's 8 neighbours are 8
 * consecutive floats (vload8) along rows and along columns alike; PoCL turns the float8
 * arithmetic, sin, cos and exp included, into SIMD code. maaf_unpack builds the guide planes
 * from the host's interleaved arrays; the host writes the sums' planes itself. The pass runs
 * per band of image rows [y0, y1) (maaf_filter_run): the host writes a band's sums, maaf_rows
 * filters them, and maaf_cols then filters the rows whose column reach the row output covers.
 *   guide  MAAF_GUIDES planes, each row with MAAF_PAD pixels of zeros on either side (usable
 *          0); pitch gpitch. The row pass takes only taps that reach the image with one of
 *          its 8 lanes (the others read the padding), the column pass only rows inside it,
 *          so no plane needs more padding or any bounds check
 *   yp     one band of the sums (image row y in row y mod yrows), 8 planes per component
 *          (re r g b w, im r g b w: the host's float order) and a flag plane (1: a usable
 *          pixel with a non-finite sum), padded as the guides; stored row by row, each image
 *          row holding every plane's row ystride floats apart, so that a tap's ~100 reads lie
 *          in a few pages
 *   tp     the row pass's output (no padding: the column pass reads image rows), a ring of
 *          trows rows (image row y in row y mod trows: a band and the column reach on either
 *          side), in blocks: for each row and 8 pixels, every plane's 8 floats one after the
 *          other, so that a column tap reads one contiguous block (in planes, its 100 streams
 *          missed the cache)
 * A rejected neighbour gets weight 0 by select, and its sums are read only through select when
 * one of them is not finite (0 * NaN would poison a lane that does not use it).
 *
 * Host arrays: pos4 (position, depth), nrm4 (normal, object id), frame4 (the light's axis t1,
 * usable flag), axis2 (its axis t2); param: MAAF_PARAM_STRIDE floats per pixel, radius in
 * pixels, then per band p: amplitude, C_x, sx^2/2 (world units). out4: filtered rgb and a flag
 * (0: unchanged, 1: filtered, 2: the full sum's weight was too small and the central component
 * alone was used). */

#define MAAF_PAIRS_MAX 5
#define MAAF_COMPS_MAX 41
#define MAAF_PARAM_STRIDE 16
/* MAAF_RADIUS_CAP_PX (maaf_filter.h) */
#define MAAF_RADIUS_CAP 32
/* padding of every row: a row tap's lanes reach at most 7 pixels past the image */
#define MAAF_PAD 8
/* below this fraction of the central component's weight the full sum is not trusted */
#define MAAF_MIN_WEIGHT_FRACTION 0.2f
/* guide planes (MAAF_GUIDES in maaf_filter.c) */
#define G_PX 0
#define G_PY 1
#define G_PZ 2
#define G_DEPTH 3
#define G_NX 4
#define G_NY 5
#define G_NZ 6
#define G_ID 7
#define G_USE 8
#define G_RAD 9
#define G_HV0 10
#define MAAF_GUIDES 11

__kernel void maaf_unpack(int width, int height, int gpitch, int gplane, __global const float4 *pos4,
                          __global const float4 *nrm4, __global const float4 *frame4, __global const float *param,
                          __global float *guide)
{
    int gx = (int)get_global_id(0), y = (int)get_global_id(1);
    if (gx >= gpitch || y >= height) return;
    int x = gx - MAAF_PAD;
    bool inside = x >= 0 && x < width;
    int i = inside ? y * width + x : 0;
    float4 p = inside ? pos4[i] : (float4)(0.0f), n = inside ? nrm4[i] : (float4)(0.0f);
    bool use = inside && frame4[i].w != 0.0f;
    __global const float *pr = param + i * MAAF_PARAM_STRIDE;
    __global float *g = guide + y * gpitch + gx;
    g[G_PX * gplane] = p.x;
    g[G_PY * gplane] = p.y;
    g[G_PZ * gplane] = p.z;
    g[G_DEPTH * gplane] = p.w;
    g[G_NX * gplane] = n.x;
    g[G_NY * gplane] = n.y;
    g[G_NZ * gplane] = n.z;
    g[G_ID * gplane] = n.w;
    g[G_USE * gplane] = use ? 1.0f : 0.0f;
    g[G_RAD * gplane] = inside ? pr[0] : 0.0f;
    g[G_HV0 * gplane] = inside ? pr[3] : 0.0f;
}

/* The centre lanes' guides, axes and filter parameters. */
typedef struct {
    float8 px, py, pz, nx, ny, nz, id, tol, t1x, t1y, t1z, t2x, t2y, t2z;
    float8 rad;  /* taps |k| <= rad; -1: the lane is not filtered */
    float8 hv0;  /* its central component's sx^2/2 times the run's sharpness factor (the rule) */
    int reach;   /* the largest radius of the 8 lanes */
} Centre;

static float8 lane_gather(__global const float *a, int stride, int i0, int lanes)
{
    float v[8];
    for (int l = 0; l < 8; ++l) v[l] = l < lanes ? a[(i0 + l) * stride] : 0.0f;
    return vload8(0, v);
}

static Centre centre_load(__global const float *guide, int gplane, int go, __global const float *frame4,
                          __global const float *axis2, __global const float *param, int pairs, int i0, int lanes,
                          float depth_tol_rel, float sharp_factor, float8 *amp, float8 *cx, float8 *hv)
{
    Centre c;
    c.px = vload8(0, guide + G_PX * gplane + go);
    c.py = vload8(0, guide + G_PY * gplane + go);
    c.pz = vload8(0, guide + G_PZ * gplane + go);
    c.nx = vload8(0, guide + G_NX * gplane + go);
    c.ny = vload8(0, guide + G_NY * gplane + go);
    c.nz = vload8(0, guide + G_NZ * gplane + go);
    c.id = vload8(0, guide + G_ID * gplane + go);
    c.tol = depth_tol_rel * vload8(0, guide + G_DEPTH * gplane + go);
    c.t1x = lane_gather(frame4, 4, i0, lanes);
    c.t1y = lane_gather(frame4 + 1, 4, i0, lanes);
    c.t1z = lane_gather(frame4 + 2, 4, i0, lanes);
    c.t2x = lane_gather(axis2, 4, i0, lanes);
    c.t2y = lane_gather(axis2 + 1, 4, i0, lanes);
    c.t2z = lane_gather(axis2 + 2, 4, i0, lanes);
    for (int p = 0; p < pairs; ++p) {
        amp[p] = lane_gather(param + 1 + 3 * p, MAAF_PARAM_STRIDE, i0, lanes);
        cx[p] = lane_gather(param + 2 + 3 * p, MAAF_PARAM_STRIDE, i0, lanes);
        hv[p] = lane_gather(param + 3 + 3 * p, MAAF_PARAM_STRIDE, i0, lanes);
    }
    c.hv0 = sharp_factor * hv[0];
    /* the reference's integer radius; a lane is filtered when usable with a radius > 0 */
    float8 rad = fmin(trunc(vload8(0, guide + G_RAD * gplane + go)), (float8)MAAF_RADIUS_CAP);
    int8 filtered = (vload8(0, guide + G_USE * gplane + go) != 0.0f) & (rad > 0.0f);
    c.rad = select((float8)(-1.0f), rad, filtered);
    float4 m4 = fmax(c.rad.lo, c.rad.hi);
    float2 m2 = fmax(m4.lo, m4.hi);
    c.reach = (int)fmax(m2.x, m2.y);
    return c;
}

/* Which lanes use the neighbour at guide offset go (tap k): AAF's rejections (another object,
 * a normal discontinuity, a depth discontinuity) and its sharpness rule (a neighbour that is
 * not filtered, or whose central filter is under half as wide as the centre's, holds detail
 * the centre's filter would smear), written as the reference's tests negated so that NaNs
 * decide alike; and the offset (d1, d2) on the centre's light axes. */
static int8 tap_lanes(const Centre *c, __global const float *guide, int gplane, int go, int k, float cos_normal_min,
                      float8 *d1, float8 *d2)
{
    float8 dx = c->px - vload8(0, guide + G_PX * gplane + go);
    float8 dy = c->py - vload8(0, guide + G_PY * gplane + go);
    float8 dz = c->pz - vload8(0, guide + G_PZ * gplane + go);
    float8 cosn = c->nx * vload8(0, guide + G_NX * gplane + go) + c->ny * vload8(0, guide + G_NY * gplane + go) +
                  c->nz * vload8(0, guide + G_NZ * gplane + go);
    float8 off = fabs(c->nx * dx + c->ny * dy + c->nz * dz);
    int8 ok = (fabs((float8)((float)k)) <= c->rad) & (vload8(0, guide + G_USE * gplane + go) != 0.0f) &
              (vload8(0, guide + G_ID * gplane + go) == c->id) & ~(cosn < cos_normal_min) & ~(off > c->tol) &
              ~(vload8(0, guide + G_RAD * gplane + go) <= 0.0f) &
              ~(vload8(0, guide + G_HV0 * gplane + go) > c->hv0);
    *d1 = dx * c->t1x + dy * c->t1y + dz * c->t1z;
    *d2 = dx * c->t2x + dy * c->t2y + dz * c->t2z;
    return ok;
}

/* cos, sin of the phase cx d and the Gaussian exp(-hv d^2); sin(0) = 0, cos(0) = exp(0) = 1
 * exactly, so the calls are skipped when every lane has a zero argument: the central band
 * (C_x = 0) and, for defocus's screen guides, the axis across the pass (d = 0).
 * native_sin/native_cos: on PoCL (CPU) as close to the C reference as sincos (max difference
 * on the bench frames 1.2e-7 and 2.9e-6 against 1.2e-7 and 3.3e-6) and 14-25% less kernel
 * time (sincos goes through a slow path for large arguments); their accuracy is the
 * implementation's, which the kernel == reference tests check on the device they run on.
 * native_exp saved nothing measurable. */
static void axis_factor(float8 cx, float8 hv, float8 d, float8 *c, float8 *s, float8 *g)
{
    float8 phase = cx * d, arg = -hv * d * d;
    *c = (float8)(1.0f);
    *s = (float8)(0.0f);
    *g = (float8)(1.0f);
    if (any(phase != 0.0f)) *s = native_sin(phase), *c = native_cos(phase);
    if (any(arg != 0.0f)) *g = exp(arg);
}

/* Per band p < pairs the complex x-factors along both axes, 0 in the lanes that do not use the
 * tap. A band whose C_x and sx in every lane are band 0's (copy[p]) has band 0's factors. */
static void tap_factors(int pairs, const bool *copy, const float8 *cx, const float8 *hv, float8 d1, float8 d2, int8 ok,
                        float8 *e1r, float8 *e1i, float8 *e2r, float8 *e2i)
{
    for (int p = 0; p < pairs; ++p) {
        if (copy[p]) {
            e1r[p] = e1r[0], e1i[p] = e1i[0], e2r[p] = e2r[0], e2i[p] = e2i[0];
            continue;
        }
        float8 c1, c2, s1, s2, g1, g2;
        axis_factor(cx[p], hv[p], d1, &c1, &s1, &g1);
        axis_factor(cx[p], hv[p], d2, &c2, &s2, &g2);
        e1r[p] = select((float8)(0.0f), g1 * c1, ok);
        e1i[p] = select((float8)(0.0f), g1 * s1, ok);
        e2r[p] = select((float8)(0.0f), g2 * c2, ok);
        e2i[p] = select((float8)(0.0f), g2 * s2, ok);
    }
}

/* The taps that some lane uses, and their factors per band (tap t, band p at t * pairs + p):
 * computed once per work item, then every component sweeps them with its sums in registers
 * (components outer, taps inner: each component's sum still adds its taps in k order). */
#define MAAF_TAPS_MAX (2 * MAAF_RADIUS_CAP + 1)
typedef struct {
    int count;
    int offset[MAAF_TAPS_MAX]; /* k */
    int8 ok[MAAF_TAPS_MAX];    /* the lanes that use it */
    bool guard[MAAF_TAPS_MAX]; /* a lane that does not use it would read a non-finite sum */
    float8 e1r[MAAF_TAPS_MAX * MAAF_PAIRS_MAX], e1i[MAAF_TAPS_MAX * MAAF_PAIRS_MAX];
    float8 e2r[MAAF_TAPS_MAX * MAAF_PAIRS_MAX], e2i[MAAF_TAPS_MAX * MAAF_PAIRS_MAX];
} Taps;

/* Bands p >= factor_pairs get no factors (the column pass: bands without amplitude in any lane,
 * whose components it skips). The shadows' plain pixels (maaf_pixel_param_plain: C_x 0 and
 * band 0's sx in every band) need one band's exp per axis instead of one per band. */
static void taps_collect(Taps *t, const Centre *c, int kmin, int kmax, int pairs, int factor_pairs, const float8 *cx,
                         const float8 *hv, float cos_normal_min, __global const float *guide, int gplane, int go,
                         int gstep, __global const float *flags, int fstep, int fy, int fring)
{
    bool copy[MAAF_PAIRS_MAX];
    for (int p = 0; p < factor_pairs; ++p) copy[p] = p > 0 && all(cx[p] == cx[0]) && all(hv[p] == hv[0]);
    t->count = 0;
    for (int k = max(-c->reach, kmin); k <= min(c->reach, kmax); ++k) {
        float8 d1, d2;
        int8 ok = tap_lanes(c, guide, gplane, go + k * gstep, k, cos_normal_min, &d1, &d2);
        if (!any(ok)) continue;
        int n = t->count++;
        tap_factors(factor_pairs, copy, cx, hv, d1, d2, ok, t->e1r + n * pairs, t->e1i + n * pairs,
                    t->e2r + n * pairs, t->e2i + n * pairs);
        t->offset[n] = k;
        t->ok[n] = ok;
        /* the flag of the neighbour's block: k blocks on, or (the column pass's ring of row
         * pass output) on ring row (fy + k) mod fring */
        int f = fring > 0 ? (fy + k) % fring : k;
        t->guard[n] = any((vload8(0, flags + f * fstep) != 0.0f) & ~ok);
    }
}

/* Component (p, q)'s weight at tap n: e1_p times e2_q, band -q the conjugate of band q. */
static void tap_weight(const Taps *t, int n, int pairs, int p, int q, float8 *wr, float8 *wi)
{
    int aq = q < 0 ? -q : q;
    float8 ar = t->e1r[n * pairs + p], ai = t->e1i[n * pairs + p];
    float8 br = t->e2r[n * pairs + aq], bi = q < 0 ? -t->e2i[n * pairs + aq] : t->e2i[n * pairs + aq];
    *wr = ar * br - ai * bi;
    *wi = ar * bi + ai * br;
}

/* The row pass: every component's complex sums into tp (unfiltered lanes: zeros, never read:
 * the column pass rejects them as neighbours). */
__kernel void maaf_rows(int width, int height, int pairs, int comps, float cos_normal_min, float depth_tol_rel,
                        float sharp_factor, int gpitch, int gplane, int ystride, int tblocks, int y0, int y1, int yrows,
                        int trows, __global const float *guide, __global const float *frame4, __global const float *axis2,
                        __global const float *param, __global const float *yp, __global float *tp,
                        __global const int *need)
{
    int x0 = (int)get_global_id(0) * 8, y = y0 + (int)get_global_id(1);
    if (x0 >= width || y >= y1) return;
    int go = y * gpitch + x0 + MAAF_PAD;
    int per = 8 * comps, yo = (y % yrows) * (per + 1) * ystride + x0 + MAAF_PAD, i0 = y * width + x0,
        lanes = min(8, width - x0);
    float8 amp[MAAF_PAIRS_MAX], cx[MAAF_PAIRS_MAX], hv[MAAF_PAIRS_MAX];
    Centre c = centre_load(guide, gplane, go, frame4, axis2, param, pairs, i0, lanes, depth_tol_rel, sharp_factor, amp, cx, hv);
    Taps t;
    /* taps whose 8 neighbours include an image pixel */
    taps_collect(&t, &c, -(x0 + 7), width - 1 - x0, pairs, pairs, cx, hv, cos_normal_min, guide, gplane, go, 1,
                 yp + yo + per * ystride, 1, 0, 0);
    __global float *o = tp + ((y % trows) * tblocks + x0 / 8) * (per + 1) * 8;
    int8 bad = (int8)(0);
    /* every component, or the central one where no column reader has amplitude in another
     * (row_needs in maaf_filter.c); the others' blocks in tp are then not written (nor read) */
    int row_comps = need[y * tblocks + x0 / 8] ? comps : 1;
    int ci = 0;
    for (int p = 0; p < pairs; ++p)
        for (int q = -(pairs - 1); q < pairs; ++q) {
            if (p == 0 && q < 0) continue;
            if (ci >= row_comps) break;
            /* one register per (channel, re/im): written out, the compiler keeps them in
             * registers (as an array it kept them in memory) */
            float8 r0 = 0.0f, r1 = 0.0f, r2 = 0.0f, r3 = 0.0f, i0 = 0.0f, i1 = 0.0f, i2 = 0.0f, i3 = 0.0f;
            for (int n = 0; n < t.count; ++n) {
                float8 wr, wi;
                tap_weight(&t, n, pairs, p, q, &wr, &wi);
                __global const float *s = yp + yo + t.offset[n] + 8 * ci * ystride;
                float8 y0 = vload8(0, s), y1 = vload8(0, s + ystride), y2 = vload8(0, s + 2 * ystride),
                       y3 = vload8(0, s + 3 * ystride), z0 = vload8(0, s + 4 * ystride),
                       z1 = vload8(0, s + 5 * ystride), z2 = vload8(0, s + 6 * ystride),
                       z3 = vload8(0, s + 7 * ystride);
                if (t.guard[n]) {
                    int8 ok = t.ok[n];
                    y0 = select(0.0f, y0, ok), y1 = select(0.0f, y1, ok), y2 = select(0.0f, y2, ok);
                    y3 = select(0.0f, y3, ok), z0 = select(0.0f, z0, ok), z1 = select(0.0f, z1, ok);
                    z2 = select(0.0f, z2, ok), z3 = select(0.0f, z3, ok);
                }
                r0 += wr * y0 - wi * z0, i0 += wr * z0 + wi * y0;
                r1 += wr * y1 - wi * z1, i1 += wr * z1 + wi * y1;
                r2 += wr * y2 - wi * z2, i2 += wr * z2 + wi * y2;
                r3 += wr * y3 - wi * z3, i3 += wr * z3 + wi * y3;
            }
            vstore8(r0, 8 * ci, o), vstore8(r1, 8 * ci + 1, o), vstore8(r2, 8 * ci + 2, o), vstore8(r3, 8 * ci + 3, o);
            vstore8(i0, 8 * ci + 4, o), vstore8(i1, 8 * ci + 5, o), vstore8(i2, 8 * ci + 6, o), vstore8(i3, 8 * ci + 7, o);
            bad |= !isfinite(r0) | !isfinite(r1) | !isfinite(r2) | !isfinite(r3) | !isfinite(i0) | !isfinite(i1) |
                   !isfinite(i2) | !isfinite(i3);
            ++ci;
        }
    vstore8(select((float8)(0.0f), (float8)(1.0f), bad), per, o);
}

/* The column pass on the row pass's sums, and eq. 21: the real part of the sum over
 * components, each with its amplitude; the conjugate half doubles every component but the
 * central one. Only the real parts of the column sums are needed. */
__kernel void maaf_cols(int width, int height, int pairs, int comps, float cos_normal_min, float depth_tol_rel,
                        float sharp_factor, int gpitch, int gplane, int tblocks, int y0, int y1, int trows,
                        __global const float *guide, __global const float *frame4, __global const float *axis2,
                        __global const float *param, __global const float *tp, __global float4 *out4)
{
    int x0 = (int)get_global_id(0) * 8, y = y0 + (int)get_global_id(1);
    if (x0 >= width || y >= y1) return;
    int go = y * gpitch + x0 + MAAF_PAD;
    int per = 8 * comps, tb = (per + 1) * 8, to = (x0 / 8) * tb, i0 = y * width + x0, lanes = min(8, width - x0);
    float8 amp[MAAF_PAIRS_MAX], cx[MAAF_PAIRS_MAX], hv[MAAF_PAIRS_MAX];
    Centre c = centre_load(guide, gplane, go, frame4, axis2, param, pairs, i0, lanes, depth_tol_rel, sharp_factor, amp, cx, hv);
    Taps t;
    /* the bands with amplitude in some lane: the components of the others are skipped below */
    int amp_pairs = 1;
    for (int p = 1; p < pairs; ++p)
        if (any(amp[p] != 0.0f)) amp_pairs = p + 1;
    /* taps on image rows */
    taps_collect(&t, &c, -y, height - 1 - y, pairs, amp_pairs, cx, hv, cos_normal_min, guide, gplane, go, gpitch,
                 tp + to + per * 8, tblocks * tb, y, trows);
    /* each tap's block in the ring of row pass output (image row y + k at ring row (y + k) mod trows) */
    int tap_block[MAAF_TAPS_MAX];
    for (int n = 0; n < t.count; ++n) tap_block[n] = to + ((y + t.offset[n]) % trows) * tblocks * tb;
    float8 sum[4] = {(float8)(0.0f), (float8)(0.0f), (float8)(0.0f), (float8)(0.0f)}, central[4];
    int ci = 0;
    for (int p = 0; p < pairs; ++p)
        for (int q = -(pairs - 1); q < pairs; ++q) {
            if (p == 0 && q < 0) continue;
            /* a component without amplitude adds nothing: skipped where no lane has one (the
             * shadows' plain pixels, AAF's far rule, have amplitude in the central one only:
             * 90% of the combined bench's work items), and its lanes left out by select
             * elsewhere, so that a non-finite sum of it is not read, as in the reference */
            float8 m = (ci == 0 ? 1.0f : 2.0f) * amp[p] * amp[q < 0 ? -q : q];
            int8 used = m != 0.0f;
            if (ci != 0 && !any(used)) {
                ++ci;
                continue;
            }
            float8 r0 = 0.0f, r1 = 0.0f, r2 = 0.0f, r3 = 0.0f; /* as maaf_rows: registers */
            for (int n = 0; n < t.count; ++n) {
                float8 wr, wi;
                tap_weight(&t, n, pairs, p, q, &wr, &wi);
                __global const float *s = tp + tap_block[n] + 64 * ci;
                float8 y0 = vload8(0, s), y1 = vload8(1, s), y2 = vload8(2, s), y3 = vload8(3, s), z0 = vload8(4, s),
                       z1 = vload8(5, s), z2 = vload8(6, s), z3 = vload8(7, s);
                if (t.guard[n]) {
                    int8 ok = t.ok[n];
                    y0 = select(0.0f, y0, ok), y1 = select(0.0f, y1, ok), y2 = select(0.0f, y2, ok);
                    y3 = select(0.0f, y3, ok), z0 = select(0.0f, z0, ok), z1 = select(0.0f, z1, ok);
                    z2 = select(0.0f, z2, ok), z3 = select(0.0f, z3, ok);
                }
                r0 += wr * y0 - wi * z0;
                r1 += wr * y1 - wi * z1;
                r2 += wr * y2 - wi * z2;
                r3 += wr * y3 - wi * z3;
            }
            sum[0] += select(0.0f, m * r0, used), sum[1] += select(0.0f, m * r1, used);
            sum[2] += select(0.0f, m * r2, used), sum[3] += select(0.0f, m * r3, used);
            if (ci == 0) central[0] = r0, central[1] = r1, central[2] = r2, central[3] = r3;
            ++ci;
        }
    float sr[8], sg[8], sb[8], sw[8], cr[8], cg[8], cb[8], cw[8], a0[8], rad[8];
    vstore8(sum[0], 0, sr);
    vstore8(sum[1], 0, sg);
    vstore8(sum[2], 0, sb);
    vstore8(sum[3], 0, sw);
    vstore8(central[0], 0, cr);
    vstore8(central[1], 0, cg);
    vstore8(central[2], 0, cb);
    vstore8(central[3], 0, cw);
    vstore8(amp[0], 0, a0);
    vstore8(c.rad, 0, rad);
    for (int l = 0; l < lanes; ++l) {
        float4 o = (float4)(0.0f);
        if (rad[l] < 0.0f)
            ; /* not filtered */
        else if (sw[l] > MAAF_MIN_WEIGHT_FRACTION * a0[l] * a0[l] * cw[l] && sw[l] > 0.0f)
            o = (float4)(sr[l] / sw[l], sg[l] / sw[l], sb[l] / sw[l], 1.0f);
        else if (cw[l] > 0.0f)
            o = (float4)(cr[l] / cw[l], cg[l] / cw[l], cb[l] / cw[l], 2.0f);
        out4[i0 + l] = o;
    }
}
