/* 4x4 affine/projective transforms with pbrt-v4 semantics (row-major, column vectors,
 * points are transformed as M * (x, y, z, 1)). Double precision: composing long chains of
 * scene-file transforms must not drift. */
#ifndef WEDGE_CORE_TRANSFORM_H
#define WEDGE_CORE_TRANSFORM_H

#include <stdbool.h>
#include "core/vec.h"

typedef struct { double m[4][4]; } Mat4;

Mat4 mat4_identity(void);
Mat4 mat4_mul(const Mat4 *a, const Mat4 *b);            /* a * b: b applied first */
bool mat4_inverse(const Mat4 *a, Mat4 *out);             /* false if singular */
Mat4 mat4_transpose(const Mat4 *a);
bool mat4_equal(const Mat4 *a, const Mat4 *b);           /* exact element equality */
bool mat4_is_identity(const Mat4 *a);

Mat4 mat4_translate(double dx, double dy, double dz);
Mat4 mat4_scale(double sx, double sy, double sz);
/* Rotation by angle_deg about axis (normalised here), as pbrt-v4 Rotate. */
Mat4 mat4_rotate(double angle_deg, double ax, double ay, double az);
/* pbrt-v4 LookAt: returns camera-from-world (left-handed camera space, +z forward).
 * Returns false (and identity) when up is parallel to the view direction or eye == look. */
bool mat4_lookat(const double eye[3], const double look[3], const double up[3], Mat4 *out);

vec3 mat4_apply_point(const Mat4 *m, vec3 p);   /* divides by w when w != 1 */
vec3 mat4_apply_vector(const Mat4 *m, vec3 v);
/* Normals transform by the inverse transpose: pass the inverse of the object's matrix. */
static inline vec3 mat4_apply_normal(const Mat4 *inv, vec3 n)
{
    double x = n.x, y = n.y, z = n.z;
    return v3((float)(inv->m[0][0] * x + inv->m[1][0] * y + inv->m[2][0] * z),
              (float)(inv->m[0][1] * x + inv->m[1][1] * y + inv->m[2][1] * z),
              (float)(inv->m[0][2] * x + inv->m[1][2] * y + inv->m[2][2] * z));
}
/* True when the transform flips handedness (negative determinant of the 3x3 part). */
bool mat4_swaps_handedness(const Mat4 *m);

#endif
