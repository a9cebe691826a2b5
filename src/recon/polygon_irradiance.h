/* Exact unoccluded irradiance from a planar polygonal emitter (Lambert's polygon formula).
 *
 * The projected solid angle of a polygon seen from a receiver at p with unit normal n,
 *
 *     Phi = integral over the polygon's solid angle of max(0, cos(n, w)) dw     [sr]
 *         = integral over its area of cos(n, q - p) |cos(n_L, q - p)| / |q - p|^2 dA,
 *
 * is, for the part above the receiver's horizon, (1/2) sum_i theta_i (n . g_i): theta_i the
 * angle the edge (v_i, v_i+1) subtends at p and g_i the unit normal of the plane through p
 * and that edge. The polygon is first clipped to the receiver's upper half space, so the
 * result is exact at grazing angles too, where a fixed quadrature is worst (it is what the
 * shadow filter divides the direct light by, AAF-shadow eq. 1, docs/algorithms.md 1.7). */
#ifndef WEDGE_RECON_POLYGON_IRRADIANCE_H
#define WEDGE_RECON_POLYGON_IRRADIANCE_H

#include <math.h>

/* Most vertices a polygon may have (clipping adds at most one). */
enum { POLYGON_MAX_VERTS = 32 };

/* Phi (steradians, >= 0) of the convex polygon v[0..count-1] (world, either winding) seen
 * from p with unit normal n. count in [3, POLYGON_MAX_VERTS - 1]; else 0. */
double polygon_projected_solid_angle(const double p[3], const double n[3], const double v[][3], int count);

/* The pieces of that sum, shared with recon/shared_triangles.c so that both compute the same
 * doubles in the same order (its results equal polygon_projected_solid_angle's bit for bit). */
static inline double polygon_dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* An edge between the unit directions a and b: c = a x b, returns |c| = sin(theta_i) (not > 0
 * for coincident directions, whose edge adds nothing). */
static inline double polygon_edge_cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
    return sqrt(polygon_dot3(c, c));
}

/* Phi from the edges' sum of theta_i (n . c) / |c|: the sign follows the winding; not finite: 0. */
static inline double polygon_phi_of_sum(double sum)
{
    double phi = 0.5 * fabs(sum);
    return isfinite(phi) ? phi : 0.0;
}

/* A receiver p closer to the plane through q with unit normal nl than this share of their
 * coordinates' size and distance (the rounding of a hit point on that plane) lies in it. */
#define POLYGON_PLANE_TOL_REL 1e-5

/* The signed distance of p from that plane, or 0 when p lies in it (POLYGON_PLANE_TOL_REL).
 * An emitter gives a receiver in its own plane no light: it subtends no solid angle there, and
 * for a point on it (a pixel that sees the back of a one-sided light, lit by another) Lambert's
 * formula, whose edges then all lie on the receiver's horizon, gives anything from 0 to pi. */
static inline double polygon_plane_side(const double p[3], const double q[3], const double nl[3])
{
    double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    double side = polygon_dot3(nl, d), size = sqrt(polygon_dot3(d, d));
    for (int k = 0; k < 3; ++k) size += fabs(p[k]) + fabs(q[k]);
    return fabs(side) > POLYGON_PLANE_TOL_REL * size ? side : 0.0;
}

#endif
