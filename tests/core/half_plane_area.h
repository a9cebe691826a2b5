/* Exact area of the part of the unit square on one side of a line: the integral of an edge
 * integrand (a shadow or silhouette boundary) for the sampler's error measurements. */
#ifndef WEDGE_TESTS_HALF_PLANE_AREA_H
#define WEDGE_TESTS_HALF_PLANE_AREA_H

#include <math.h>

/* Area of the unit square where (p - q) . d > 0: the square clipped by the half-plane
 * (one Sutherland-Hodgman step), then the shoelace formula. */
static inline double half_plane_area(double qx, double qy, double dx, double dy)
{
    const double sx[4] = {0, 1, 1, 0}, sy[4] = {0, 0, 1, 1};
    double ox[8], oy[8], twice = 0.0;
    int m = 0;
    for (int i = 0; i < 4; ++i) {
        int j = (i + 1) & 3;
        double a = (sx[i] - qx) * dx + (sy[i] - qy) * dy, b = (sx[j] - qx) * dx + (sy[j] - qy) * dy;
        if (a > 0) ox[m] = sx[i], oy[m++] = sy[i];
        if ((a > 0) != (b > 0)) {
            double t = a / (a - b);
            ox[m] = sx[i] + t * (sx[j] - sx[i]), oy[m++] = sy[i] + t * (sy[j] - sy[i]);
        }
    }
    for (int i = 0; i < m; ++i) twice += ox[i] * oy[(i + 1) % m] - ox[(i + 1) % m] * oy[i];
    return fabs(twice) / 2.0;
}

#endif
