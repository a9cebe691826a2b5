/* The swept extent of a moving planar light (see maaf_light_sweep.h). */
#include "recon/maaf/maaf_light_sweep.h"

#include <math.h>

static double dot3d(const double a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The pose at shutter time u of the emitter light l belongs to (every triangle of its shape):
 * its area-weighted centroid and its extent along l's axes from that centroid. */
static bool pose_at(const Renderer *r, int light, float u, float disk_half, const MaafLight *l, double c[3],
                    double lo[2], double hi[2])
{
    RenderLightInfo me;
    if (!renderer_light_info_at(r, light, u, &me) || me.kind != RENDER_LIGHT_AREA) return false;
    if (!me.is_triangle) { /* a disk: its box of the same area around its centre */
        c[0] = me.center_world.x, c[1] = me.center_world.y, c[2] = me.center_world.z;
        lo[0] = lo[1] = -disk_half;
        hi[0] = hi[1] = disk_half;
        return true;
    }
    double area = 0.0;
    c[0] = c[1] = c[2] = 0.0;
    int count = renderer_light_count(r);
    for (int pass = 0; pass < 2; ++pass) {
        lo[0] = lo[1] = INFINITY;
        hi[0] = hi[1] = -INFINITY;
        for (int k = 0; k < count; ++k) {
            RenderLightInfo b;
            if (k == light) b = me;
            else if (me.shape < 0 || !renderer_light_info_at(r, k, u, &b) || b.kind != RENDER_LIGHT_AREA ||
                     b.shape != me.shape || !b.is_triangle)
                continue;
            if (pass == 0) { /* the centroid first */
                c[0] += b.area_world * b.center_world.x;
                c[1] += b.area_world * b.center_world.y;
                c[2] += b.area_world * b.center_world.z;
                area += b.area_world;
                continue;
            }
            for (int v = 0; v < 3; ++v) {
                double d[3] = {b.tri_world[v].x - c[0], b.tri_world[v].y - c[1], b.tri_world[v].z - c[2]};
                double a1 = dot3d(d, l->t1), a2 = dot3d(d, l->t2);
                lo[0] = fmin(lo[0], a1), hi[0] = fmax(hi[0], a1);
                lo[1] = fmin(lo[1], a2), hi[1] = fmax(hi[1], a2);
            }
        }
        if (pass == 0) {
            if (!(area > 0.0)) return false;
            for (int k = 0; k < 3; ++k) c[k] /= area;
        }
    }
    return hi[0] > lo[0] && hi[1] > lo[1];
}

bool maaf_light_sweep(const Renderer *r, int light, float disk_half, MaafLight *l)
{
    RenderLightInfo info;
    if (!renderer_light_info(r, light, &info) || info.kind != RENDER_LIGHT_AREA || !info.moving) return false;
    if (l->t1[0] == 0.0f && l->t1[1] == 0.0f && l->t1[2] == 0.0f) return false; /* a sphere */
    double c[MAAF_SWEEP_NODES][3], lo[MAAF_SWEEP_NODES][2], hi[MAAF_SWEEP_NODES][2], mean[3] = {0, 0, 0};
    for (int k = 0; k < MAAF_SWEEP_NODES; ++k) {
        if (!pose_at(r, light, (float)((k + 0.5) / MAAF_SWEEP_NODES), disk_half, l, c[k], lo[k], hi[k])) return false;
        for (int i = 0; i < 3; ++i) mean[i] += c[k][i] / MAAF_SWEEP_NODES;
    }
    for (int i = 0; i < 3; ++i) l->center[i] = (float)mean[i];
    /* the union of the poses' extents, the shutter's ends included (no sample falls outside) */
    l->lo[0] = l->lo[1] = INFINITY;
    l->hi[0] = l->hi[1] = -INFINITY;
    for (int end = 0; end < 2; ++end) {
        double ce[3], loe[2], hie[2];
        if (!pose_at(r, light, (float)end, disk_half, l, ce, loe, hie)) continue;
        double shift[3] = {ce[0] - mean[0], ce[1] - mean[1], ce[2] - mean[2]};
        double s[2] = {dot3d(shift, l->t1), dot3d(shift, l->t2)};
        for (int a = 0; a < 2; ++a) {
            l->lo[a] = fminf(l->lo[a], (float)(loe[a] + s[a]));
            l->hi[a] = fmaxf(l->hi[a], (float)(hie[a] + s[a]));
        }
    }
    for (int k = 0; k < MAAF_SWEEP_NODES; ++k) {
        double shift[3] = {c[k][0] - mean[0], c[k][1] - mean[1], c[k][2] - mean[2]};
        double s[2] = {dot3d(shift, l->t1), dot3d(shift, l->t2)};
        for (int a = 0; a < 2; ++a) {
            l->sweep_lo[a][k] = (float)(lo[k][a] + s[a]);
            l->sweep_hi[a][k] = (float)(hi[k][a] + s[a]);
            l->lo[a] = fminf(l->lo[a], l->sweep_lo[a][k]);
            l->hi[a] = fmaxf(l->hi[a], l->sweep_hi[a][k]);
        }
    }
    l->sweep_nodes = MAAF_SWEEP_NODES;
    return true;
}
