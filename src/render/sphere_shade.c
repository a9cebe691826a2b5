/* The top-level sphere case of tracer.c's shade_hit for many hits at once (issue 22).
 *
 * shade_hit takes a sphere hit's point into object space by a double 4x4 transform,
 * reprojects it onto the sphere (a double square root and division), takes it back by a
 * second transform and normalises the normal in float (a square root and a division
 * more): a chain of dependent long-latency operations per hit, which the hits of a chunk
 * of rays do not need to wait on. Here every lane does exactly those operations in their
 * order (IEEE + - * / and sqrt round the same in every width; C11 mode contracts no
 * multiply-add, docs/design.md 12.4), as one loop that GCC vectorises: the same values bit
 * for bit, with the exits made selects. */
#include "render/sphere_shade.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/vec.h"
#include "core/vectorise.h"

/* Lane k's results: t, the point, the unit normal, whether the normal's length l was in
 * v3_normalize's plain range, and the offset magnitude v3_max_abs(p) + reach (fmax_nonneg's
 * NaN rule as a select). Inline in both loops. */
static inline void lane_store(SphereShadeBatch *restrict b, int k, float t, float px, float py, float pz, float nx,
                              float ny, float nz, float l, float reach_f)
{
    b->ok[k] = (l > V3_LENGTH_PLAIN_MIN) & (l < V3_LENGTH_PLAIN_MAX);
    b->n[0][k] = nx, b->n[1][k] = ny, b->n[2][k] = nz;
    b->p[0][k] = px, b->p[1][k] = py, b->p[2][k] = pz;
    b->t[k] = t;
    float ax = fabsf(px), ay = fabsf(py), az = fabsf(pz);
    float myz = (ay > az || az != az) ? ay : az;
    float mxyz = (ax > myz || myz != myz) ? ax : myz;
    b->mag[k] = mxyz + reach_f;
}

WEDGE_VECTORISED void sphere_shade_batch(SphereShadeBatch *restrict b, const Mat4 *object_from_geom,
                                         const Mat4 *geom_from_object, double radius, float world_from_tracer,
                                         double reach)
{
    const double(*m)[4] = object_from_geom->m, (*g)[4] = geom_from_object->m;
    /* the loop-invariant matrix entries as scalars (no aliasing with the lanes' arrays) */
    const double a00 = m[0][0], a01 = m[0][1], a02 = m[0][2], a03 = m[0][3];
    const double a10 = m[1][0], a11 = m[1][1], a12 = m[1][2], a13 = m[1][3];
    const double a20 = m[2][0], a21 = m[2][1], a22 = m[2][2], a23 = m[2][3];
    const double g00 = g[0][0], g01 = g[0][1], g02 = g[0][2], g03 = g[0][3];
    const double g10 = g[1][0], g11 = g[1][1], g12 = g[1][2], g13 = g[1][3];
    const double g20 = g[2][0], g21 = g[2][1], g22 = g[2][2], g23 = g[2][3];
    const float reach_f = (float)reach;
    for (int k = 0; k < b->count; ++k) {
        float t = world_from_tracer * b->tfar[k];
        /* the ray's point in double, then apply_point_d into object space */
        double p0 = (double)b->o[0][k] + (double)t * b->d[0][k];
        double p1 = (double)b->o[1][k] + (double)t * b->d[1][k];
        double p2 = (double)b->o[2][k] + (double)t * b->d[2][k];
        double q0 = a00 * p0 + a01 * p1 + a02 * p2 + a03;
        double q1 = a10 * p0 + a11 * p1 + a12 * p2 + a13;
        double q2 = a20 * p0 + a21 * p1 + a22 * p2 + a23;
        /* reprojected onto the surface when len > 0 (the quotient is computed in every lane
         * and kept by a select) */
        double len = sqrt(q0 * q0 + q1 * q1 + q2 * q2);
        double s = radius / len;
        int scale = len > 0.0;
        double r0 = scale ? q0 * s : q0, r1 = scale ? q1 * s : q1, r2 = scale ? q2 * s : q2;
        /* back to geometry space (apply_point_d), rounded to float */
        float px = (float)(g00 * r0 + g01 * r1 + g02 * r2 + g03);
        float py = (float)(g10 * r0 + g11 * r1 + g12 * r2 + g13);
        float pz = (float)(g20 * r0 + g21 * r1 + g22 * r2 + g23);
        /* the normal: mat4_apply_normal of the float object-space point, v3_normalize's
         * plain case */
        double x = (float)r0, y = (float)r1, z = (float)r2;
        float nx = (float)(a00 * x + a10 * y + a20 * z);
        float ny = (float)(a01 * x + a11 * y + a21 * z);
        float nz = (float)(a02 * x + a12 * y + a22 * z);
        float l = sqrtf(nx * nx + ny * ny + nz * nz);
        float inv = 1.0f / l;
        lane_store(b, k, t, px, py, pz, nx * inv, ny * inv, nz * inv, l, reach_f);
    }
}

/* sphere_hit_shade (tracer.c) for a sphere placed by a translation alone, lane by lane: the
 * offset from the centre in double rounded to float, the hit's offset and its normalisation in
 * float, the point c + r n in double rounded once. The same operations in the same order, so
 * each lane's values are sphere_hit_shade's bit for bit (ok = 0 where v3_normalize would leave
 * its plain case). */
WEDGE_VECTORISED void sphere_shade_batch_translated(SphereShadeBatch *restrict b, const double centre[3], double radius,
                                                    float world_from_tracer, double reach)
{
    const double cx = centre[0], cy = centre[1], cz = centre[2], r = radius;
    const float reach_f = (float)reach;
    for (int k = 0; k < b->count; ++k) {
        float t = world_from_tracer * b->tfar[k];
        float ox = (float)((double)b->o[0][k] - cx), oy = (float)((double)b->o[1][k] - cy),
              oz = (float)((double)b->o[2][k] - cz);
        float vx = ox + b->d[0][k] * t, vy = oy + b->d[1][k] * t, vz = oz + b->d[2][k] * t;
        float l = sqrtf(vx * vx + vy * vy + vz * vz);
        float inv = 1.0f / l;
        float nx = vx * inv, ny = vy * inv, nz = vz * inv;
        float px = (float)(cx + r * (double)nx), py = (float)(cy + r * (double)ny), pz = (float)(cz + r * (double)nz);
        lane_store(b, k, t, px, py, pz, nx, ny, nz, l, reach_f);
    }
}
