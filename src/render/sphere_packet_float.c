/* The packet sphere test of sphere_packet.c in single precision, with a bound that sends
 * every lane it cannot decide to the double test (issue 22, docs/algorithms.md "The packet
 * sphere test in float").
 *
 * The double test is a chain of long-latency operations (three divisions, two square roots)
 * in 8-lane vectors; in float a packet of 16 is one vector and the chain is one square root
 * and two divisions (the discriminant from the cross product, |d|^2 r^2 - |o x d|^2, the form
 * pbrt-v4 section 6.8.1 derives: it does not cancel the way b^2 - 4ac does). Each lane also
 * carries a first-order bound on its rounding error (Higham's model: each float operation
 * is exact times 1 + e, |e| <= u = 2^-24), propagated through the same steps and doubled for
 * the second-order terms. A lane is decided when the bound puts its discriminant's sign and
 * each of its roots' place against tnear and tfar beyond doubt, and it is not near tangency
 * (discriminant below 2^-8 of |d|^2 r^2, where the root's error grows as 1 / sqrt(disc)). A
 * decided lane's hit is the exact test's, so the double test's (whose own error is some
 * 10^8 times smaller); its t is within the bound of the double test's. */
#include "render/sphere_packet_float.h"

#include "render/sphere_packet.h"

#include <math.h>

#include "core/vectorise.h"

enum { RAYN_ORG_X, RAYN_ORG_Y, RAYN_ORG_Z, RAYN_TNEAR, RAYN_DIR_X, RAYN_DIR_Y, RAYN_DIR_Z, RAYN_TIME, RAYN_TFAR };

/* float's unit roundoff, and the share of |d|^2 r^2 below which a discriminant is near tangency */
#define SPHERE_FLOAT_U 0x1p-24f
#define SPHERE_FLOAT_TANGENT 0x1p-8f

WEDGE_VECTORISED int sphere_packet_hits_float(const float *rays, const int *valid, unsigned n, double w,
                                              const double translation[3], double r, int *restrict hit,
                                              double *restrict t, float *restrict t_err, int *restrict decided)
{
    const float *ox = rays + RAYN_ORG_X * n, *oy = rays + RAYN_ORG_Y * n, *oz = rays + RAYN_ORG_Z * n;
    const float *dx = rays + RAYN_DIR_X * n, *dy = rays + RAYN_DIR_Y * n, *dz = rays + RAYN_DIR_Z * n;
    const float *tn = rays + RAYN_TNEAR * n, *tf = rays + RAYN_TFAR * n;
    const float u = SPHERE_FLOAT_U;
    /* In tracer units (geometry space over w, a power of two, so exact): the ray's direction
     * is Embree's float as it is, and t is the same parameter. */
    const double inv_w = 1.0 / w;
    const double cx = translation[0] * inv_w, cy = translation[1] * inv_w, cz = translation[2] * inv_w;
    const float rf = (float)(r * inv_w), r2 = rf * rf;
    int undecided = 0;
    for (unsigned i = 0; i < n; ++i) {
        /* o - c in double, rounded once: its error is relative to the origin's distance from
         * the centre, not to the world's scale */
        float o0 = (float)((double)ox[i] + cx), o1 = (float)((double)oy[i] + cy), o2 = (float)((double)oz[i] + cz);
        float d0 = dx[i], d1 = dy[i], d2 = dz[i];
        float tnear = tn[i], tfar = tf[i];
        float a = d0 * d0 + d1 * d1 + d2 * d2;
        float b = d0 * o0 + d1 * o1 + d2 * o2; /* half of the b of a t^2 + 2 b t + c */
        float oo = o0 * o0 + o1 * o1 + o2 * o2;
        float c = oo - r2;
        float x0 = o1 * d2 - o2 * d1, x1 = o2 * d0 - o0 * d2, x2 = o0 * d1 - o1 * d0;
        float xx = x0 * x0 + x1 * x1 + x2 * x2;
        float ar2 = a * r2;
        float disc = ar2 - xx;
        /* The discriminant's bound, sqrt-free: |o x d|^2 errs by at most 8u sum_k |x_k| p_k +
         * 3u |o x d|^2 (x_k the cross product's components, p_k the sum of the two products'
         * magnitudes: their rounding, the difference's and o's), and by Cauchy-Schwarz and
         * Lagrange's identity (|o x d|^2 <= |o|^2 |d|^2) that is at most 15u |o|^2 |d|^2;
         * a r^2 errs by 7u of it, the subtraction by u |disc| <= u s. Doubled: 32u s. */
        float s = oo * a + ar2;
        float e_disc = 32.0f * u * s;
        /* c = |o|^2 - r^2: 5u |o|^2 (the squares, the sums, o's rounding), 3u r^2, u |c| */
        float e_c = 6.0f * u * oo + 4.0f * u * r2;
        /* every lane computes every value (selects, no branches: the loop vectorises) */
        float inv_a = 1.0f / a;
        float h = sqrtf(disc > 0.0f ? disc : 0.0f);
        float q = b < 0.0f ? h - b : -(b + h);
        float aq = fabsf(q), inv_q = 1.0f / q;
        /* q = -(b + sign(b) h): sqrt(disc) errs by at most e_disc / h when e_disc < disc (a
         * decided hit has it), plus its rounding u h; b by 4u sum |d_i o_i| <= 4u |o| |d| <=
         * 4u sqrt(s), an eighth of e_disc / h at most (h^2 <= a r^2 <= s); the sum u |q| */
        float e_q = 36.0f * u * s / h + u * (h + aq);
        /* each root with its own bound (doubled for the second-order terms): the near root of a
         * ray leaving the surface is small and known far better than the far one */
        float t0 = q * inv_a, t1 = c * inv_q;
        float e0 = 2.0f * (e_q + 6.0f * u * aq) * inv_a;
        float e1 = 2.0f * ((e_c + fabsf(t1) * e_q) * fabsf(inv_q) + 2.0f * u * fabsf(t1));
        int in0 = (t0 > tnear) & (t0 < tfar), in1 = (t1 > tnear) & (t1 < tfar);
        /* decided: a sure miss of the line, or a line well inside the sphere's silhouette whose
         * roots are each farther than their bound from tnear and tfar (false for NaN) */
        int line_miss = disc < -e_disc;
        /* or an origin outside moving away from the centre, whatever the line: the ray leaving a
         * sphere's surface. c > 2 e_c puts the exact c above e_c >= 6u |o|^2; with b > 0 in
         * float the exact b is positive (|o + t d|^2 > |o|^2 > r^2 for every t > 0) or below
         * b's error 4u |o| |d| in magnitude, so b^2 < a c and the line misses. A root is never
         * positive in float then either (c > 0, q < 0), so such a lane's hit is 0 as it is. */
        int behind = (c > 2.0f * e_c) & (b > 0.0f) & (tnear >= 0.0f);
        int line_hit = (disc > SPHERE_FLOAT_TANGENT * ar2 + e_disc) & (a > 0x1p-100f);
        int clear = (fabsf(t0 - tnear) > e0) & (fabsf(t0 - tfar) > e0) & (fabsf(t1 - tnear) > e1) &
                    (fabsf(t1 - tfar) > e1);
        int live = valid[i] == -1;
        int sure = (!live) | line_miss | behind | (line_hit & clear);
        decided[i] = sure;
        undecided |= !sure;
        hit[i] = live & line_hit & (in0 | in1);
        t[i] = in0 & in1 ? (t0 > t1 ? t1 : t0) : in0 ? t0 : t1;
        t_err[i] = e0 + e1;
    }
    return !undecided;
}

/* The float test, and for the lanes it leaves undecided the double test's results. Each lane's
 * answer depends on its own ray alone, not on the packet it shares (so images do not depend on
 * how rays are grouped: threads, tiles, MPI ranks). */
void sphere_packet_hits_fast(const float *rays, const int *valid, unsigned n, double w, const double translation[3],
                             double r, int *hit, double *t)
{
    enum { MAX = SPHERE_PACKET_FLOAT_MAX };
    float t_err[MAX];
    int decided[MAX], hit_d[MAX];
    double t_d[MAX];
    if (sphere_packet_hits_float(rays, valid, n, w, translation, r, hit, t, t_err, decided)) return;
    sphere_packet_hits(rays, valid, n, w, translation, r, hit_d, t_d);
    for (unsigned i = 0; i < n; ++i)
        if (!decided[i]) hit[i] = hit_d[i], t[i] = t_d[i];
}
