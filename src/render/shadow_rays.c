/* Shadow rays made ahead for a wave's lanes (see shadow_rays.h). */
#include "render/shadow_rays.h"

#include <math.h>

#include "core/vectorise.h"

/* shadow_ray_to for count samples of a point or spot light at target (a finite distance,
 * no offset at the light, as its samples have) from receivers p (geometric normals ng,
 * offsets err), written out per coordinate so that GCC vectorises the loop: the same
 * operations in the same order. redo[k]: the length is outside v3_length's plain range or
 * the distance not finite, and shadow_ray_to must compute that ray itself. */
WEDGE_VECTORISED void point_shadow_rays(int count, const float (*restrict p)[WAVE_SAMPLES],
                                               const float (*restrict ng)[WAVE_SAMPLES], const float *restrict err,
                                               vec3 target, WaveDeltaSamples *restrict ps)
{
    for (int k = 0; k < count; ++k) {
        float nx = ng[0][k], ny = ng[1][k], nz = ng[2][k];
        /* surface_offset */
        float side = nx * ps->wi[0][k] + ny * ps->wi[1][k] + nz * ps->wi[2][k] >= 0.0f ? err[k] : -err[k];
        float ox = p[0][k] + nx * side, oy = p[1][k] + ny * side, oz = p[2][k] + nz * side;
        float dx = target.x - ox, dy = target.y - oy, dz = target.z - oz;
        float len = sqrtf(dx * dx + dy * dy + dz * dz), inv = 1.0f / len;
        ps->o[0][k] = ox, ps->o[1][k] = oy, ps->o[2][k] = oz;
        ps->dir[0][k] = dx * inv, ps->dir[1][k] = dy * inv, ps->dir[2][k] = dz * inv;
        ps->len[k] = len;
        ps->redo[k] = !((len > V3_LENGTH_PLAIN_MIN) & (len < V3_LENGTH_PLAIN_MAX) & (ps->dist[k] < INFINITY));
    }
}

/* shadow_ray_to for lane k of g, a sample of a triangle light (normal n_light, offset
 * err_light > 0): as point_shadow_rays, with the end pushed off the light's surface to the
 * receiver's side. */
static inline __attribute__((always_inline)) void triangle_shadow_ray_lane(float nx, float ny, float nz, float err_light,
                                                                           int k, WaveTriangleSamples *restrict g)
{
    float gx = g->ng[0][k], gy = g->ng[1][k], gz = g->ng[2][k];
    float side = gx * g->wi[0][k] + gy * g->wi[1][k] + gz * g->wi[2][k] >= 0.0f ? g->err[k] : -g->err[k];
    float ox = g->p[0][k] + gx * side, oy = g->p[1][k] + gy * side, oz = g->p[2][k] + gz * side;
    float lx = g->pl[0][k], ly = g->pl[1][k], lz = g->pl[2][k];
    float to_side = nx * (ox - lx) + ny * (oy - ly) + nz * (oz - lz) >= 0.0f ? 1.0f : -1.0f;
    float push = to_side * err_light;
    float dx = (lx + nx * push) - ox, dy = (ly + ny * push) - oy, dz = (lz + nz * push) - oz;
    float len = sqrtf(dx * dx + dy * dy + dz * dz), inv = 1.0f / len;
    g->o[0][k] = ox, g->o[1][k] = oy, g->o[2][k] = oz;
    g->dir[0][k] = dx * inv, g->dir[1][k] = dy * inv, g->dir[2][k] = dz * inv;
    g->len[k] = len;
    g->redo[k] = !((len > V3_LENGTH_PLAIN_MIN) & (len < V3_LENGTH_PLAIN_MAX) & (g->dist[k] < INFINITY));
}

/* The shadow rays of every lane of g, one triangle light's samples. */
WEDGE_VECTORISED void triangle_shadow_rays(vec3 n_light, float err_light, WaveTriangleSamples *restrict g)
{
    for (int k = 0; k < g->count; ++k) triangle_shadow_ray_lane(n_light.x, n_light.y, n_light.z, err_light, k, g);
}

/* Each lane's triangle's normal and offset, loaded by its index as floats (LIGHT_F_...:
 * gathers where the vector width has them), and whether its shadow ray can be made ahead
 * (light_triangle_rays_ahead). */
static inline void mesh_lane_normals(const Light *lights, int count, const int *restrict tri, float *restrict nx,
                                     float *restrict ny, float *restrict nz, float *restrict err, int *restrict ahead)
{
    const float *restrict f = (const float *)lights;
    for (int k = 0; k < count; ++k) {
        int i = tri[k] * LIGHT_FLOATS; /* an index, not a pointer: GCC gathers through the one, not the other */
        float x = f[i + LIGHT_F_TRI_N], y = f[i + LIGHT_F_TRI_N + 1], z = f[i + LIGHT_F_TRI_N + 2];
        float e = f[i + LIGHT_F_TRI_ERR];
        nx[k] = x, ny[k] = y, nz[k] = z, err[k] = e;
        ahead[k] = (e > 0.0f) & (x * x + y * y + z * z > 0.0f);
    }
}

/* The same for a mesh's lanes, each with its own triangle lights[g->tri[k]]; a lane whose
 * triangle has no offset or no normal is left to shadow_ray_to (redo), as a single light's
 * group is: its ray is made, then replaced. */
WEDGE_VECTORISED void mesh_shadow_rays(const Light *lights, WaveTriangleSamples *restrict g)
{
    float nx[WAVE_SAMPLES], ny[WAVE_SAMPLES], nz[WAVE_SAMPLES], err[WAVE_SAMPLES];
    int ahead[WAVE_SAMPLES];
    mesh_lane_normals(lights, g->count, g->tri, nx, ny, nz, err, ahead);
    for (int k = 0; k < g->count; ++k) triangle_shadow_ray_lane(nx[k], ny[k], nz[k], err[k], k, g);
    /* apart: as selects in the loop above they kept it scalar */
    for (int k = 0; k < g->count; ++k) {
        if (ahead[k]) continue;
        g->o[0][k] = g->o[1][k] = g->o[2][k] = g->dir[0][k] = g->dir[1][k] = g->dir[2][k] = g->len[k] = 0.0f;
        g->redo[k] = 1;
    }
}

/* shadow_ray_to for the samples of a constant sky in g (directions wi, an infinite
 * distance): from the receiver pushed off its surface towards wi (surface_offset), along
 * wi, unbounded; never redone. */
WEDGE_VECTORISED void sky_shadow_rays(WaveTriangleSamples *restrict g)
{
    for (int k = 0; k < g->count; ++k) {
        float gx = g->ng[0][k], gy = g->ng[1][k], gz = g->ng[2][k];
        float wx = g->wi[0][k], wy = g->wi[1][k], wz = g->wi[2][k];
        float side = gx * wx + gy * wy + gz * wz >= 0.0f ? g->err[k] : -g->err[k];
        g->o[0][k] = g->p[0][k] + gx * side, g->o[1][k] = g->p[1][k] + gy * side, g->o[2][k] = g->p[2][k] + gz * side;
        g->dir[0][k] = wx, g->dir[1][k] = wy, g->dir[2][k] = wz;
        g->len[k] = INFINITY;
        g->redo[k] = 0;
    }
}
