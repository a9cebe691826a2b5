/* Which of Embree's two builds a layer's scene gets (layer_build.h). */
#include "render/layer_build.h"

#include <math.h>

/* The surface area of the box lo .. hi (zero for an empty box). */
static double box_area(const double lo[3], const double hi[3])
{
    double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    if (!(dx >= 0.0 && dy >= 0.0 && dz >= 0.0)) return 0.0;
    return 2.0 * (dx * dy + dy * dz + dz * dx);
}

bool layer_build_two_level(const Geom *geoms, int count)
{
    double all_lo[3] = {INFINITY, INFINITY, INFINITY}, all_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double area_sum = 0.0, area_max = 0.0;
    int meshes = 0;
    for (int i = 0; i < count; ++i) {
        const Geom *g = &geoms[i];
        if (g->kind != GEOM_TRIANGLES || g->vertex_count <= 0) continue;
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int v = 0; v < g->vertex_count; ++v)
            for (int a = 0; a < 3; ++a) {
                double x = g->p[3 * v + a];
                lo[a] = x < lo[a] ? x : lo[a];
                hi[a] = x > hi[a] ? x : hi[a];
            }
        for (int a = 0; a < 3; ++a) {
            all_lo[a] = lo[a] < all_lo[a] ? lo[a] : all_lo[a];
            all_hi[a] = hi[a] > all_hi[a] ? hi[a] : all_hi[a];
        }
        double area = box_area(lo, hi);
        area_sum += area;
        area_max = area > area_max ? area : area_max;
        ++meshes;
    }
    double area_all = box_area(all_lo, all_hi);
    return meshes >= 2 && area_all > 0.0 && area_sum - area_max >= LAYER_TWO_LEVEL_SHARE * area_all;
}
