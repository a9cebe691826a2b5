/* FSF (fast 4D sheared filtering, seeds/000) kernels: the four 1D passes of eqs. 12-15 and
 * the per-pixel tap tables they gather through. One work-item per pixel everywhere. The C
 * version of every kernel is in fsf_filter.c (same arithmetic; the tests compare them); see
 * fsf_filter.h for the coordinates, the shear and the density correction.
 *
 * Buffers (host layout in fsf_cl.c):
 *   count       samples per pixel; y: 2 floats per slot (light metres along u, v); value: 3
 *   px          8 floats per pixel (FsfPixel): dir1 (2), dir2 (2), eta (2), sigma (2)
 *   pos4, nrm4  the guides; usable: 1 byte per pixel. A pixel that is not usable is nobody's
 *               neighbour and its result is discarded by the host, so every pass skips it: no
 *               taps, no slots in the tables, nothing in P, G or Q; its output is 0 (the C
 *               passes and the oracle give the same)
 *   n_taps      taps per pixel; tap_off: the pixel's first slot in the tables below (its slots:
 *               2 r + 2 rounded up to whole float8, r its unmasked radius, fsf_cl.c tap_offsets);
 *               tap_node: an int per slot (-1: no tap), q J + j0 along the first axis, q
 *               FSF_NODE_STRIDE2 + j0 along the second (q the neighbour's pixel in its ring, j0 its
 *               node: pass 2b takes them apart by a shift and a mask, not a division by J);
 *               tap_a0, tap_a1: the weights of nodes j0
 *               and j0 + 1, a float per slot each
 *   cum1        along the first axis, the running sums of its tap weights at the same slots
 *   P           J * 4 floats per pixel (J shift nodes) and y2 bin of the launch (C of them,
 *               interleaved: see fsf_pass1a) of a ring of `ring` image rows (row y at y % ring):
 *               pass 1 runs in bands of rows, so P never holds the whole frame
 *   Q           FSF_Q_FLOATS(B, geo) floats per pixel of a ring of image rows (pass 2 runs in bands
 *               too): each bin's 4 sums over its marginal, then the marginals clamped to the bins
 *               for the bin offsets -B .. 2 B + 7 (fsf_pass2a); G: B * 4 floats per pixel (B y2
 *               bins, whole frame) */

#define FSF_RADIUS_CAP_PX 16
#define FSF_TAPS (2 * FSF_RADIUS_CAP_PX + 1)
#define FSF_TAP_SLOTS 40 /* FSF_TAPS rounded up to whole float8: the most slots a pixel has */
#define FSF_CUM (2 * FSF_RADIUS_CAP_PX + 2)
#define FSF_MAX_Y2_BINS 64
#define FSF_NODE_SHIFT2 7 /* FSF_NODE_STRIDE2 = 128 >= J = B + 1 <= FSF_MAX_Y2_BINS + 1 */
#define FSF_NODE_STRIDE2 (1 << FSF_NODE_SHIFT2)
/* Q's floats per pixel: 4 B sums, then with form 4 3 B + 8 marginals (fsf_filter.h's
 * FSF_Q2_CL_FLOATS mirrors this for fsf_cl.c, which sizes Q for them); without it pass 2b reads no marginal and a pixel's Q is its 4 B sums, 5 B apart as in
 * the C passes */
#define FSF_Q_FLOATS(B, geo) ((geo) ? 7 * (B) + 8 : 5 * (B))

typedef struct {
    float half1, half2;  /* L1, L2 */
    int J, B;            /* shift nodes, y2 bins */
    float cos_normal_min, plane_tol_rel;
    int width, height;
    float prof1, prof2;  /* the box profile's half extents (FsfGrid.profile_half) */
    int geo;             /* 1: passes 1a, 2a weight by the light's geometric term (form 4, fsf_geo_term.h) */
    float lc[3], lu[3], lv[3], ln[3]; /* the light's frame (world): centre, axes u, v, normal */
    float reach;         /* FsfGrid.reach_sigmas */
    float ramp1, ramp2;  /* FsfGrid.ramp_m: a moving light's density ramps (0: the box) */
    float geo_w1[8];     /* geo_swept: the z1 midpoints' weights of form 4's marginals (fsf_geo_swept_weights) */
    int geo_swept;       /* 1: form 4's light ramps along z1 (FsfGeoTerm.ramp_m[0] > 0) */
} FsfArgs;

/* fsf_tap_radius (fsf_filter.c) */
static int fsf_radius(float sigma, float reach)
{
    if (!(sigma > 0.0f)) return 0;
    float r = ceil(reach * sigma);
    return r < (float)FSF_RADIUS_CAP_PX ? (int)r : FSF_RADIUS_CAP_PX;
}

static int fsf_bin2(float y2, float half2, int B)
{
    int b = (int)floor((y2 + half2) / (2.0f * half2) * (float)B);
    return b < 0 ? 0 : b >= B ? B - 1 : b;
}

#define FSF_LANES8 (int8)(0, 1, 2, 3, 4, 5, 6, 7)
/* p[k.s0], ..., p[k.s7] */
#define FSF_GATHER8(p, k)                                                                                  \
    (float8)((p)[(k).s0], (p)[(k).s1], (p)[(k).s2], (p)[(k).s3], (p)[(k).s4], (p)[(k).s5], (p)[(k).s6], \
             (p)[(k).s7])

/* fsf_gauss at 8 taps */
static float8 fsf_gauss8(float8 t, float sigma)
{
    return sigma > 0.0f ? exp(-0.5f * t * t / (sigma * sigma)) : (float8)(1.0f);
}

/* fsf_density_mean (fsf_filter.c): the mean over the profile box |z| <= h of the density of
 * the filter (eta, sigma), from the taps' weights g[t + r] that fsf_taps has already taken
 * (fsf_gauss8's vector exp: the scalar exp per tap it once took differs from it in the last
 * bit only, relMSE 1e-17 on the bench scenes, and was a fifth of the kernel). */
static float fsf_density_mean(float eta, int r, const float *g, float half_m, float prof)
{
    float sum = 0.0f;
    for (int t = -r; t <= r; ++t) {
        float c = eta * (float)t, lo = fmax(-prof, c - half_m), hi = fmin(prof, c + half_m);
        if (hi > lo) sum += g[t + r] * (hi - lo);
    }
    return sum / (2.0f * prof);
}

/* Each pixel's taps along one axis (fsf_taps, fsf_filter.c), 8 at a time (PoCL gives one work
 * item one SIMD lane; float8 fills the unit): n_taps = 2 r + 1 entries from t = -r on, from the
 * pixel's slot tap_off on (node -1: no tap). Along axis 0 also cum1 (fsf_tap_prefix). A pixel
 * that is not usable gets no taps (n_taps 0) and has no slots.
 * The nodes index a ring of `ring` image rows (neighbour row qy at qy % ring: P's for axis 0,
 * Q's for axis 1; ring = height: the whole frame); a tap more than `halo` rows away, which the
 * host's halo (band_halo_rows) rules out up to FSF_RADIUS_CAP_PX, the most a unit direction
 * reaches, is dropped rather than read from a stale row. */
__kernel void fsf_taps(const FsfArgs a, const int axis, const int ring, const int halo, const int guided, __global const float *px, __global const float *pos4,
                       __global const float *nrm4, __global const uchar *usable, __global const int *tap_off, __global int *n_taps,
                       __global int *tap_node, __global float *tap_a0, __global float *tap_a1, __global float *cum1)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height) return;
    if (!usable[i]) { /* skipped by every pass: see the buffers above */
        n_taps[i] = 0;
        return;
    }
    __global const float *pp = px + 8 * i;
    float dx = pp[2 * axis], dy = pp[2 * axis + 1], eta = pp[4 + axis], sigma = pp[6 + axis];
    int x = i % a.width, y = i / a.width, J = a.J;
    float half_m = axis == 0 ? a.half1 : a.half2;
    float inv_dY = 1.0f / (4.0f * half_m / (float)(J - 1)), mid = 0.5f * (float)(J - 1);
    int r = fsf_radius(sigma, a.reach);
    n_taps[i] = 2 * r + 1;
    /* the taps' Gaussian weights, t = -r .. r, once for their weights and (axis 0) the running
     * sums (lanes past 2 r + 1: computed, never read) */
    float g[FSF_TAP_SLOTS];
    for (int e0 = 0; e0 < 2 * r + 1; e0 += 8) vstore8(fsf_gauss8(convert_float8((int8)(e0 - r) + FSF_LANES8), sigma), 0, g + e0);
    /* along the first axis, this pixel's mean density in place of each neighbour's (cum1 below
     * divides pass 1a's by its own): fsf_filter.h, fsf_density_mean */
    float inv_mean = axis == 0 ? 1.0f / fsf_density_mean(eta, r, g, a.half1, a.prof1) : 1.0f;
    /* the centre's guides (fsf_accept); without guides (guided 0: FsfGuides' NULL pos4, nrm4)
     * every usable neighbour is accepted and pos4, nrm4 are not read */
    float c_nx = 0.0f, c_ny = 0.0f, c_nz = 0.0f, c_px = 0.0f, c_py = 0.0f, c_pz = 0.0f, c_tol = 0.0f;
    if (guided) {
        c_nx = nrm4[4 * i], c_ny = nrm4[4 * i + 1], c_nz = nrm4[4 * i + 2];
        c_px = pos4[4 * i], c_py = pos4[4 * i + 1], c_pz = pos4[4 * i + 2];
        c_tol = a.plane_tol_rel * pos4[4 * i + 3];
    }
    for (int e0 = 0; e0 < 2 * r + 1; e0 += 8) {
        int8 ti = (int8)(e0 - r) + FSF_LANES8;
        float8 tf = convert_float8(ti);
        int8 qx = x + convert_int8(floor(tf * dx + 0.5f)), qy = y + convert_int8(floor(tf * dy + 0.5f));
        int8 ok = (ti <= r) & (qx >= 0) & (qy >= 0) & (qx < a.width) & (qy < a.height), in_frame = ok;
        int8 q = select((int8)(i), qy * a.width + qx, ok);
        /* fsf_accept for t != 0: usable, normal within the cone, on the centre's plane */
        int8 use = (int8)(usable[q.s0], usable[q.s1], usable[q.s2], usable[q.s3], usable[q.s4], usable[q.s5],
                          usable[q.s6], usable[q.s7]);
        int8 near = (int8)(-1);
        if (guided) {
            /* each neighbour's normal and position as one float4 load each, then taken apart
             * into lanes: the same values as six gathers of their x, y, z */
            int qa[8];
            vstore8(q, 0, qa);
            float4 n0 = vload4(qa[0], nrm4), n1 = vload4(qa[1], nrm4), n2 = vload4(qa[2], nrm4), n3 = vload4(qa[3], nrm4);
            float4 n4 = vload4(qa[4], nrm4), n5 = vload4(qa[5], nrm4), n6 = vload4(qa[6], nrm4), n7 = vload4(qa[7], nrm4);
            float4 p0 = vload4(qa[0], pos4), p1 = vload4(qa[1], pos4), p2 = vload4(qa[2], pos4), p3 = vload4(qa[3], pos4);
            float4 p4 = vload4(qa[4], pos4), p5 = vload4(qa[5], pos4), p6 = vload4(qa[6], pos4), p7 = vload4(qa[7], pos4);
            float8 nx = (float8)(n0.x, n1.x, n2.x, n3.x, n4.x, n5.x, n6.x, n7.x);
            float8 ny = (float8)(n0.y, n1.y, n2.y, n3.y, n4.y, n5.y, n6.y, n7.y);
            float8 nz = (float8)(n0.z, n1.z, n2.z, n3.z, n4.z, n5.z, n6.z, n7.z);
            float8 px8 = (float8)(p0.x, p1.x, p2.x, p3.x, p4.x, p5.x, p6.x, p7.x);
            float8 py8 = (float8)(p0.y, p1.y, p2.y, p3.y, p4.y, p5.y, p6.y, p7.y);
            float8 pz8 = (float8)(p0.z, p1.z, p2.z, p3.z, p4.z, p5.z, p6.z, p7.z);
            float8 cosn = c_nx * nx + c_ny * ny + c_nz * nz;
            float8 off = c_nx * (px8 - c_px) + c_ny * (py8 - c_py) + c_nz * (pz8 - c_pz);
            near = (q == i) | ((cosn >= a.cos_normal_min) & (fabs(off) <= c_tol));
        }
        ok &= (ti == 0) | ((use != 0) & near);
        float8 f = -eta * tf * inv_dY + mid;
        ok &= (f >= 0.0f) & (f <= (float)(J - 1));
        ok &= abs(qy - y) <= halo;
        f = select((float8)(0.0f), f, ok);
        int8 j0 = min(convert_int8(floor(f)), J - 2);
        float8 b = f - convert_float8(j0), wt = vload8(0, g + e0) * inv_mean;
        int o = tap_off[i] + e0;
        /* q's pixel in the ring: q's row is y + dy (|dy| <= halo < ring where the tap is kept, the
         * node of a dropped one is not used), so its ring row is y's wrapped once; q / width %
         * ring and q % width in integers, without a vector division (24 scalar ones) */
        int8 dyq = select((int8)(0), qy - y, in_frame), ry = (int8)(y % ring) + dyq;
        ry = select(ry, ry + ring, ry < 0), ry = select(ry, ry - ring, ry >= ring);
        int8 qp = ry * a.width + select((int8)(x), qx, in_frame);
        vstore8(select((int8)(-1), qp * (axis == 0 ? J : FSF_NODE_STRIDE2) + j0, ok), 0, tap_node + o);
        vstore8(select((float8)(0.0f), wt * (1.0f - b), ok), 0, tap_a0 + o);
        vstore8(select((float8)(0.0f), wt * b, ok), 0, tap_a1 + o);
    }
    if (axis == 0) { /* the running sums of the weights (g: sigma is pp[6] along this axis) */
        __global float *cum = cum1 + tap_off[i];
        float c = 0.0f;
        cum[0] = c;
        for (int e = 0; e < 2 * r + 1; ++e) cum[e + 1] = c = c + g[e];
        for (int e = 0; e < 2 * r + 2; ++e) cum[e] *= inv_mean; /* fsf_tap_prefix_mean */
    }
}

/* Each sample slot's y2 bin, once for the 16 slices of pass 1a (usable pixels only). */
__kernel void fsf_bins(const FsfArgs a, const int capacity, __global const int *count, __global const float *ys,
                       __global const uchar *usable, __global uchar *bin2)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height || !usable[i]) return;
    int k = 0, n_k = count[i];
    /* eight slots at a time (fsf_bin2's operations lane by lane: the same bins), then the rest */
    for (; k + 8 <= n_k; k += 8) {
        float8 y2 = vload16(0, ys + 2 * (i * capacity + k)).odd;
        int8 b = convert_int8(floor((y2 + a.half2) / (2.0f * a.half2) * (float)a.B));
        vstore8(convert_uchar8(clamp(b, 0, a.B - 1)), 0, bin2 + i * capacity + k);
    }
    for (; k < n_k; ++k) bin2[i * capacity + k] = (uchar)fsf_bin2(ys[2 * (i * capacity + k) + 1], a.half2, a.B);
}

/* fsf_density at 8 light coordinates at once (PoCL runs one work item's scalar code on one
 * SIMD lane; a float8 fills the vector unit): the same arithmetic lane by lane. Defined for
 * running sums in private memory (pass 2b makes its own) and in global memory (pass 1a reads
 * fsf_taps' cum1 in place rather than copy it once per launch). */
#define FSF_DEFINE_DENSITY8(name, space)                                                                   \
    static float8 name(float8 z, float eta, float half_m, int r, space const float *cum)                   \
    {                                                                                                       \
        float8 lo = (float8)(-(float)r), hi = (float8)((float)r);                                         \
        if (eta != 0.0f) {                                                                                  \
            float inv_eta = 1.0f / eta; /* a product per lane, not a division (fsf_density) */              \
            float8 a = (z - half_m) * inv_eta, b = (z + half_m) * inv_eta;                                  \
            lo = fmax(lo, ceil(fmin(a, b))), hi = fmin(hi, floor(fmax(a, b)));                              \
        } else { /* no shear: every tap or none */                                                          \
            hi = select(hi, (float8)(-1.0f - (float)r), fabs(z) > half_m);                                  \
        }                                                                                                   \
        int8 none = isless(hi, lo);                                                                         \
        /* clamped before the conversion: a lane left out may hold +-inf (eta near 0) */                    \
        int8 ih = convert_int8(clamp(hi, -(float)r, (float)r)) + (r + 1),                                   \
             il = convert_int8(clamp(lo, -(float)r, (float)r)) + r;                                         \
        float8 rho = FSF_GATHER8(cum, ih) - FSF_GATHER8(cum, il);                                           \
        return select(rho, (float8)(0.0f), none);                                                           \
    }
FSF_DEFINE_DENSITY8(fsf_density8, __private)
FSF_DEFINE_DENSITY8(fsf_density8_global, __global)

/* fsf_swept_weight (fsf_filter.c) at 8 light coordinates: a moving light's profile
 * T(z) = clamp((L - |z|) / ramp, 0, 1) over the density of reprojected samples
 * rho(z) = sum_t w(t) T(z - eta t), w(t) the running sums' steps; 0 where either is 0. */
static float8 fsf_swept_profile8(float8 z, float half_m, float ramp)
{
    return clamp((half_m - fabs(z)) / ramp, 0.0f, 1.0f);
}
#define FSF_DEFINE_SWEPT8(name, space)                                                                     \
    static float8 name(float8 z, float eta, float half_m, float ramp, int r, space const float *cum)       \
    {                                                                                                       \
        float8 rho = (float8)(0.0f);                                                                        \
        for (int t = -r; t <= r; ++t)                                                                       \
            rho += (cum[t + r + 1] - cum[t + r]) * fsf_swept_profile8(z - eta * (float)t, half_m, ramp);    \
        float8 prof = fsf_swept_profile8(z, half_m, ramp);                                                  \
        return select((float8)(0.0f), prof / rho, (prof > 0.0f) & (rho > 0.0f));                           \
    }
FSF_DEFINE_SWEPT8(fsf_swept8, __private)
FSF_DEFINE_SWEPT8(fsf_swept8_global, __global)

/* fsf_geo_G (fsf_geo_term.c) at 8 light points (z1, y2) from the receiver point p, normal n */
static float8 fsf_geo_G8(const FsfArgs *a, float3 p, float3 n, float8 z1, float y2)
{
    float8 l0 = a->lc[0] + z1 * a->lu[0] + y2 * a->lv[0] - p.x;
    float8 l1 = a->lc[1] + z1 * a->lu[1] + y2 * a->lv[1] - p.y;
    float8 l2 = a->lc[2] + z1 * a->lu[2] + y2 * a->lv[2] - p.z;
    float8 d2 = l0 * l0 + l1 * l1 + l2 * l2, inv_d = 1.0f / sqrt(d2);
    float8 cos_r = (l0 * n.x + l1 * n.y + l2 * n.z) * inv_d;
    float8 cos_l = fabs(l0 * a->ln[0] + l1 * a->ln[1] + l2 * a->ln[2]) * inv_d;
    return select((float8)(0.0f), cos_r * cos_l / d2, (d2 > 0.0f) & (cos_r > 0.0f));
}

/* fsf_geo_G8 with y2 per lane: its products with the light's v axis on their own, as in
 * fsf_geo_G8, where y2 is a scalar whose product is not fused into the vector sum (a vector
 * product inside the sum would be): the same floats lane by lane */
static float8 fsf_geo_G8y(const FsfArgs *a, float3 p, float3 n, float8 z1, float8 y2)
{
    float8 v0 = y2 * a->lv[0], v1 = y2 * a->lv[1], v2 = y2 * a->lv[2];
    float8 l0 = a->lc[0] + z1 * a->lu[0] + v0 - p.x;
    float8 l1 = a->lc[1] + z1 * a->lu[1] + v1 - p.y;
    float8 l2 = a->lc[2] + z1 * a->lu[2] + v2 - p.z;
    float8 d2 = l0 * l0 + l1 * l1 + l2 * l2, inv_d = 1.0f / sqrt(d2);
    float8 cos_r = (l0 * n.x + l1 * n.y + l2 * n.z) * inv_d;
    float8 cos_l = fabs(l0 * a->ln[0] + l1 * a->ln[1] + l2 * a->ln[2]) * inv_d;
    return select((float8)(0.0f), cos_r * cos_l / d2, (d2 > 0.0f) & (cos_r > 0.0f));
}

/* fsf_geo_marginal (fsf_geo_term.c): G's mean over 8 midpoints in z1 at y2, summed in its order */
static float fsf_geo_marginal(const FsfArgs *a, float3 p, float3 n, float y2)
{
    const float8 lane = (float8)(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f);
    float8 z1 = a->half1 * (2.0f * (lane + 0.5f) / 8.0f - 1.0f), g = fsf_geo_G8(a, p, n, z1, y2);
    if (a->geo_swept) { /* a swept light: weighted by its samples' density along z1 */
        float8 w = vload8(0, a->geo_w1), wg = w * g;
        return (wg.s0 + wg.s1 + wg.s2 + wg.s3 + wg.s4 + wg.s5 + wg.s6 + wg.s7) /
               (w.s0 + w.s1 + w.s2 + w.s3 + w.s4 + w.s5 + w.s6 + w.s7);
    }
    return (g.s0 + g.s1 + g.s2 + g.s3 + g.s4 + g.s5 + g.s6 + g.s7) / 8.0f;
}

/* fsf_geo_marginal at the B bin centres y2 (B <= FSF_MAX_Y2_BINS; gm holds B rounded up to 8),
 * eight bins at once: for each z1 midpoint G over eight bins (fsf_geo_G8y), each bin's eight
 * terms summed in z1's order as fsf_geo_marginal's one float8 does lane by lane, so the same
 * floats without its horizontal sum per bin */
static void fsf_geo_marginals(const FsfArgs *a, float3 p, float3 n, float L2, int B, float *gm)
{
    const float8 lane = (float8)(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f);
    float z1s[8], y2s[FSF_MAX_Y2_BINS + 8];
    vstore8(a->half1 * (2.0f * (lane + 0.5f) / 8.0f - 1.0f), 0, z1s);
    for (int b = 0; b < B; ++b) y2s[b] = 2.0f * L2 / (float)B * ((float)b + 0.5f - 0.5f * (float)B);
    for (int b = B; b < (B + 7) / 8 * 8; ++b) y2s[b] = 0.0f; /* lanes past B: computed, never read */
    for (int b0 = 0; b0 < B; b0 += 8) {
        float8 y2 = vload8(0, y2s + b0), sum = (float8)(0.0f);
        if (a->geo_swept) { /* a swept light: each z1 by its samples' density (fsf_geo_marginal) */
            float weights = 0.0f;
            for (int k = 0; k < 8; ++k) {
                float w = a->geo_w1[k];
                sum += w * fsf_geo_G8y(a, p, n, (float8)(z1s[k]), y2), weights += w;
            }
            vstore8(sum / weights, 0, gm + b0);
            continue;
        }
        for (int k = 0; k < 8; ++k) {
            float8 g = fsf_geo_G8y(a, p, n, (float8)(z1s[k]), y2);
            sum = k == 0 ? g : sum + g;
        }
        vstore8(sum / 8.0f, 0, gm + b0);
    }
}

/* Pass 1a for the y2 bins bin0 .. bin0 + C - 1 (fsf_pass1a, eq. 12) over the image rows
 * row0 .. row1 - 1 (one work item per pixel of the launch), one slice of P each, interleaved:
 * node n of slice c at float4 n * C + c (node n = J * pixel + j, pixel (x, y) at row y % ring),
 * so that pass 1b's tap reads the C slices' values of a node from one or two cache lines
 * instead of C places a slice apart. A sample's shift nodes 8 at a time. Several bins per launch share each work item's set-up (radius, running sums, the scan
 * of its slots). */
__kernel void fsf_pass1a(const FsfArgs a, const int bin0, const int C, const int capacity, const int row0,
                         const int row1, const int ring, __global const int *count, __global const float *ys,
                         __global const uchar *bin2, __global const float *value, __global const float *px,
                         __global const uchar *usable, __global const int *tap_off, __global const float *cum1,
                         __global const float *pos4, __global const float *nrm4, __global const float *mean_g,
                         __global float *P)
{
    int i = row0 * a.width + get_global_id(0);
    if (i >= row1 * a.width) return; /* the launch's rows only: the ring's others are in use */
    if (!usable[i]) return;          /* no tap reads its nodes (fsf_taps) */
    int J = a.J;
    float dY = 4.0f * a.half1 / (float)(J - 1), L1 = a.half1, mid = 0.5f * (float)(J - 1);
    int ip = (i / a.width % ring) * a.width + i % a.width; /* the pixel's place in P's ring */
    int r = fsf_radius(px[8 * i + 6], a.reach);
    float eta = px[8 * i + 4];
    __global const float *cum = cum1 + tap_off[i];
    /* the running sums' first and last lines asked for before the clear of P below, which
     * takes long enough to hide their fetch: each launch of a band reads them afresh, and the
     * density's first gather waited on them (fsf_taps wrote them a pass before; PoCL's own
     * prefetch() is empty, clang's builtin emits the instruction) */
    __builtin_prefetch(cum);
    __builtin_prefetch(cum + 2 * r + 1);
    for (int e = 0; e < J * C; ++e) vstore4((float4)(0.0f), J * C * ip + e, P);
    /* eta = 0 (no shear) or r = 0 (one tap): fsf_density8's range is every tap at each node
     * the box keeps (|z| <= prof1 <= L1; for r = 0 the signs of z -+ L1 are exact), so its
     * difference of running sums is this one, the same float, without its two gathers */
    int rho_all = (eta == 0.0f || r == 0) && !(a.ramp1 > 0.0f); /* a swept light: fsf_swept8 */
    float rho_c = rho_all ? cum[2 * r + 1] - cum[0] : 0.0f;
    const float8 lane = (float8)(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f);
    /* form 4 (fsf_geo_term.h): the pixel's mean position, normal and mean term; 0: none */
    float g_mean = a.geo ? mean_g[i] : 0.0f;
    float3 gp = (float3)(0.0f), gn = (float3)(0.0f);
    if (g_mean > 0.0f) gp = vload3(0, pos4 + 4 * i), gn = vload3(0, nrm4 + 4 * i);
    /* the launch's bins' samples, listed 64 slots at a time without a branch per slot (which
     * of them fall in the launch's bins is unpredictable), then taken in k's order */
    int n_k = count[i];
    uchar pick[64];
    for (int k0 = 0; k0 < n_k; k0 += 64) {
        int n_pick = 0;
        for (int k = k0; k < min(n_k, k0 + 64); ++k) {
            pick[n_pick] = (uchar)(k - k0);
            n_pick += (uint)((int)bin2[i * capacity + k] - bin0) < (uint)C;
        }
        for (int kp = 0; kp < n_pick; ++kp) {
            int slot = i * capacity + k0 + pick[kp], c = (int)bin2[slot] - bin0;
            __global float *Pi = P + 4 * (J * C * ip + c); /* node s at Pi + 4 C s */
            float y1 = ys[2 * slot];
            float4 v = (float4)(value[3 * slot], value[3 * slot + 1], value[3 * slot + 2], 1.0f);
            float y2 = ys[2 * slot + 1];
            /* the sample's own term at y (0: form 4 leaves the sample as it is) */
            float g_y = g_mean > 0.0f ? fsf_geo_G8(&a, gp, gn, (float8)(y1), y2).s0 : 0.0f;
            int j0 = (int)ceil((y1 - L1) / dY + mid), j1 = (int)floor((y1 + L1) / dY + mid);
            if (j0 < 0) j0 = 0;
            if (j1 > J - 1) j1 = J - 1;
            for (int s0 = j0; s0 <= j1; s0 += 8) {
                float8 z = y1 - ((float8)((float)s0) + lane - mid) * dY;
                /* no shear or a single tap: every node the box keeps sees all taps */
                float8 wk;
                if (a.ramp1 > 0.0f) { /* a swept light: T(z) / rho(z), inside the box */
                    wk = select((float8)(0.0f), fsf_swept8_global(z, eta, L1, a.ramp1, r, cum), fabs(z) <= a.prof1);
                } else {
                    float8 rho = rho_all ? (float8)(rho_c) : fsf_density8_global(z, eta, L1, r, cum);
                    /* the box (rounding at the light's ends) and an empty density leave a node out */
                    wk = select((float8)(0.0f), 1.0f / rho, (fabs(z) <= a.prof1) & (rho > 0.0f));
                }
                float8 wv = wk, ww = wk;
                if (g_y > 0.0f) { /* form 4: rgb times g(z) / g(y), weight times g(z) / mean */
                    float8 g_z = fsf_geo_G8(&a, gp, gn, z, y2);
                    wv = wk * (g_z / g_y), ww = wk * (g_z / g_mean);
                }
                float w[8], wd[8];
                int nl = min(8, j1 - s0 + 1);
                vstore8(select((float8)(0.0f), wv, lane < (float)nl), 0, w);
                vstore8(select((float8)(0.0f), ww, lane < (float)nl), 0, wd);
                if (s0 + 8 <= J) { /* all eight nodes inside the pixel's: no branch (a weight 0 adds an exact 0) */
                    for (int l = 0; l < 8; ++l)
                        vstore4(vload4(C * (s0 + l), Pi) + (float4)(w[l] * v.xyz, wd[l]), C * (s0 + l), Pi);
                } else {
                    for (int l = 0; l < nl; ++l)
                        if (w[l] != 0.0f || wd[l] != 0.0f)
                            vstore4(vload4(C * (s0 + l), Pi) + (float4)(w[l] * v.xyz, wd[l]), C * (s0 + l), Pi);
                }
            }
        }
    }
}

/* One pixel's gather through its taps (passes 1b and 2b), in the order of t. */
static float4 fsf_gather(int i, __global const int *n_taps, __global const int *tap_off, __global const int *tap_node,
                         __global const float *tap_a0, __global const float *tap_a1, __global const float *F)
{
    float4 acc = (float4)(0.0f);
    int n = n_taps[i], o0 = tap_off[i];
    for (int e = 0; e < n; ++e) {
        int o = o0 + e, node = tap_node[o];
        if (node < 0) continue;
        acc += tap_a0[o] * vload4(node, F) + tap_a1[o] * vload4(node + 1, F);
    }
    return acc;
}

/* Pass 1b for the C <= 8 bins of pass 1a's launches (fsf_pass1b, eq. 13; fsf_cl.h's
 * FSF_CL_MAX_BINS_PER_LAUNCH) over the image rows row0 .. row1 - 1: each tap read once for all
 * of them, one accumulator a bin. The taps' nodes index P's ring; the C
 * slices' values of node n are the float4 n * C .. n * C + C - 1 (pass 1a). */
__kernel void fsf_pass1b(const FsfArgs a, const int bin0, const int C, const int row0, const int row1, const int ring,
                         __global const uchar *usable, __global const int *n_taps, __global const int *tap_off,
                         __global const int *tap_node, __global const float *tap_a0, __global const float *tap_a1,
                         __global const float *P, __global float *G)
{
    int i = row0 * a.width + get_global_id(0);
    if (i >= row1 * a.width || !usable[i]) return; /* its G is never read (pass 2a skips it) */
    float4 acc0 = (float4)(0.0f), acc1 = acc0, acc2 = acc0, acc3 = acc0, acc4 = acc0, acc5 = acc0, acc6 = acc0, acc7 = acc0;
    int n = n_taps[i], o0 = tap_off[i];
    for (int e = 0; e < n; ++e) {
        int o = o0 + e, node = tap_node[o];
        if (node < 0) continue;
        float a0 = tap_a0[o], a1 = tap_a1[o];
        int n0 = C * node, n1 = C * (node + 1);
        acc0 += a0 * vload4(n0, P) + a1 * vload4(n1, P);
        if (C > 1) acc1 += a0 * vload4(n0 + 1, P) + a1 * vload4(n1 + 1, P);
        if (C > 2) acc2 += a0 * vload4(n0 + 2, P) + a1 * vload4(n1 + 2, P);
        if (C > 3) acc3 += a0 * vload4(n0 + 3, P) + a1 * vload4(n1 + 3, P);
        if (C > 4) acc4 += a0 * vload4(n0 + 4, P) + a1 * vload4(n1 + 4, P);
        if (C > 5) acc5 += a0 * vload4(n0 + 5, P) + a1 * vload4(n1 + 5, P);
        if (C > 6) acc6 += a0 * vload4(n0 + 6, P) + a1 * vload4(n1 + 6, P);
        if (C > 7) acc7 += a0 * vload4(n0 + 7, P) + a1 * vload4(n1 + 7, P);
    }
    vstore4(acc0, a.B * i + bin0, G);
    if (C > 1) vstore4(acc1, a.B * i + bin0 + 1, G);
    if (C > 2) vstore4(acc2, a.B * i + bin0 + 2, G);
    if (C > 3) vstore4(acc3, a.B * i + bin0 + 3, G);
    if (C > 4) vstore4(acc4, a.B * i + bin0 + 4, G);
    if (C > 5) vstore4(acc5, a.B * i + bin0 + 5, G);
    if (C > 6) vstore4(acc6, a.B * i + bin0 + 6, G);
    if (C > 7) vstore4(acc7, a.B * i + bin0 + 7, G);
}

/* Pass 2a (fsf_pass2a) over the image rows row0 .. row1 - 1, into Q's ring of `ring` rows: each
 * bin over its form-4 marginal, then the marginals, gm[clamp(k - B, 0, B - 1)] for k = 0 .. 3 B + 7:
 * the bin offsets pass 2b reads eight at a time (-B .. 2 B + 7) clamped here once, so that its
 * reads are contiguous loads of the same values instead of gathers through clamped indices;
 * the density is pass 2b's, of the gathering pixel's filter. */
__kernel void fsf_pass2a(const FsfArgs a, const int row0, const int row1, const int ring, __global const uchar *usable,
                         __global const float *pos4, __global const float *nrm4, __global const float *mean_g,
                         __global const float *G, __global float *Q)
{
    int i = row0 * a.width + get_global_id(0);
    if (i >= row1 * a.width) return; /* the launch's rows only: the ring's others are in use */
    if (!usable[i]) return;          /* no tap reads it (fsf_taps) */
    int iq = (i / a.width % ring) * a.width + i % a.width; /* the pixel's place in Q's ring */
    int B = a.B;
    __global float *gs = Q + FSF_Q_FLOATS(B, a.geo) * iq, *gmq = gs + 4 * B;
    float gm[FSF_MAX_Y2_BINS + 8];
    int geo = a.geo && mean_g[i] > 0.0f;
    if (geo) {
        float3 gp = vload3(0, pos4 + 4 * i), gn = vload3(0, nrm4 + 4 * i);
        fsf_geo_marginals(&a, gp, gn, a.half2, B, gm);
        for (int b = 0; geo && b < B; ++b) geo = gm[b] > 0.0f;
    }
    for (int b = 0; b < B; ++b) {
        float4 gi = vload4(B * i + b, G);
        if (!geo) gm[b] = 1.0f;
        else gi = gi / gm[b];
        vstore4(gi, b, gs);
    }
    for (int k = 0; a.geo && k < 3 * B + 8; ++k) gmq[k] = gm[clamp(k - B, 0, B - 1)]; /* read by 2b under form 4 only */
}

/* Pass 2b (fsf_pass2b, eqs. 14-15; B = J - 1: the density depends on m = b - 2 j only) over the
 * image rows row0 .. row1 - 1: the gathering pixel's 3 B densities 8 at a time, then per tap
 * its two nodes' sums over the bins of the pixel it reads in Q's ring (a pixel that is not
 * usable has no taps: 0). */
__kernel void fsf_pass2b(const FsfArgs a, const int row0, const int row1, __global const float *px,
                         __global const uchar *usable, __global const int *n_taps, __global const int *tap_off,
                         __global const int *tap_node, __global const float *tap_a0, __global const float *tap_a1,
                         __global const float *Q, __global float *out4)
{
    int i = row0 * a.width + get_global_id(0);
    if (i >= row1 * a.width) return;
    float4 acc = (float4)(0.0f);
    if (!usable[i]) {
        vstore4(acc, i, out4);
        return;
    }
    int B = a.B;
    float L2 = a.half2;
    float sigma = px[8 * i + 7], eta = px[8 * i + 5];
    int r = fsf_radius(sigma, a.reach);
    float cum[FSF_CUM], g[FSF_TAP_SLOTS], inv_rho[3 * FSF_MAX_Y2_BINS + 8];
    for (int e0 = 0; e0 < 2 * r + 1; e0 += 8) vstore8(fsf_gauss8(convert_float8((int8)(e0 - r) + FSF_LANES8), sigma), 0, g + e0);
    float c = 0.0f;
    cum[0] = c;
    for (int e = 0; e < 2 * r + 1; ++e) cum[e + 1] = c = c + g[e];
    /* the span of m with a nonzero weight (lanes past 3 B hold 0 below), found eight at a time */
    int8 m_lo8 = (int8)(3 * B), m_hi8 = (int8)(-1);
    for (int m0 = -2 * B; m0 < B; m0 += 8) {
        float8 z = 2.0f * L2 / (float)B * (convert_float8((int8)(m0) + FSF_LANES8) + 0.5f * (float)B + 0.5f);
        int8 inbox = fabs(z) <= a.prof2;
        float8 w = (float8)(0.0f);
        /* the box keeps about B of the 3 B coordinates: the densities of eight outside it are
         * not needed, their weight is 0 anyway */
        if (any(inbox) && a.ramp2 > 0.0f) { /* a swept light: T(z) / rho(z) */
            w = select((float8)(0.0f), fsf_swept8(z, eta, L2, a.ramp2, r, cum), inbox);
        } else if (any(inbox)) {
            float8 rho = fsf_density8(z, eta, L2, r, cum);
            w = select((float8)(0.0f), 1.0f / rho, inbox & (rho > 0.0f));
        }
        vstore8(w, 0, inv_rho + m0 + 2 * B); /* past 3 B (B not a multiple of 8): weight 0 */
        int8 m = (int8)(m0 + 2 * B) + FSF_LANES8, live = (w != 0.0f) & (m < 3 * B);
        m_lo8 = min(m_lo8, select((int8)(3 * B), m, live)), m_hi8 = max(m_hi8, select((int8)(-1), m, live));
    }
    vstore8((float8)(0.0f), 0, inv_rho + 3 * B); /* the lanes past a tap's last bin read up to 3 B + 6 */
    /* the span of m with a nonzero weight: each node sums only the bins in it, in the same
     * order (those left out had weight 0, which the sum skips anyway) */
    int4 lo4 = min(m_lo8.lo, m_lo8.hi), hi4 = max(m_hi8.lo, m_hi8.hi);
    int2 lo2 = min(lo4.lo, lo4.hi), hi2 = max(hi4.lo, hi4.hi);
    int m_lo = min(lo2.x, lo2.y), m_hi = max(hi2.x, hi2.y);
    int n = n_taps[i], o0 = tap_off[i];
    for (int e = 0; e < n; ++e) {
        int o = o0 + e, node = tap_node[o];
        if (node < 0) continue;
        int q = node >> FSF_NODE_SHIFT2, j0 = node & (FSF_NODE_STRIDE2 - 1); /* fsf_taps' second axis */
        __global const float *gs = Q + FSF_Q_FLOATS(B, a.geo) * q, *gm = gs + 4 * B; /* gm[B + o]: offset o */
        float a0 = tap_a0[o], a1 = tap_a1[o];
        /* the two nodes' sums interpolated, one weight per bin (fsf_pass2b): nodes j0 and
         * j0 + 1 see bin b at m0 = b - 2 j0 + 2 B and m0 - 2, so the bins of either span */
        int b_lo = max(0, m_lo - 2 * B + 2 * j0), b_hi = min(B - 1, m_hi - 2 * B + 2 * j0 + 2);
        /* eight bins' weights at once (their m are consecutive), then summed in b's order as
         * one bin at a time would: a zero 1 / rho makes its term an exact 0, which adds
         * nothing, so no branch per bin (the same floats as fsf_pass2b's) */
        for (int b0 = b_lo; b0 <= b_hi; b0 += 8) {
            int m00 = b0 - 2 * j0 + 2 * B; /* m0 of bin b0; <= 3 B + 6 with the lanes past b_hi */
            float8 w0 = vload8(0, inv_rho + m00), w1 = vload8(0, inv_rho + m00 - 2);
            float wk[8];
            if (a.geo) {
                /* the marginals of bins clamp(m - B) and clamp(m - 2 - B), m = m00 .. m00 + 7, from
                 * pass 2a's clamped table (m00 - B in 2 - B .. 2 B - 1: 0 <= b0, j0 < B) */
                float8 g0 = vload8(0, gm + m00), g1 = vload8(0, gm + m00 - 2);
                float8 t0 = a0 * w0 * g0;
                vstore8(t0 + a1 * w1 * g1, 0, wk);
            } else { /* without form 4 every marginal is 1 (pass 2a): the products by them are
                      * exact, and a1 w1 is rounded before the sum as a1 w1 g1 is (no fused
                      * multiply-add across statements): the same floats without the gathers */
                float8 t0 = a0 * w0, t1 = a1 * w1;
                vstore8(t0 + t1, 0, wk);
            }
            int nl = min(8, b_hi - b0 + 1);
            for (int l = 0; l < nl; ++l) acc += vload4(b0 + l, gs) * wk[l];
        }
    }
    vstore4(acc, i, out4);
}
