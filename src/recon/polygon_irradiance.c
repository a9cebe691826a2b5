/* Lambert's polygon formula with horizon clipping (see polygon_irradiance.h). */
#include "recon/polygon_irradiance.h"

#include <math.h>

/* Sutherland-Hodgman against the plane h(q) = n . (q - p) >= 0, in receiver-relative
 * coordinates. Returns the clipped vertex count (0 when nothing is above the horizon). */
static int clip_to_horizon(const double n[3], const double in[][3], int count, double out[][3])
{
    int m = 0;
    for (int i = 0; i < count; ++i) {
        const double *a = in[i], *b = in[(i + 1) % count];
        double ha = polygon_dot3(n, a), hb = polygon_dot3(n, b);
        if (ha >= 0.0) {
            for (int k = 0; k < 3; ++k) out[m][k] = a[k];
            ++m;
        }
        if ((ha >= 0.0) != (hb >= 0.0)) { /* the edge crosses the horizon: add the crossing */
            double t = ha / (ha - hb);
            for (int k = 0; k < 3; ++k) out[m][k] = a[k] + t * (b[k] - a[k]);
            ++m;
        }
    }
    return m;
}

double polygon_projected_solid_angle(const double p[3], const double n[3], const double v[][3], int count)
{
    if (count < 3 || count >= POLYGON_MAX_VERTS) return 0.0;
    double rel[POLYGON_MAX_VERTS][3], clipped[POLYGON_MAX_VERTS][3];
    for (int i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) rel[i][k] = v[i][k] - p[k];
    int m = clip_to_horizon(n, rel, count, clipped);
    if (m < 3) return 0.0;
    /* unit directions to the vertices; a vertex at the receiver itself contributes nothing */
    double u[POLYGON_MAX_VERTS][3];
    for (int i = 0; i < m; ++i) {
        double len = sqrt(polygon_dot3(clipped[i], clipped[i]));
        if (!(len > 0.0)) return 0.0;
        for (int k = 0; k < 3; ++k) u[i][k] = clipped[i][k] / len;
    }
    double sum = 0.0;
    for (int i = 0; i < m; ++i) {
        const double *a = u[i], *b = u[(i + 1) % m];
        double c[3], s = polygon_edge_cross(a, b, c);
        if (!(s > 0.0)) continue; /* coincident directions: a zero-length edge */
        double theta = atan2(s, polygon_dot3(a, b));
        sum += theta * polygon_dot3(c, n) / s;
    }
    return polygon_phi_of_sum(sum);
}
