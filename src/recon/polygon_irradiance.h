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

/* Most vertices a polygon may have (clipping adds at most one). */
enum { POLYGON_MAX_VERTS = 32 };

/* Phi (steradians, >= 0) of the convex polygon v[0..count-1] (world, either winding) seen
 * from p with unit normal n. count in [3, POLYGON_MAX_VERTS - 1]; else 0. */
double polygon_projected_solid_angle(const double p[3], const double n[3], const double v[][3], int count);

#endif
