/* Transforms against hand-computed matrices. */
#include "check.h"
#include "core/transform.h"

static void check_point(const Mat4 *m, vec3 p, vec3 expect)
{
    vec3 r = mat4_apply_point(m, p);
    CHECK_NEAR(r.x, expect.x, 1e-5);
    CHECK_NEAR(r.y, expect.y, 1e-5);
    CHECK_NEAR(r.z, expect.z, 1e-5);
}

int main(void)
{
    Mat4 t = mat4_translate(1, 2, 3);
    check_point(&t, v3(1, 1, 1), v3(2, 3, 4));
    vec3 v = mat4_apply_vector(&t, v3(1, 1, 1));
    CHECK_NEAR(v.x, 1, 0);

    /* Rotate 90 degrees about z takes +x to +y (counter-clockwise looking down -z). */
    Mat4 r = mat4_rotate(90, 0, 0, 1);
    check_point(&r, v3(1, 0, 0), v3(0, 1, 0));
    Mat4 rx = mat4_rotate(90, 1, 0, 0);
    check_point(&rx, v3(0, 1, 0), v3(0, 0, 1));

    /* Post-multiplication: Translate then Scale means scale is applied to the point first. */
    Mat4 s = mat4_scale(2, 2, 2);
    Mat4 ts = mat4_mul(&t, &s);
    check_point(&ts, v3(1, 1, 1), v3(3, 4, 5));

    Mat4 inv;
    CHECK(mat4_inverse(&ts, &inv));
    Mat4 id = mat4_mul(&ts, &inv);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) CHECK_NEAR(id.m[i][j], i == j ? 1.0 : 0.0, 1e-12);
    Mat4 zero = mat4_scale(0, 1, 1);
    CHECK(!mat4_inverse(&zero, &inv));

    /* LookAt from (0,0,-5) to the origin with +y up: camera +z is world +z, and pbrt-v4's
     * left-handed frame puts camera +x along world +x (right = up x dir). */
    double eye[3] = {0, 0, -5}, look[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    Mat4 cam;
    CHECK(mat4_lookat(eye, look, up, &cam));
    check_point(&cam, v3(0, 0, 0), v3(0, 0, 5));
    check_point(&cam, v3(1, 0, -5), v3(1, 0, 0));
    check_point(&cam, v3(0, 1, -5), v3(0, 1, 0));
    double bad_up[3] = {0, 0, 1};
    CHECK(!mat4_lookat(eye, look, bad_up, &cam));

    CHECK(mat4_swaps_handedness(&(Mat4){{{-1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}}));
    CHECK(!mat4_swaps_handedness(&r));
    CHECK_DONE();
}
