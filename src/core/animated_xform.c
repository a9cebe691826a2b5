/* Animated transforms as in pbrt-v4 (Pharr, Jakob, Humphreys, "Physically Based Rendering",
 * 4th ed., sec. 3.9 "Animating Transformations"; Shoemake and Duff 1992, "Matrix Animation
 * and Polar Decomposition"): decompose both ends into T R S, interpolate T and S linearly
 * and R by quaternion slerp (Shoemake 1985), and recompose. */
#include "core/animated_xform.h"

#include <math.h>
#include <string.h>

/* ---- small 3x3 helpers (upper-left block of a Mat4) ----------------------------------- */

typedef struct {
    double m[3][3];
} Mat3;

static Mat3 mat3_from4(const Mat4 *a)
{
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = a->m[i][j];
    return r;
}

static double mat3_det(const Mat3 *a)
{
    const double(*m)[3] = a->m;
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* Inverse transpose by cofactors: (A^-1)^T = cof(A) / det(A). False when det is zero or
 * not finite relative to the entries' scale. */
static bool mat3_inverse_transpose(const Mat3 *a, Mat3 *out)
{
    const double(*m)[3] = a->m;
    double det = mat3_det(a);
    double scale = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) scale = fmax(scale, fabs(m[i][j]));
    /* Treat a determinant below 1e-14 of the entries' cube as singular: the Newton step
     * below would otherwise blow up. */
    if (!(fabs(det) > 1e-14 * scale * scale * scale) || !isfinite(det)) return false;
    double inv_det = 1.0 / det;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            out->m[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) * inv_det;
        }
    return true;
}

/* ---- quaternions ----------------------------------------------------------------------- */

static double quat_dot(Quat a, Quat b) { return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w; }

static Quat quat_scale(Quat a, double s)
{
    Quat r = {a.x * s, a.y * s, a.z * s, a.w * s};
    return r;
}

static Quat quat_add(Quat a, Quat b)
{
    Quat r = {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w};
    return r;
}

static Quat quat_normalize(Quat a)
{
    double len = sqrt(quat_dot(a, a));
    if (!(len > 0.0)) {
        Quat id = {0, 0, 0, 1};
        return id;
    }
    return quat_scale(a, 1.0 / len);
}

/* Standard rotation matrix of q = (v sin(theta/2), cos(theta/2)): rotation by theta about v,
 * counter-clockwise in a right-handed frame, the same convention as mat4_rotate. The
 * factor 2/|q|^2 makes it exact for slightly non-unit q. */
Mat4 quat_to_mat4(Quat q)
{
    double n2 = quat_dot(q, q);
    double s = n2 > 0.0 ? 2.0 / n2 : 0.0;
    double xx = q.x * q.x * s, yy = q.y * q.y * s, zz = q.z * q.z * s;
    double xy = q.x * q.y * s, xz = q.x * q.z * s, yz = q.y * q.z * s;
    double wx = q.w * q.x * s, wy = q.w * q.y * s, wz = q.w * q.z * s;
    Mat4 r = mat4_identity();
    r.m[0][0] = 1.0 - (yy + zz);
    r.m[0][1] = xy - wz;
    r.m[0][2] = xz + wy;
    r.m[1][0] = xy + wz;
    r.m[1][1] = 1.0 - (xx + zz);
    r.m[1][2] = yz - wx;
    r.m[2][0] = xz - wy;
    r.m[2][1] = yz + wx;
    r.m[2][2] = 1.0 - (xx + yy);
    return r;
}

/* Inverse of quat_to_mat4 (Shoemake 1985). The branch picks the largest of w^2, x^2, y^2,
 * z^2 to take the square root of, so the division below is never by a small number. */
Quat quat_from_mat4(const Mat4 *a)
{
    const double(*m)[4] = a->m;
    double trace = m[0][0] + m[1][1] + m[2][2];
    Quat q;
    if (trace > 0.0) {
        double s = 2.0 * sqrt(trace + 1.0); /* s = 4w */
        q.w = 0.25 * s;
        q.x = (m[2][1] - m[1][2]) / s;
        q.y = (m[0][2] - m[2][0]) / s;
        q.z = (m[1][0] - m[0][1]) / s;
    } else if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
        double s = 2.0 * sqrt(fmax(0.0, 1.0 + m[0][0] - m[1][1] - m[2][2])); /* s = 4x */
        if (!(s > 0.0)) s = 1.0;
        q.x = 0.25 * s;
        q.w = (m[2][1] - m[1][2]) / s;
        q.y = (m[0][1] + m[1][0]) / s;
        q.z = (m[0][2] + m[2][0]) / s;
    } else if (m[1][1] >= m[2][2]) {
        double s = 2.0 * sqrt(fmax(0.0, 1.0 + m[1][1] - m[0][0] - m[2][2])); /* s = 4y */
        if (!(s > 0.0)) s = 1.0;
        q.y = 0.25 * s;
        q.w = (m[0][2] - m[2][0]) / s;
        q.x = (m[0][1] + m[1][0]) / s;
        q.z = (m[1][2] + m[2][1]) / s;
    } else {
        double s = 2.0 * sqrt(fmax(0.0, 1.0 + m[2][2] - m[0][0] - m[1][1])); /* s = 4z */
        if (!(s > 0.0)) s = 1.0;
        q.z = 0.25 * s;
        q.w = (m[1][0] - m[0][1]) / s;
        q.x = (m[0][2] + m[2][0]) / s;
        q.y = (m[1][2] + m[2][1]) / s;
    }
    return quat_normalize(q);
}

/* Spherical linear interpolation along the shorter great arc (q and -q are the same
 * rotation, so flipping b when a.b < 0 halves the angle travelled). Written as rotating a
 * towards the unit quaternion perpendicular to it in the a-b plane, by angle u*theta. When
 * a and b are nearly parallel, that perpendicular is ill-determined; the normalised linear
 * blend is then within ~1e-6 rad of the arc and still a pure rotation. */
Quat quat_slerp(Quat a, Quat b, double u)
{
    double d = quat_dot(a, b);
    if (d < 0.0) {
        b = quat_scale(b, -1.0);
        d = -d;
    }
    if (d > 0.9995) return quat_normalize(quat_add(quat_scale(a, 1.0 - u), quat_scale(b, u)));
    double theta = acos(fmin(d, 1.0));
    Quat perp = quat_normalize(quat_add(b, quat_scale(a, -d)));
    return quat_add(quat_scale(a, cos(theta * u)), quat_scale(perp, sin(theta * u)));
}

/* ---- decomposition --------------------------------------------------------------------- */

void mat4_decompose(const Mat4 *m, double t[3], Quat *r, Mat4 *s)
{
    for (int i = 0; i < 3; ++i) t[i] = m->m[i][3];
    Mat3 a = mat3_from4(m);

    /* Polar decomposition A = R S by Newton's iteration R <- (R + R^-T) / 2 (Higham 1986,
     * "Computing the polar decomposition"): it converges quadratically to the orthogonal
     * factor for any nonsingular A. Bounded at 100 steps; each step at least halves the
     * distance of the singular values from 1 once they are near it. */
    Mat3 rot = a;
    bool ok = true;
    for (int iter = 0; iter < 100; ++iter) {
        Mat3 inv_t;
        if (!mat3_inverse_transpose(&rot, &inv_t)) {
            ok = false;
            break;
        }
        double change = 0.0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double next = 0.5 * (rot.m[i][j] + inv_t.m[i][j]);
                change = fmax(change, fabs(next - rot.m[i][j]));
                rot.m[i][j] = next;
            }
        if (change <= 1e-15) break;
    }
    if (!ok) {
        /* Singular A (a zero scale): no unique rotation. Keep R = I and put all of A in S,
         * so the animation degrades to a linear matrix blend but still reconstructs. */
        memset(&rot, 0, sizeof rot);
        for (int i = 0; i < 3; ++i) rot.m[i][i] = 1.0;
    }
    /* A mirror (det < 0) makes the orthogonal factor a reflection, which has no quaternion:
     * move the sign into S instead (R S = (-R)(-S)). */
    double sign = mat3_det(&rot) < 0.0 ? -1.0 : 1.0;
    Mat4 rot4 = mat4_identity();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) rot4.m[i][j] = sign * rot.m[i][j];
    *r = quat_from_mat4(&rot4);

    /* S = R^T A with R rebuilt from the quaternion, so that T R S reproduces m with the very
     * rotation that the interpolation uses. */
    Mat4 rq = quat_to_mat4(*r);
    *s = mat4_identity();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double sum = 0.0;
            for (int k = 0; k < 3; ++k) sum += rq.m[k][i] * a.m[k][j];
            s->m[i][j] = sum;
        }
}

/* ---- animation ------------------------------------------------------------------------- */

void anim_xform_init(AnimXform *a, const Mat4 *start, const Mat4 *end)
{
    memset(a, 0, sizeof *a);
    a->start = *start;
    a->end = *end;
    a->animated = !mat4_equal(start, end);
    mat4_decompose(start, a->t[0], &a->r[0], &a->s[0]);
    mat4_decompose(end, a->t[1], &a->r[1], &a->s[1]);
    if (quat_dot(a->r[0], a->r[1]) < 0.0) a->r[1] = quat_scale(a->r[1], -1.0);
}

/* T(u) R(u) S(u) from the interpolated factors (upper 3x3 = R S, last column = T). */
static Mat4 compose_at(const AnimXform *a, double u)
{
    Mat4 rq = quat_to_mat4(quat_slerp(a->r[0], a->r[1], u));
    Mat4 out = mat4_identity();
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double sum = 0.0;
            for (int k = 0; k < 3; ++k) {
                double s_kj = (1.0 - u) * a->s[0].m[k][j] + u * a->s[1].m[k][j];
                sum += rq.m[i][k] * s_kj;
            }
            out.m[i][j] = sum;
        }
        out.m[i][3] = (1.0 - u) * a->t[0][i] + u * a->t[1][i];
    }
    return out;
}

Mat4 anim_xform_at(const AnimXform *a, double u)
{
    /* The ends are returned exactly (no round trip through the decomposition), and so is a
     * transform that does not move; NaN u falls back to the start. */
    if (!a->animated || !(u > 0.0)) return a->start;
    if (u >= 1.0) return a->end;
    return compose_at(a, u);
}

/* ---- motion bounds --------------------------------------------------------------------- */

static void extend(double lo[3], double hi[3], const double p[3])
{
    for (int i = 0; i < 3; ++i) {
        lo[i] = fmin(lo[i], p[i]);
        hi[i] = fmax(hi[i], p[i]);
    }
}

static void apply_point(const Mat4 *m, const double p[3], double out[3])
{
    for (int i = 0; i < 3; ++i) out[i] = m->m[i][0] * p[0] + m->m[i][1] * p[1] + m->m[i][2] * p[2] + m->m[i][3];
}

/* Why sampling plus padding is conservative: M(u) is affine, so the moving box is at every
 * time the convex hull of its 8 moving corners, and it is enough to bound each corner's
 * path c(u) = T(u) + R(u) q(u), q(u) = S(u) p (linear in u). Between two sample times
 * h apart, the path stays within h^2/8 * max|c''| of the chord joining the samples (the
 * interpolation error of a linear fit), and the chord lies in the box of the samples.
 * R(u) turns about a fixed axis at rate phi (the rotation angle between the ends), so
 * |R' v| <= phi |v|, |R'' v| <= phi^2 |v|, and |c''| = |R'' q + 2 R' q'| <=
 * phi^2 max|q| + 2 phi |q1 - q0| (max|q| is reached at an end: |q(u)| is convex). */
void anim_xform_motion_bounds(const AnimXform *a, const double lo[3], const double hi[3], double u0,
                              double u1, double out_lo[3], double out_hi[3])
{
    for (int i = 0; i < 3; ++i) {
        out_lo[i] = INFINITY;
        out_hi[i] = -INFINITY;
    }
    u0 = fmin(fmax(u0, 0.0), 1.0);
    u1 = fmin(fmax(u1, u0), 1.0);
    int steps = 0;
    double pad = 0.0;
    if (a->animated) {
        /* Rotation rate per unit u; 10% slack covers the near-parallel lerp branch of
         * slerp, whose speed varies slightly. */
        double d = fmin(fabs(quat_dot(a->r[0], a->r[1])), 1.0);
        double phi = 2.0 * acos(d) * 1.1;
        /* At most 1/8 rad of turn per step keeps the padding below ~0.2% of the radius. */
        steps = (int)fmin(256.0, fmax(16.0, ceil(8.0 * phi * (u1 - u0))));
        double h = (u1 - u0) / steps;
        double c2_max = 0.0;
        for (int c = 0; c < 8; ++c) {
            double p[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]};
            double q0[3], q1[3], q_max = 0.0, dq = 0.0;
            apply_point(&a->s[0], p, q0); /* s[] has zero translation */
            apply_point(&a->s[1], p, q1);
            double n0 = 0.0, n1 = 0.0;
            for (int i = 0; i < 3; ++i) {
                n0 += q0[i] * q0[i];
                n1 += q1[i] * q1[i];
                dq += (q1[i] - q0[i]) * (q1[i] - q0[i]);
            }
            q_max = sqrt(fmax(n0, n1));
            c2_max = fmax(c2_max, phi * phi * q_max + 2.0 * phi * sqrt(dq));
        }
        pad = h * h / 8.0 * c2_max;
    }
    for (int k = 0; k <= steps; ++k) {
        double u = steps ? u0 + (u1 - u0) * k / steps : u0;
        Mat4 m = anim_xform_at(a, u);
        for (int c = 0; c < 8; ++c) {
            double p[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]};
            double w[3];
            apply_point(&m, p, w);
            extend(out_lo, out_hi, w);
        }
    }
    /* Pad also by a few ulps of the coordinates' magnitude: the sampled corners carry
     * rounding error, and the caller may convert to float. */
    for (int i = 0; i < 3; ++i) {
        double mag = fmax(fabs(out_lo[i]), fabs(out_hi[i]));
        double eps = pad + 1e-7 * mag;
        out_lo[i] -= eps;
        out_hi[i] += eps;
    }
}
