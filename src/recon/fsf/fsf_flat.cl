/* FSF's indirect-light filter as two spatial passes over pixel sums (fsf_flat.h, the C
 * reference and the no-device path; docs/algorithms.md section 10, "The bounce filter as two
 * spatial passes"), one work item per pixel:
 *
 *   fsf_flat_pass_a  G(q) = sum_t1 w_q(t1) S(q + t1 dir1_q) / sum_{|t1| <= r1} w_q(t1),
 *                    S = (count value, count) taken from value4 and count as it is read
 *   fsf_flat_pass_b  out(p) = sum_t2 w_p(t2) G(p + t2 dir2_p)
 *
 * The arithmetic is fsf_flat.c's, operation for operation and in the same order (the weights'
 * recurrence, the tap rounding, fsf_accept's guide test, the sums over t = -r .. r), so that the
 * two agree to the last bits of the exponential: a driver's exp may differ from the C
 * library's expf by an ulp or two. Contraction into fused multiply-adds is off, as the C build's
 * (C11's -ffp-contract=off): a fused t dir + 0.5 could round a tap to another pixel.
 *
 * Buffers: value4 4 floats a pixel (rgb read), count an int, px 8 floats (FsfPixel: dir1, dir2,
 * eta, sigma), usable a byte, pos4 and nrm4 4 floats (read only when guided), G and out4 4
 * floats. A pixel that is not usable gets 0. */
#pragma OPENCL FP_CONTRACT OFF

#define FSF_FLAT_RADIUS_CAP 16 /* fsf_filter.h's FSF_RADIUS_CAP_PX */

typedef struct {
    int width, height;
    float reach;          /* the grid's reach_sigmas (fsf_tap_radius) */
    float cos_normal_min; /* the guides' (fsf_accept) */
    float plane_tol_rel;
    int guided;           /* 0: no guides, every usable neighbour accepted */
} FsfFlatArgs;

/* fsf_radius_reach (fsf_filter.c): taps each side for a width, capped */
static int flat_radius(float sigma, float reach)
{
    if (!(sigma > 0.0f)) return 0;
    float r = ceil(reach * sigma);
    return r < (float)FSF_FLAT_RADIUS_CAP ? (int)r : FSF_FLAT_RADIUS_CAP;
}

/* fsf_flat.c's gauss_weights: w[t] = exp(-t^2 / (2 sigma^2)), t = 0 .. r, by w(t + 1) = w(t)
 * c^(2 t + 1) */
static void flat_weights(float sigma, int r, float *w)
{
    w[0] = 1.0f;
    if (r == 0) return;
    float c = exp(-0.5f / (sigma * sigma)), c2 = c * c, step = c;
    for (int t = 1; t <= r; ++t) w[t] = w[t - 1] * step, step *= c2;
}

/* fsf_accept for a tap t != 0 from centre p to the in-frame pixel q */
static bool flat_accept(const FsfFlatArgs *a, __global const uchar *usable, __global const float *pos4,
                        __global const float *nrm4, int p, int q)
{
    if (!usable[q]) return false;
    if (q == p || !a->guided) return true;
    __global const float *np = nrm4 + 4 * p, *nq = nrm4 + 4 * q;
    if (np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2] < a->cos_normal_min) return false;
    __global const float *pp = pos4 + 4 * p, *pq = pos4 + 4 * q;
    float off = np[0] * (pq[0] - pp[0]) + np[1] * (pq[1] - pp[1]) + np[2] * (pq[2] - pp[2]);
    return fabs(off) <= a->plane_tol_rel * pp[3];
}

/* One gather along pixel i's own axis `axis` (0: pass A, divided by its weights' sum; 1: pass
 * B); from_value: the input is S made from value4 and count (pass A), else in4 (pass B's G). */
static float4 flat_gather(const FsfFlatArgs *a, int i, int axis, bool from_value, __global const float *value4,
                          __global const int *count, __global const float *in4, __global const float *px,
                          __global const uchar *usable, __global const float *pos4, __global const float *nrm4)
{
    float4 acc = (float4)(0.0f);
    if (!usable[i]) return acc;
    __global const float *pp = px + 8 * i;
    float dx = pp[2 * axis], dy = pp[2 * axis + 1], sigma = pp[6 + axis];
    int x = i % a->width, y = i / a->width;
    int r = flat_radius(sigma, a->reach);
    float wt[FSF_FLAT_RADIUS_CAP + 1];
    flat_weights(sigma, r, wt);
    float all = 0.0f;
    for (int t = -r; t <= r; ++t) {
        float wk = wt[t < 0 ? -t : t];
        all += wk;
        /* fsf_step_pixel */
        int qx = x + (int)floor((float)t * dx + 0.5f), qy = y + (int)floor((float)t * dy + 0.5f);
        if (qx < 0 || qy < 0 || qx >= a->width || qy >= a->height) continue;
        int q = qy * a->width + qx;
        if (t != 0 && !flat_accept(a, usable, pos4, nrm4, i, q)) continue;
        float4 f;
        if (from_value) { /* fsf_flat.c's sums_range: a non-finite channel 0 */
            float c = (float)count[q];
            float4 v = vload4(q, value4);
            f = (float4)(isfinite(v.x) ? c * v.x : 0.0f, isfinite(v.y) ? c * v.y : 0.0f,
                         isfinite(v.z) ? c * v.z : 0.0f, c);
        } else {
            f = vload4(q, in4);
        }
        acc.x += wk * f.x, acc.y += wk * f.y, acc.z += wk * f.z, acc.w += wk * f.w;
    }
    if (axis == 0) acc.x /= all, acc.y /= all, acc.z /= all, acc.w /= all;
    return acc;
}

__kernel void fsf_flat_pass_a(const FsfFlatArgs a, __global const float *value4, __global const int *count,
                              __global const float *px, __global const uchar *usable, __global const float *pos4,
                              __global const float *nrm4, __global float *G)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height) return;
    vstore4(flat_gather(&a, i, 0, true, value4, count, value4, px, usable, pos4, nrm4), i, G);
}

__kernel void fsf_flat_pass_b(const FsfFlatArgs a, __global const float *G, __global const float *px,
                              __global const uchar *usable, __global const float *pos4, __global const float *nrm4,
                              __global float *out4)
{
    int i = get_global_id(0);
    if (i >= a.width * a.height) return;
    vstore4(flat_gather(&a, i, 1, false, G, (__global const int *)0, G, px, usable, pos4, nrm4), i, out4);
}
