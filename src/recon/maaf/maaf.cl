/* Multiple axis-aligned filters: the image-space pass of seeds/003 eq. 21 for the 4D soft-shadow
 * filter (a product of two orthogonal 2D designs, Sec. 6.1), run twice: along pixel rows, then
 * along pixel columns. OpenCL C 1.2, float only. The C reference is maaf_filter_reference
 * (maaf_filter.c); docs/algorithms.md 9.6 has the derivation.
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
 * Per pixel: in/tmp: 2 float4 (re, im) per component; pos4 (position, depth), nrm4 (normal,
 * object id), frame4 (the light's axis t1, usable flag), axis2 (its axis t2); param: MAAF_PARAM_STRIDE floats,
 * radius in pixels, then per band p: amplitude, C_x, sx^2/2 (world units). out4: filtered rgb
 * and a flag (0: unchanged, 1: filtered, 2: the full sum's weight was too small and the
 * central component alone was used). */

#define MAAF_PAIRS_MAX 5
#define MAAF_COMPS_MAX 41
#define MAAF_PARAM_STRIDE 16
/* below this fraction of the central component's weight the full sum is not trusted */
#define MAAF_MIN_WEIGHT_FRACTION 0.2f
/* sx^2 ratio of the sharpness rule: a neighbour's std under 1/2 of the centre's */
#define MAAF_SHARP_FACTOR 4.0f

__kernel void maaf_pass(int width, int height, int axis, int pairs, int comps, float cos_normal_min,
                        float depth_tol_rel, __global const float4 *in, __global const float4 *pos4,
                        __global const float4 *nrm4, __global const float4 *frame4,
                        __global const float4 *axis2, __global const float *param, __global float4 *tmp, __global float4 *out4)
{
    int x = (int)get_global_id(0), y = (int)get_global_id(1);
    if (x >= width || y >= height) return;
    int i = y * width + x;
    int stride = 2 * comps;
    float4 cf = frame4[i];
    __global const float *pr = param + i * MAAF_PARAM_STRIDE;
    int radius = (int)pr[0];
    if (cf.w == 0.0f || radius <= 0) {
        if (axis == 0)
            for (int c = 0; c < stride; ++c) tmp[i * stride + c] = in[i * stride + c];
        else
            out4[i] = (float4)(0.0f);
        return;
    }
    float3 t1 = cf.xyz, t2 = axis2[i].xyz;
    float4 cp = pos4[i], cn = nrm4[i];
    float tol = depth_tol_rel * cp.w;
    float amp[MAAF_PAIRS_MAX], cx[MAAF_PAIRS_MAX], hv[MAAF_PAIRS_MAX];
    for (int p = 0; p < pairs; ++p) {
        amp[p] = pr[1 + 3 * p];
        cx[p] = pr[2 + 3 * p];
        hv[p] = pr[3 + 3 * p];
    }
    float4 acc[2 * MAAF_COMPS_MAX];
    for (int c = 0; c < stride; ++c) acc[c] = (float4)(0.0f);
    for (int k = -radius; k <= radius; ++k) {
        int nx = axis == 0 ? x + k : x, ny = axis == 0 ? y : y + k;
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        int j = ny * width + nx;
        if (frame4[j].w == 0.0f) continue;
        float4 np = pos4[j], nn = nrm4[j];
        float3 dlt = cp.xyz - np.xyz;
        /* AAF's rejections: another object, a normal discontinuity, a depth discontinuity */
        if (nn.w != cn.w || dot(cn.xyz, nn.xyz) < cos_normal_min || fabs(dot(cn.xyz, dlt)) > tol) continue;
        /* AAF's sharpness rule: a neighbour that is not filtered, or whose central filter is under
         * half as wide as the centre's, holds detail (a contact shadow, a shadow from an occluder
         * outside the centre's wedge) that the centre's filter would smear */
        __global const float *pn = param + j * MAAF_PARAM_STRIDE;
        if (pn[0] <= 0.0f || pn[3] > MAAF_SHARP_FACTOR * hv[0]) continue;
        float d1 = dot(dlt, t1), d2 = dot(dlt, t2);
        float2 e1[MAAF_PAIRS_MAX], e2[MAAF_PAIRS_MAX];
        for (int p = 0; p < pairs; ++p) {
            float c1, c2;
            float s1 = sincos(cx[p] * d1, &c1), s2 = sincos(cx[p] * d2, &c2);
            float g1 = exp(-hv[p] * d1 * d1), g2 = exp(-hv[p] * d2 * d2);
            e1[p] = (float2)(g1 * c1, g1 * s1);
            e2[p] = (float2)(g2 * c2, g2 * s2);
        }
        __global const float4 *yj = in + j * stride;
        int c = 0;
        for (int p = 0; p < pairs; ++p)
            for (int q = -(pairs - 1); q < pairs; ++q) {
                if (p == 0 && q < 0) continue;
                float2 b = q >= 0 ? e2[q] : (float2)(e2[-q].x, -e2[-q].y); /* band -q: conjugate */
                float2 w = (float2)(e1[p].x * b.x - e1[p].y * b.y, e1[p].x * b.y + e1[p].y * b.x);
                float4 yr = yj[2 * c], yi = yj[2 * c + 1];
                acc[2 * c] += w.x * yr - w.y * yi;
                acc[2 * c + 1] += w.x * yi + w.y * yr;
                ++c;
            }
    }
    if (axis == 0) {
        for (int c = 0; c < stride; ++c) tmp[i * stride + c] = acc[c];
        return;
    }
    /* eq. 21: the real part of the sum over components, each with its amplitude; the conjugate
     * half doubles every component but the central one */
    float4 sum = (float4)(0.0f);
    int c = 0;
    for (int p = 0; p < pairs; ++p)
        for (int q = -(pairs - 1); q < pairs; ++q) {
            if (p == 0 && q < 0) continue;
            float m = (c == 0 ? 1.0f : 2.0f) * amp[p] * amp[q < 0 ? -q : q];
            sum += m * acc[2 * c];
            ++c;
        }
    float4 central = acc[0];
    if (sum.w > MAAF_MIN_WEIGHT_FRACTION * amp[0] * amp[0] * central.w && sum.w > 0.0f)
        out4[i] = (float4)(sum.xyz / sum.w, 1.0f);
    else if (central.w > 0.0f)
        out4[i] = (float4)(central.xyz / central.w, 2.0f);
    else
        out4[i] = (float4)(0.0f);
}
