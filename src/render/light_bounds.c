/* A box around every area light, and whether a ray can reach it (issue 22).
 *
 * The BSDF-sampled ray of a path's last vertex only looks for emitters: the emission it
 * finds is weighed by MIS against light sampling, and the path ends there. In a scene
 * without infinite lights, a ray that misses a box holding every emitter finds no emission
 * whatever Embree would return (a miss, or a surface that does not emit), so its estimate is
 * exactly 0 and the integrator need not trace it (integrator.c, wave_vertex_rays). On
 * soft_shadows.pbrt, lit by a small quad under the ceiling, that is most of those rays.
 *
 * The box is in world units and padded by LIGHT_BOUND_PAD_REL of its largest coordinate:
 * Embree's hit tests round at a few float ulps (about 1e-7 relative) of the coordinates
 * involved, and so does the slab test below, so no hit on an emitter can lie outside it and
 * no ray that reaches the unpadded box is judged to miss the padded one. Emitters that move
 * (a shape in a moving instance's layer) make the box unbounded: then every ray is traced. */
#include "render/light.h"

#include <math.h>

#include "core/transform.h"
#include "core/vectorise.h"

/* the padding, relative to the box's largest |coordinate| (1e4 times float rounding) */
#define LIGHT_BOUND_PAD_REL 1e-3f

static void grow(vec3 *lo, vec3 *hi, vec3 p)
{
    lo->x = p.x < lo->x ? p.x : lo->x, lo->y = p.y < lo->y ? p.y : lo->y, lo->z = p.z < lo->z ? p.z : lo->z;
    hi->x = p.x > hi->x ? p.x : hi->x, hi->y = p.y > hi->y ? p.y : hi->y, hi->z = p.z > hi->z ? p.z : hi->z;
}

void lights_bound_emitters(LightSet *set, const Tracer *tr)
{
    vec3 lo = v3s(INFINITY), hi = v3s(-INFINITY);
    bool bounded = true;
    for (int li = 0; li < tr->layer_count && bounded; ++li) {
        const Layer *layer = &tr->layers[li];
        for (int gi = 0; gi < layer->geom_count && bounded; ++gi) {
            const Geom *g = &layer->geoms[gi];
            if (g->area_light < 0 || g->kind == GEOM_INSTANCE || g->light_first < 0) continue;
            /* lights_build makes emitters of layer 0 (world space) and of moving shapes'
             * own layers, which move */
            if (li != 0) {
                bounded = false;
                break;
            }
            if (g->kind == GEOM_TRIANGLES) {
                /* every vertex of the mesh: unreferenced ones only widen the box */
                for (int k = 0; k < g->vertex_count; ++k) grow(&lo, &hi, v3(g->p[3 * k], g->p[3 * k + 1], g->p[3 * k + 2]));
            } else {
                /* the object-space box of the whole sphere or disk (a partial one lies in
                 * it), its eight corners placed in the world */
                double r = g->radius, z0 = g->kind == GEOM_SPHERE ? -r : g->height, z1 = g->kind == GEOM_SPHERE ? r : g->height;
                for (int c = 0; c < 8; ++c) {
                    vec3 q = v3((float)(c & 1 ? r : -r), (float)(c & 2 ? r : -r), (float)(c & 4 ? z1 : z0));
                    grow(&lo, &hi, mat4_apply_point(&g->geom_from_object, q));
                }
            }
        }
    }
    bool finite = isfinite(lo.x) && isfinite(lo.y) && isfinite(lo.z) && isfinite(hi.x) && isfinite(hi.y) && isfinite(hi.z);
    set->emitters_bounded = bounded && finite && set->has_area;
    if (!set->emitters_bounded) return;
    float pad = LIGHT_BOUND_PAD_REL * fmax_nonneg(v3_max_abs(lo), v3_max_abs(hi));
    set->emitter_lo = v3_sub(lo, v3s(pad));
    set->emitter_hi = v3_add(hi, v3s(pad));
}

/* The slab test over t in [0, inf) for n rays at once (o[axis][k], d[axis][k]), written per
 * lane so that GCC vectorises it (the selections `a < b ? a : b` are IEEE minimum and maximum
 * instructions, with the same operand for an unordered pair). A direction component of 0
 * gives infinite slab distances, and an origin on a slab's plane with it a NaN, which the
 * comparisons pass over (such a ray does not enter the padded box's interior). */
static WEDGE_VECTORISED void rays_may_reach_box(int n, const float *const restrict o[3], const float *const restrict d[3],
                                                 vec3 lo, vec3 hi, int *restrict may)
{
    const float *ox = o[0], *oy = o[1], *oz = o[2], *dx = d[0], *dy = d[1], *dz = d[2];
    for (int k = 0; k < n; ++k) {
        float t_near = 0.0f, t_far = INFINITY;
        float inv = 1.0f / dx[k];
        float t0 = (lo.x - ox[k]) * inv, t1 = (hi.x - ox[k]) * inv;
        float tn = t0 < t1 ? t0 : t1, tf = t0 < t1 ? t1 : t0;
        t_near = tn > t_near ? tn : t_near;
        t_far = tf < t_far ? tf : t_far;
        inv = 1.0f / dy[k];
        t0 = (lo.y - oy[k]) * inv, t1 = (hi.y - oy[k]) * inv;
        tn = t0 < t1 ? t0 : t1, tf = t0 < t1 ? t1 : t0;
        t_near = tn > t_near ? tn : t_near;
        t_far = tf < t_far ? tf : t_far;
        inv = 1.0f / dz[k];
        t0 = (lo.z - oz[k]) * inv, t1 = (hi.z - oz[k]) * inv;
        tn = t0 < t1 ? t0 : t1, tf = t0 < t1 ? t1 : t0;
        t_near = tn > t_near ? tn : t_near;
        t_far = tf < t_far ? tf : t_far;
        may[k] = t_near <= t_far;
    }
}

void lights_rays_may_reach_emitter(const LightSet *set, int n, const float *const o[3], const float *const d[3], int *may)
{
    if (!set->emitters_bounded) {
        for (int k = 0; k < n; ++k) may[k] = 1;
        return;
    }
    rays_may_reach_box(n, o, d, set->emitter_lo, set->emitter_hi, may);
}

bool lights_ray_may_reach_emitter(const LightSet *set, vec3 o, vec3 d)
{
    const float ox = o.x, oy = o.y, oz = o.z, dx = d.x, dy = d.y, dz = d.z;
    const float *const o3[3] = {&ox, &oy, &oz}, *const d3[3] = {&dx, &dy, &dz};
    int may;
    lights_rays_may_reach_emitter(set, 1, o3, d3, &may);
    return may != 0;
}
