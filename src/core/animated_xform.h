/* Transforms that move during the shutter, as pbrt-v4's AnimatedTransform: each end matrix
 * is decomposed into translation T, rotation R (unit quaternion) and scale/shear S
 * (M = T R S, polar decomposition); in between, T and S are interpolated linearly and R by
 * slerp, so rotating objects stay rigid. */
#ifndef WEDGE_CORE_ANIMATED_XFORM_H
#define WEDGE_CORE_ANIMATED_XFORM_H

#include <stdbool.h>

#include "core/transform.h"

typedef struct {
    double x, y, z, w; /* w is the scalar part */
} Quat;

typedef struct {
    Mat4 start, end;
    bool animated;        /* start != end */
    double t[2][3];       /* translation at start/end */
    Quat r[2];            /* rotation at start/end (r[1] sign chosen for the shorter arc) */
    Mat4 s[2];            /* scale/shear at start/end (upper 3x3 used) */
} AnimXform;

void anim_xform_init(AnimXform *a, const Mat4 *start, const Mat4 *end);
/* The transform at normalised shutter time u in [0, 1] (0 = start, 1 = end). */
Mat4 anim_xform_at(const AnimXform *a, double u);
/* Polar decomposition of an affine matrix: m = T * R * S. */
void mat4_decompose(const Mat4 *m, double t[3], Quat *r, Mat4 *s);
Mat4 quat_to_mat4(Quat q);
Quat quat_slerp(Quat a, Quat b, double u);

/* Rotation matrix (upper 3x3 of m, assumed orthonormal with determinant +1) to a unit
 * quaternion. */
Quat quat_from_mat4(const Mat4 *m);
/* A conservative axis-aligned bound of the box [lo, hi] (object space) moved by `a` over the
 * shutter interval [u0, u1] (0 <= u0 <= u1 <= 1): every point of the box at every time in
 * the interval lies inside [out_lo, out_hi]. Sampled at several times and padded by a bound
 * on how far the motion can bulge between samples (rotation arcs). */
void anim_xform_motion_bounds(const AnimXform *a, const double lo[3], const double hi[3], double u0,
                              double u1, double out_lo[3], double out_hi[3]);

#endif
