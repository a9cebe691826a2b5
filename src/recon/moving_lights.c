/* A frame's moving area lights: whether any moves, their poses and swept extent (see
 * moving_lights.h). */
#include "recon/moving_lights.h"

#include <math.h>

#include "render/integrator.h"
#include "render/light.h"
#include "render/tracer.h"

bool recon_area_light_moves(const Renderer *r)
{
    const IntegratorScene *isc = renderer_integrator_scene(r);
    if (!isc || !isc->lights || !isc->tracer) return false;
    for (int i = 0; i < isc->lights->count; ++i) {
        const Light *l = &isc->lights->lights[i];
        if (l->kind != LIGHT_AREA || l->instance < 0 || l->instance >= isc->tracer->instance_count) continue;
        if (isc->tracer->instances[l->instance].moving) return true;
    }
    return false;
}

static double dot3d(const double a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

bool recon_light_pose(const Renderer *r, int light, float u, float disk_half, const float axis1[3],
                      const float axis2[3], double c[3], double lo[2], double hi[2])
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
                double a1 = dot3d(d, axis1), a2 = dot3d(d, axis2);
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

bool recon_light_sweep(const Renderer *r, int light, float disk_half, const float axis1[3], const float axis2[3],
                       ReconLightSweep *s)
{
    enum { N = RECON_SWEEP_POSES };
    double c[N][3], lo[N][2], hi[N][2], mean[3] = {0, 0, 0};
    for (int k = 0; k < N; ++k) {
        if (!recon_light_pose(r, light, (float)((k + 0.5) / N), disk_half, axis1, axis2, c[k], lo[k], hi[k]))
            return false;
        for (int i = 0; i < 3; ++i) mean[i] += c[k][i] / N;
    }
    for (int i = 0; i < 3; ++i) s->centre[i] = mean[i];
    /* the union of the poses' extents, the shutter's ends included (no sample falls outside) */
    s->lo[0] = s->lo[1] = INFINITY;
    s->hi[0] = s->hi[1] = -INFINITY;
    for (int end = 0; end < 2; ++end) {
        double *ce = s->end_centre[end], *loe = s->end_lo[end], *hie = s->end_hi[end];
        s->ends_ok[end] = recon_light_pose(r, light, (float)end, disk_half, axis1, axis2, ce, loe, hie);
        if (!s->ends_ok[end]) continue;
        double shift[3] = {ce[0] - mean[0], ce[1] - mean[1], ce[2] - mean[2]};
        double sh[2] = {dot3d(shift, axis1), dot3d(shift, axis2)};
        for (int a = 0; a < 2; ++a) {
            s->lo[a] = fminf(s->lo[a], (float)(loe[a] + sh[a]));
            s->hi[a] = fmaxf(s->hi[a], (float)(hie[a] + sh[a]));
        }
    }
    for (int k = 0; k < N; ++k) {
        double shift[3] = {c[k][0] - mean[0], c[k][1] - mean[1], c[k][2] - mean[2]};
        double sh[2] = {dot3d(shift, axis1), dot3d(shift, axis2)};
        for (int a = 0; a < 2; ++a) {
            s->pose_lo[a][k] = (float)(lo[k][a] + sh[a]);
            s->pose_hi[a][k] = (float)(hi[k][a] + sh[a]);
            s->lo[a] = fminf(s->lo[a], s->pose_lo[a][k]);
            s->hi[a] = fmaxf(s->hi[a], s->pose_hi[a][k]);
        }
    }
    return true;
}
