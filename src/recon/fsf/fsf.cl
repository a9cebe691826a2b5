/* FSF (fast 4D sheared filtering, seeds/000) kernels: the four 1D passes of eqs. 12-15 and
 * the per-pixel tap tables they gather through. One work-item per pixel everywhere. The C
 * version of every kernel is in fsf_filter.c (same arithmetic; the tests compare them); see
 * fsf_filter.h for the coordinates, the shear and the density correction.
 *
 * Buffers (host layout in fsf_cl.c):
 *   count       samples per pixel; y: 2 floats per slot (light metres along u, v); value: 3
 *   px          8 floats per pixel (FsfPixel): dir1 (2), dir2 (2), eta (2), sigma (2)
 *   pos4, nrm4  the guides; usable: 1 byte per pixel
 *   tap_node    FSF_TAPS ints per pixel (-1: no tap); tap_w: 2 floats per tap
 *   cum1        FSF_CUM floats per pixel: running sums of the first axis' tap weights
 *   P, Q        J * 4 floats per pixel (J shift nodes); G: B * 4 floats per pixel (B y2 bins) */

#define FSF_RADIUS_CAP_PX 16
#define FSF_TAPS (2 * FSF_RADIUS_CAP_PX + 1)
#define FSF_CUM (2 * FSF_RADIUS_CAP_PX + 2)
#define FSF_RADIUS_SIGMAS 2.0f
#define FSF_MAX_Y2_BINS 64

typedef struct {
    float half1, half2;  /* L1, L2 */
    int J, B;            /* shift nodes, y2 bins */
    float cos_normal_min, plane_tol_rel;
    int width, height;
    float prof1, prof2;  /* the box profile's half extents (FsfGrid.profile_half) */
} FsfArgs;

static int fsf_radius(float sigma)
{
    if (!(sigma > 0.0f)) return 0;
    float r = ceil(FSF_RADIUS_SIGMAS * sigma);
    return r < (float)FSF_RADIUS_CAP_PX ? (int)r : FSF_RADIUS_CAP_PX;
}

static float fsf_gauss(float t, float sigma) { return sigma > 0.0f ? exp(-0.5f * t * t / (sigma * sigma)) : 1.0f; }

static float fsf_box(float y, float half_m) { return fabs(y) <= half_m ? 1.0f : 0.0f; }

static int fsf_bin2(float y2, float half2, int B)
{
    int b = (int)floor((y2 + half2) / (2.0f * half2) * (float)B);
    return b < 0 ? 0 : b >= B ? B - 1 : b;
}

static float fsf_density(float z, float eta, float half_m, int r, __global const float *cum)
{
    float lo = -(float)r, hi = (float)r;
    if (eta != 0.0f) {
        float a = (z - half_m) / eta, b = (z + half_m) / eta;
        lo = fmax(lo, ceil(fmin(a, b))), hi = fmin(hi, floor(fmax(a, b)));
    } else if (!(fabs(z) <= half_m)) {
        return 0.0f;
    }
    if (hi < lo) return 0.0f;
    return cum[(int)hi + r + 1] - cum[(int)lo + r];
}

static float fsf_density_p(float z, float eta, float half_m, int r, const float *cum)
{
    float lo = -(float)r, hi = (float)r;
    if (eta != 0.0f) {
        float a = (z - half_m) / eta, b = (z + half_m) / eta;
        lo = fmax(lo, ceil(fmin(a, b))), hi = fmin(hi, floor(fmax(a, b)));
    } else if (!(fabs(z) <= half_m)) {
        return 0.0f;
    }
    if (hi < lo) return 0.0f;
    return cum[(int)hi + r + 1] - cum[(int)lo + r];
}

static bool fsf_accept(const FsfArgs a, __global const float *pos4, __global const float *nrm4,
                       __global const uchar *usable, int p, int q)
{
    if (!usable[q]) return false;
    if (q == p) return true;
    float3 np = vload3(0, nrm4 + 4 * p), nq = vload3(0, nrm4 + 4 * q);
    if (dot(np, nq) < a.cos_normal_min) return false;
    float3 pp = vload3(0, pos4 + 4 * p), pq = vload3(0, pos4 + 4 * q);
    return fabs(dot(np, pq - pp)) <= a.plane_tol_rel * pos4[4 * p + 3];
}

/* Each pixel's taps along one axis (fsf_taps); along axis 0 also its cum1 (fsf_tap_prefix). */
__kernel void fsf_taps(const FsfArgs a, const int axis, __global const float *px, __global const float *pos4,
                       __global const float *nrm4, __global const uchar *usable, __global int *tap_node,
                       __global float *tap_w, __global float *cum1)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height) return;
    __global const float *pp = px + 8 * i;
    float dx = pp[2 * axis], dy = pp[2 * axis + 1], eta = pp[4 + axis], sigma = pp[6 + axis];
    int x = i % a.width, y = i / a.width, J = a.J;
    float half_m = axis == 0 ? a.half1 : a.half2;
    float inv_dY = 1.0f / (4.0f * half_m / (float)(J - 1)), mid = 0.5f * (float)(J - 1);
    int r = usable[i] ? fsf_radius(sigma) : 0;
    for (int t = -FSF_RADIUS_CAP_PX; t <= FSF_RADIUS_CAP_PX; ++t) {
        int o = FSF_TAPS * i + t + FSF_RADIUS_CAP_PX;
        tap_node[o] = -1, tap_w[2 * o] = 0.0f, tap_w[2 * o + 1] = 0.0f;
        if (t < -r || t > r) continue;
        int qx = x + (int)floor((float)t * dx + 0.5f), qy = y + (int)floor((float)t * dy + 0.5f);
        if (qx < 0 || qy < 0 || qx >= a.width || qy >= a.height) continue;
        int q = qy * a.width + qx;
        if (t != 0 && !fsf_accept(a, pos4, nrm4, usable, i, q)) continue;
        float f = -eta * (float)t * inv_dY + mid;
        if (!(f >= 0.0f && f <= (float)(J - 1))) continue;
        int j0 = (int)floor(f);
        if (j0 > J - 2) j0 = J - 2;
        float b = f - (float)j0, wt = fsf_gauss((float)t, sigma);
        tap_node[o] = q * J + j0, tap_w[2 * o] = wt * (1.0f - b), tap_w[2 * o + 1] = wt * b;
    }
    if (axis == 0) {
        int rr = fsf_radius(pp[6]);
        __global float *cum = cum1 + FSF_CUM * i;
        cum[0] = 0.0f;
        for (int t = -rr; t <= rr; ++t) cum[t + rr + 1] = cum[t + rr] + fsf_gauss((float)t, pp[6]);
    }
}

/* Each sample slot's y2 bin, once for the 16 slices of pass 1a. */
__kernel void fsf_bins(const FsfArgs a, const int capacity, __global const int *count, __global const float *ys,
                       __global uchar *bin2)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height) return;
    for (int k = 0; k < count[i]; ++k) bin2[i * capacity + k] = (uchar)fsf_bin2(ys[2 * (i * capacity + k) + 1], a.half2, a.B);
}

/* Pass 1a for one y2 bin (fsf_pass1a, eq. 12). */
__kernel void fsf_pass1a(const FsfArgs a, const int bin, const int capacity, __global const int *count,
                         __global const float *ys, __global const uchar *bin2, __global const float *value,
                         __global const float *px, __global const float *cum1, __global float *P)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height) return;
    int J = a.J;
    float dY = 4.0f * a.half1 / (float)(J - 1), L1 = a.half1, mid = 0.5f * (float)(J - 1);
    __global float *Pi = P + J * 4 * i;
    for (int k = 0; k < 4 * J; ++k) Pi[k] = 0.0f;
    int r = fsf_radius(px[8 * i + 6]);
    float eta = px[8 * i + 4];
    __global const float *cum = cum1 + FSF_CUM * i;
    for (int k = 0; k < count[i]; ++k) {
        int slot = i * capacity + k;
        if (bin2[slot] != bin) continue;
        float y1 = ys[2 * slot];
        float v0 = value[3 * slot], v1 = value[3 * slot + 1], v2 = value[3 * slot + 2];
        int j0 = (int)ceil((y1 - L1) / dY + mid), j1 = (int)floor((y1 + L1) / dY + mid);
        if (j0 < 0) j0 = 0;
        if (j1 > J - 1) j1 = J - 1;
        for (int jj = j0; jj <= j1; ++jj) {
            float z = y1 - ((float)jj - mid) * dY;
            if (fsf_box(z, a.prof1) == 0.0f) continue;
            float rho = fsf_density(z, eta, L1, r, cum);
            if (!(rho > 0.0f)) continue;
            float wk = 1.0f / rho;
            __global float *o = Pi + 4 * jj;
            o[0] += wk * v0, o[1] += wk * v1, o[2] += wk * v2, o[3] += wk;
        }
    }
}

/* One pixel's gather through its taps (passes 1b and 2b). */
static float4 fsf_gather(int i, __global const int *tap_node, __global const float *tap_w, __global const float *F)
{
    float4 acc = (float4)(0.0f);
    for (int t = 0; t < FSF_TAPS; ++t) {
        int o = FSF_TAPS * i + t, node = tap_node[o];
        if (node < 0) continue;
        acc += tap_w[2 * o] * vload4(node, F) + tap_w[2 * o + 1] * vload4(node + 1, F);
    }
    return acc;
}

/* Pass 1b for one y2 bin (fsf_pass1b, eq. 13). */
__kernel void fsf_pass1b(const FsfArgs a, const int bin, __global const int *tap_node, __global const float *tap_w,
                         __global const float *P, __global float *G)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height) return;
    vstore4(fsf_gather(i, tap_node, tap_w, P), a.B * i + bin, G);
}

/* Pass 2a (fsf_pass2a, eq. 14; B = J - 1: the density depends on m = b - 2 j only). */
__kernel void fsf_pass2a(const FsfArgs a, __global const float *px, __global const float *G, __global float *Q)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height) return;
    int J = a.J, B = a.B;
    float L2 = a.half2;
    float sigma = px[8 * i + 7], eta = px[8 * i + 5];
    int r = fsf_radius(sigma);
    float cum[FSF_CUM], inv_rho[3 * FSF_MAX_Y2_BINS];
    cum[0] = 0.0f;
    for (int t = -r; t <= r; ++t) cum[t + r + 1] = cum[t + r] + fsf_gauss((float)t, sigma);
    for (int m = -2 * B; m < B; ++m) {
        float z = 2.0f * L2 / (float)B * ((float)m + 0.5f * (float)B + 0.5f);
        float rho = fsf_box(z, a.prof2) != 0.0f ? fsf_density_p(z, eta, L2, r, cum) : 0.0f;
        inv_rho[m + 2 * B] = rho > 0.0f ? 1.0f / rho : 0.0f;
    }
    for (int jj = 0; jj < J; ++jj) {
        float4 acc = (float4)(0.0f);
        for (int b = 0; b < B; ++b) {
            float wk = inv_rho[b - 2 * jj + 2 * B];
            if (wk == 0.0f) continue;
            acc += vload4(B * i + b, G) * wk;
        }
        vstore4(acc, J * i + jj, Q);
    }
}

/* Pass 2b (fsf_pass2b, eq. 15). */
__kernel void fsf_pass2b(const FsfArgs a, __global const int *tap_node, __global const float *tap_w,
                         __global const float *Q, __global float *out4)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height) return;
    vstore4(fsf_gather(i, tap_node, tap_w, Q), i, out4);
}
