/* The shading of many sphere hits at once (issue 22): the top-level sphere case of
 * tracer.c's shade_hit, in a loop over the hits that GCC vectorises. */
#ifndef WEDGE_RENDER_SPHERE_SHADE_H
#define WEDGE_RENDER_SPHERE_SHADE_H

#include "core/transform.h"

/* One sphere's hits, one lane each: the world ray (o, d) and Embree's hit distance in
 * tracer units (tfar) in; the world-space distance t, point p and unit normal n (before
 * the sphere's orientation flip) and the offset magnitude mag out. ok[k] = 0 where the
 * normal's length was outside v3_normalize's plain range: that lane's n is not the
 * scalar code's and it must be shaded one by one. */
enum { SPHERE_SHADE_MAX = 64 }; /* lanes: a chunk of the tracer's batches */
typedef struct {
    int count;
    float o[3][SPHERE_SHADE_MAX], d[3][SPHERE_SHADE_MAX], tfar[SPHERE_SHADE_MAX];
    float t[SPHERE_SHADE_MAX], p[3][SPHERE_SHADE_MAX], n[3][SPHERE_SHADE_MAX], mag[SPHERE_SHADE_MAX];
    int ok[SPHERE_SHADE_MAX];
} SphereShadeBatch;

/* For the sphere of the given radius placed by geom_from_object (object_from_geom its
 * inverse) at the top level, world_from_tracer the tracer's scale and reach its
 * quadric_reach: each lane's values are shade_hit's, bit for bit. */
void sphere_shade_batch(SphereShadeBatch *b, const Mat4 *object_from_geom, const Mat4 *geom_from_object, double radius,
                        float world_from_tracer, double reach);

/* The same for a sphere placed by a translation alone (centre in geometry space): each lane's
 * values are tracer.c's sphere_hit_shade's, bit for bit (mostly float: docs/algorithms.md, "A
 * translated sphere's hit in float"). */
void sphere_shade_batch_translated(SphereShadeBatch *b, const double centre[3], double radius, float world_from_tracer,
                                   double reach);

#endif
