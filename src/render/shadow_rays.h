/* Shadow rays from a receiver to a light sample: one at a time (shadow_ray_make, the
 * definition) and for a wave's lanes ahead of tracing (the batch builders below), which make
 * the same rays with the same operations in the same order, so that both give the same bits.
 * A lane whose ray would need v3_length's scaled path (a length outside
 * [V3_LENGTH_PLAIN_MIN, V3_LENGTH_PLAIN_MAX]) or whose light is at no finite distance is
 * marked redo, and shadow_ray_make computes that ray itself. */
#ifndef WEDGE_RENDER_SHADOW_RAYS_H
#define WEDGE_RENDER_SHADOW_RAYS_H

#include <stdbool.h>

#include "core/vec.h"
#include "render/light.h"
#include "render/tracer.h"
#include "render/wave_light_lanes.h"

/* The shadow ray from the receiver h to light sample ls: it leaves the receiver (pushed off
 * its surface towards the light) and stops short of the light's surface (pushed off it by
 * err_light to the receiver's side), or runs unbounded to a light at no finite distance.
 * False when the two ends coincide (no direction). */
static inline bool shadow_ray_make(const SurfaceHit *h, const LightSample *ls, vec3 *o, vec3 *dir, float *tmax)
{
    *o = surface_offset(h, ls->wi);
    *dir = ls->wi;
    *tmax = INFINITY;
    if (!isfinite(ls->dist)) return true;
    vec3 target = ls->p_light;
    if (ls->err_light > 0.0f && v3_length2(ls->n_light) > 0.0f) {
        float side = v3_dot(ls->n_light, v3_sub(*o, ls->p_light)) >= 0.0f ? 1.0f : -1.0f;
        target = v3_madd(ls->p_light, ls->n_light, side * ls->err_light);
    }
    vec3 d = v3_sub(target, *o);
    float len = v3_length(d);
    if (!(len > 0.0f)) return false;
    *dir = v3_scale(d, 1.0f / len);
    *tmax = len;
    return true;
}

/* Lanes [0, count) of a point or spot light's samples ps (wi, dist) at target (no offset at
 * the light) from receivers p with geometric normals ng and offsets err: ps's o, dir, len and
 * redo. */
void point_shadow_rays(int count, const float (*restrict p)[WAVE_SAMPLES], const float (*restrict ng)[WAVE_SAMPLES],
                       const float *restrict err, vec3 target, WaveDeltaSamples *restrict ps);

/* Every lane of g, samples of one triangle light of normal n_light and offset err_light > 0
 * (g's receivers p, ng, err, samples wi, dist, pl): g's o, dir, len and redo. */
void triangle_shadow_rays(vec3 n_light, float err_light, WaveTriangleSamples *restrict g);

/* The same for a mesh's lanes, lane k's triangle lights[g->tri[k]]; a lane whose triangle has
 * no offset or no normal is zeroed and marked redo. */
void mesh_shadow_rays(const Light *lights, WaveTriangleSamples *restrict g);

/* A constant sky's lanes: from the receiver pushed towards wi, along wi, unbounded. */
void sky_shadow_rays(WaveTriangleSamples *restrict g);

#endif
