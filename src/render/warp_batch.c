/* The warps of warp.h over whole runs of samples, as loops that GCC vectorises (issue 22,
 * docs/design.md 12.4): the lens positions of a run's camera samples and the cosine-weighted
 * directions of its vertices' BSDF samples. Each lane does warp.h's operations in its order
 * (the branch-free concentric map; the polynomial sin and cos; one square root), so every
 * copy gives the inline functions' values bit for bit (test_pick_warp compares them). */
#include "render/warp.h"

#include "core/vectorise.h"

WEDGE_VECTORISED void warp_disk_concentric_run(int count, const vec2 *restrict u, float *restrict x, float *restrict y)
{
    for (int i = 0; i < count; ++i) {
        vec2 d = warp_disk_concentric(u[i]);
        x[i] = d.x, y[i] = d.y;
    }
}

WEDGE_VECTORISED void warp_cosine_hemisphere_run(int count, const vec2 *restrict u, float *restrict x, float *restrict y,
                                                 float *restrict z)
{
    for (int i = 0; i < count; ++i) {
        vec3 d = warp_cosine_hemisphere(u[i]);
        x[i] = d.x, y[i] = d.y, z[i] = d.z;
    }
}
