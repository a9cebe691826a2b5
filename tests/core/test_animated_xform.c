/* Animated transforms: polar decomposition, quaternion conversion, slerp, interpolation and
 * motion bounds, checked against transforms built directly from their factors. */
#include <math.h>
#include <stdio.h>

#include "check.h"
#include "core/animated_xform.h"
#include "core/rng.h"

static double urand(Pcg32 *r) { return (double)pcg32_next(r) * 0x1p-32; }

static double max_abs_diff(const Mat4 *a, const Mat4 *b)
{
    double d = 0.0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) d = fmax(d, fabs(a->m[i][j] - b->m[i][j]));
    return d;
}

static Mat4 random_rotation(Pcg32 *r, double *angle_deg, double axis[3])
{
    double z = 2.0 * urand(r) - 1.0, phi = 2.0 * M_PI * urand(r), rho = sqrt(1.0 - z * z);
    axis[0] = rho * cos(phi);
    axis[1] = rho * sin(phi);
    axis[2] = z;
    *angle_deg = 360.0 * urand(r) - 180.0;
    return mat4_rotate(*angle_deg, axis[0], axis[1], axis[2]);
}

static Mat4 mul3(Mat4 a, Mat4 b, Mat4 c)
{
    Mat4 ab = mat4_mul(&a, &b);
    return mat4_mul(&ab, &c);
}

static Mat4 rebuild(const double t[3], Quat q, const Mat4 *s)
{
    Mat4 tm = mat4_translate(t[0], t[1], t[2]), rm = quat_to_mat4(q);
    return mul3(tm, rm, *s);
}

/* M = T R D with D a positive diagonal scale: the polar decomposition must return exactly
 * these factors (R D is already in polar form, since D is symmetric positive definite),
 * and T R S must reproduce M. */
static void test_decompose_random(void)
{
    Pcg32 rng;
    pcg32_seed(&rng, 1234, 5);
    for (int trial = 0; trial < 500; ++trial) {
        double angle, axis[3];
        Mat4 rot = random_rotation(&rng, &angle, axis);
        /* Scales over four orders of magnitude, including strongly anisotropic ones. */
        double sc[3];
        for (int i = 0; i < 3; ++i) sc[i] = pow(10.0, 4.0 * urand(&rng) - 2.0);
        double tr[3];
        for (int i = 0; i < 3; ++i) tr[i] = 200.0 * urand(&rng) - 100.0;
        Mat4 m = mul3(mat4_translate(tr[0], tr[1], tr[2]), rot, mat4_scale(sc[0], sc[1], sc[2]));

        double t[3];
        Quat q;
        Mat4 s;
        mat4_decompose(&m, t, &q, &s);
        Mat4 back = rebuild(t, q, &s);
        double scale = fmax(fmax(sc[0], sc[1]), sc[2]);
        CHECK(max_abs_diff(&back, &m) <= 1e-9 * fmax(1.0, scale));
        for (int i = 0; i < 3; ++i) CHECK_NEAR(t[i], tr[i], 0);
        CHECK_NEAR(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w, 1.0, 1e-12);
        Mat4 rq = quat_to_mat4(q);
        CHECK(max_abs_diff(&rq, &rot) <= 1e-9);
        Mat4 d = mat4_scale(sc[0], sc[1], sc[2]);
        CHECK(max_abs_diff(&s, &d) <= 1e-9 * scale);
    }

    /* General affine maps (random entries, including shear) also reconstruct, S comes out
     * symmetric, and R is a proper rotation even for mirrored maps (det < 0). */
    int mirrored = 0;
    for (int trial = 0; trial < 500; ++trial) {
        Mat4 m = mat4_identity();
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j) m.m[i][j] = 4.0 * urand(&rng) - 2.0;
        mirrored += mat4_swaps_handedness(&m);
        double t[3];
        Quat q;
        Mat4 s;
        mat4_decompose(&m, t, &q, &s);
        Mat4 back = rebuild(t, q, &s);
        CHECK(max_abs_diff(&back, &m) <= 1e-9);
        Mat4 rq = quat_to_mat4(q);
        CHECK(!mat4_swaps_handedness(&rq));
        Mat4 rtr = mat4_transpose(&rq);
        Mat4 should_be_id = mat4_mul(&rtr, &rq);
        Mat4 id = mat4_identity();
        CHECK(max_abs_diff(&should_be_id, &id) <= 1e-12);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) CHECK_NEAR(s.m[i][j], s.m[j][i], 1e-9);
    }
    CHECK(mirrored > 100); /* the random set really exercised the mirror case */

    /* A zero scale (singular) still reconstructs. */
    Mat4 flat = mul3(mat4_translate(1, 2, 3), mat4_rotate(30, 0, 1, 0), mat4_scale(2, 0, 1));
    double t[3];
    Quat q;
    Mat4 s;
    mat4_decompose(&flat, t, &q, &s);
    Mat4 back = rebuild(t, q, &s);
    CHECK(max_abs_diff(&back, &flat) <= 1e-9);
}

/* quat_from_mat4 inverts quat_to_mat4 on every branch (trace > 0 and each largest diagonal
 * element, including half turns where w = 0). */
static void test_quat_roundtrip(void)
{
    const double cases[][4] = {{0, 0, 0, 1},     {30, 1, 0, 0},    {180, 1, 0, 0},  {180, 0, 1, 0},
                               {180, 0, 0, 1},   {179.9, 1, 1, 0}, {170, 0, 1, 1},  {-120, 1, 1, 1},
                               {100, 0.2, 1, -3}, {359, 0, 0, 1},  {90, 0, 0, 1},   {181, 1, -2, 0.5}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        Mat4 m = mat4_rotate(cases[c][0], cases[c][1], cases[c][2], cases[c][3]);
        Quat q = quat_from_mat4(&m);
        Mat4 back = quat_to_mat4(q);
        CHECK(max_abs_diff(&back, &m) <= 1e-12);
    }
}

static double dist(vec3 a, vec3 b) { return sqrt(v3_length2(v3_sub(a, b))); }

static void test_ends_and_static(void)
{
    Mat4 a = mul3(mat4_translate(1, -2, 3), mat4_rotate(40, 1, 2, 3), mat4_scale(1, 2, 3));
    Mat4 b = mul3(mat4_translate(-4, 5, 0.5), mat4_rotate(-75, 3, 0, 1), mat4_scale(0.5, 0.25, 4));
    AnimXform an;
    anim_xform_init(&an, &a, &b);
    CHECK(an.animated);
    Mat4 at0 = anim_xform_at(&an, 0.0), at1 = anim_xform_at(&an, 1.0);
    CHECK(mat4_equal(&at0, &a));
    CHECK(mat4_equal(&at1, &b));
    /* Just inside the ends, the interpolation is continuous with them. */
    Mat4 near0 = anim_xform_at(&an, 1e-9), near1 = anim_xform_at(&an, 1.0 - 1e-9);
    CHECK(max_abs_diff(&near0, &a) < 1e-7);
    CHECK(max_abs_diff(&near1, &b) < 1e-7);

    AnimXform still;
    anim_xform_init(&still, &a, &a);
    CHECK(!still.animated);
    for (double u = 0.0; u <= 1.0; u += 0.125) {
        Mat4 m = anim_xform_at(&still, u);
        CHECK(mat4_equal(&m, &a));
    }
    Mat4 nan_u = anim_xform_at(&an, NAN);
    CHECK(mat4_equal(&nan_u, &a));
}

static void test_rotation(void)
{
    /* 0 -> 90 degrees about z: at u the transform is the rotation by 90u degrees (slerp has
     * constant angular speed), in particular exactly 45 degrees at u = 0.5. */
    Mat4 r0 = mat4_identity(), r90 = mat4_rotate(90, 0, 0, 1);
    AnimXform an;
    anim_xform_init(&an, &r0, &r90);
    Mat4 half = anim_xform_at(&an, 0.5), r45 = mat4_rotate(45, 0, 0, 1);
    CHECK(max_abs_diff(&half, &r45) <= 1e-12);
    for (int k = 0; k <= 16; ++k) {
        double u = k / 16.0;
        Mat4 m = anim_xform_at(&an, u), expect = mat4_rotate(90.0 * u, 0, 0, 1);
        CHECK(max_abs_diff(&m, &expect) <= 1e-12);
    }

    /* Rigid motion between two random rigid transforms: the distances between transformed
     * points are those of the object at every u (rotating objects do not shrink, unlike a
     * linear blend of matrices). */
    Pcg32 rng;
    pcg32_seed(&rng, 77, 1);
    for (int trial = 0; trial < 50; ++trial) {
        double angle, axis[3];
        Mat4 ra = random_rotation(&rng, &angle, axis), rb = random_rotation(&rng, &angle, axis);
        Mat4 ta = mat4_translate(urand(&rng), urand(&rng), urand(&rng));
        Mat4 tb = mat4_translate(5 * urand(&rng), 5 * urand(&rng), 5 * urand(&rng));
        Mat4 a = mat4_mul(&ta, &ra), b = mat4_mul(&tb, &rb);
        anim_xform_init(&an, &a, &b);
        vec3 p[4] = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 2, 0), v3(0.5f, -1, 3)};
        for (int k = 0; k <= 20; ++k) {
            Mat4 m = anim_xform_at(&an, k / 20.0);
            for (int i = 0; i < 4; ++i)
                for (int j = i + 1; j < 4; ++j) {
                    vec3 pi = mat4_apply_point(&m, p[i]), pj = mat4_apply_point(&m, p[j]);
                    CHECK_NEAR(dist(pi, pj), dist(p[i], p[j]), 1e-5); /* float points */
                }
            CHECK(!mat4_swaps_handedness(&m));
        }
    }

    /* 0 -> 350 degrees is the same end matrix as -10 degrees: the object turns the short
     * way, through -5 degrees at u = 0.5 (as pbrt-v4, which only sees the matrices). */
    Mat4 r350 = mat4_rotate(350, 0, 0, 1), rm5 = mat4_rotate(-5, 0, 0, 1);
    anim_xform_init(&an, &r0, &r350);
    Mat4 mid = anim_xform_at(&an, 0.5);
    CHECK(max_abs_diff(&mid, &rm5) <= 1e-12);
}

static void test_translation(void)
{
    Mat4 a = mat4_translate(1, 2, 3), b = mat4_translate(-3, 10, 0.5);
    AnimXform an;
    anim_xform_init(&an, &a, &b);
    for (int k = 0; k <= 10; ++k) {
        double u = k / 10.0;
        Mat4 m = anim_xform_at(&an, u);
        Mat4 expect = mat4_translate(1 - 4 * u, 2 + 8 * u, 3 - 2.5 * u);
        CHECK(max_abs_diff(&m, &expect) <= 1e-12);
    }
}

static void test_slerp(void)
{
    /* q and -q are the same rotation: slerp from identity to -(30 degrees about x) must
     * pass through 15 degrees, not through 165 (the long arc). */
    Mat4 r30 = mat4_rotate(30, 1, 0, 0), r15 = mat4_rotate(15, 1, 0, 0);
    Quat q30 = quat_from_mat4(&r30);
    Quat neg = {-q30.x, -q30.y, -q30.z, -q30.w};
    Quat id = {0, 0, 0, 1};
    Mat4 mid = quat_to_mat4(quat_slerp(id, neg, 0.5));
    CHECK(max_abs_diff(&mid, &r15) <= 1e-12);
    /* Ends of the slerp are the inputs as rotations. */
    Mat4 end = quat_to_mat4(quat_slerp(id, neg, 1.0)), start = quat_to_mat4(quat_slerp(id, neg, 0.0));
    CHECK(max_abs_diff(&end, &r30) <= 1e-12);
    Mat4 ident = mat4_identity();
    CHECK(max_abs_diff(&start, &ident) <= 1e-15);

    /* Near-parallel quaternions take the normalised-lerp branch: still unit, and within
     * 1e-6 rad of the exact slerp angle (rotation by 0.05 degrees about y, halfway). */
    Mat4 small = mat4_rotate(0.05, 0, 1, 0), half_small = mat4_rotate(0.025, 0, 1, 0);
    Quat qs = quat_from_mat4(&small);
    Quat h = quat_slerp(id, qs, 0.5);
    CHECK_NEAR(h.x * h.x + h.y * h.y + h.z * h.z + h.w * h.w, 1.0, 1e-12);
    Mat4 hm = quat_to_mat4(h);
    CHECK(max_abs_diff(&hm, &half_small) <= 1e-6);
}

/* Every point of the box at every time lies inside the bound; and the bound is tight:
 * no more than 2% of the box's world size larger than a dense sampling of the motion. */
static void test_motion_bounds(void)
{
    Pcg32 rng;
    pcg32_seed(&rng, 4242, 3);
    for (int trial = 0; trial < 30; ++trial) {
        double angle, axis[3];
        Mat4 ra = random_rotation(&rng, &angle, axis), rb = random_rotation(&rng, &angle, axis);
        Mat4 a = mul3(mat4_translate(urand(&rng), 0, 0), ra, mat4_scale(1 + urand(&rng), 1, 2));
        Mat4 b = mul3(mat4_translate(0, 3 * urand(&rng), 0), rb, mat4_scale(1, 1 + urand(&rng), 1));
        AnimXform an;
        anim_xform_init(&an, &a, &b);
        double lo[3] = {-1, -0.5, -2}, hi[3] = {1, 0.5, 0.25};
        double u0 = trial % 2 ? 0.0 : 0.25 * urand(&rng), u1 = trial % 2 ? 1.0 : 0.5 + 0.5 * urand(&rng);
        double blo[3], bhi[3];
        anim_xform_motion_bounds(&an, lo, hi, u0, u1, blo, bhi);
        double dlo[3] = {INFINITY, INFINITY, INFINITY}, dhi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int k = 0; k < 4000; ++k) {
            double u = u0 + (u1 - u0) * (k < 2000 ? urand(&rng) : (k - 2000) / 1999.0);
            Mat4 m = anim_xform_at(&an, u);
            /* random points inside the box, and corners (where the extremes are) */
            double p[3];
            for (int i = 0; i < 3; ++i)
                p[i] = (k % 3 == 0) ? lo[i] + (hi[i] - lo[i]) * urand(&rng)
                                    : ((pcg32_next(&rng) & 1) ? hi[i] : lo[i]);
            for (int i = 0; i < 3; ++i) {
                double w = m.m[i][0] * p[0] + m.m[i][1] * p[1] + m.m[i][2] * p[2] + m.m[i][3];
                CHECK(w >= blo[i] && w <= bhi[i]);
                dlo[i] = fmin(dlo[i], w);
                dhi[i] = fmax(dhi[i], w);
            }
        }
        for (int i = 0; i < 3; ++i) {
            double size = dhi[i] - dlo[i];
            CHECK((dlo[i] - blo[i]) + (bhi[i] - dhi[i]) <= 0.02 * size + 1e-9);
        }
    }
    /* A static transform bounds exactly its box's image. */
    Mat4 t = mat4_translate(1, 2, 3);
    AnimXform st;
    anim_xform_init(&st, &t, &t);
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, blo[3], bhi[3];
    anim_xform_motion_bounds(&st, lo, hi, 0, 1, blo, bhi);
    for (int i = 0; i < 3; ++i) {
        CHECK_NEAR(blo[i], i + 1, 1e-6);
        CHECK_NEAR(bhi[i], i + 2, 1e-6);
    }
}

int main(void)
{
    test_decompose_random();
    test_quat_roundtrip();
    test_ends_and_static();
    test_rotation();
    test_translation();
    test_slerp();
    test_motion_bounds();
    CHECK_DONE();
}
