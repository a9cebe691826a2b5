/* The swept extent of a moving planar light (see maaf_light_sweep.h). */
#include "recon/maaf/maaf_light_sweep.h"

#include "recon/moving_lights.h"

_Static_assert(MAAF_SWEEP_NODES == RECON_SWEEP_POSES, "MAAF's sweep nodes are the shared sweep's poses");

bool maaf_light_sweep(const Renderer *r, int light, float disk_half, MaafSweep *poses, MaafLight *l)
{
    RenderLightInfo info;
    if (!renderer_light_info(r, light, &info) || info.kind != RENDER_LIGHT_AREA || !info.moving) return false;
    if (l->t1[0] == 0.0f && l->t1[1] == 0.0f && l->t1[2] == 0.0f) return false; /* a sphere */
    if (!poses) return false;
    ReconLightSweep s;
    if (!recon_light_sweep(r, light, disk_half, l->t1, l->t2, &s)) return false;
    for (int i = 0; i < 3; ++i) l->center[i] = (float)s.centre[i];
    for (int a = 0; a < 2; ++a) {
        l->lo[a] = s.lo[a], l->hi[a] = s.hi[a];
        for (int k = 0; k < MAAF_SWEEP_NODES; ++k) poses->lo[a][k] = s.pose_lo[a][k], poses->hi[a][k] = s.pose_hi[a][k];
    }
    l->sweep_nodes = MAAF_SWEEP_NODES;
    l->sweep = poses;
    return true;
}
