/* A curved mesh emitter's projected solid angle through the boundaries of the parts of it that
 * face a receiver.
 *
 * Lambert's formula (polygon_irradiance.h) sums a term per polygon edge that changes sign with the
 * edge's direction. Over triangles that all face the receiver from the same side and lie wholly
 * above its horizon, every triangle's signed sum has the same sign, so their projected solid
 * angles add up to half the absolute sum of the terms, and an edge two of them share in opposite
 * directions cancels: only the edges on the boundary of such a set count. A planar mesh is one
 * such set from any receiver off its plane (emitter_boundary.h); a curved one is not, but it is
 * made of many: the triangles are put in a tree (Morton order of their centroids), each node
 * with a bounding sphere and a cone holding its triangles' normals, and a receiver takes a node
 * whole, through the edges on the node's boundary, when the sphere lies above its horizon and
 * the cone and the sphere's angular size show every triangle facing it from one side (or away,
 * for a one-sided emitter: nothing). Other nodes are split, down to single triangles, which are
 * summed alone (clipped to the horizon where it cuts them). The result is the sum of the
 * triangles' own projected solid angles (what summing them one by one gives) to rounding, at the
 * cost of the nodes a receiver visits and their boundary edges rather than of every triangle:
 * a torus of 40,000 triangles took 20 s for FSF's 128x128 irradiance one triangle at a time. */
#ifndef WEDGE_RECON_EMITTER_FACING_H
#define WEDGE_RECON_EMITTER_FACING_H

#include <stdbool.h>

typedef struct EmitterFacing EmitterFacing;
typedef struct EmitterFacingAt EmitterFacingAt;

/* The count triangles tri[t][k] (world, each wound so that its normal is its emitting side's),
 * vertices the same when their coordinates are equal bit for bit; two_sided: both sides emit.
 * NULL when count < 1 or out of memory. */
EmitterFacing *emitter_facing_create(int count, const double (*tri)[3][3], bool two_sided);
void emitter_facing_destroy(EmitterFacing *f);

/* One thread's per-receiver values (vertex directions, edge angles). NULL when out of memory. */
EmitterFacingAt *emitter_facing_at_create(const EmitterFacing *f);
void emitter_facing_at_destroy(EmitterFacingAt *at);

/* The sum over the triangles of the projected solid angle (steradians) of the part above the
 * horizon of a receiver at p with unit normal n; a one-sided emitter's triangles count only
 * from their front. A triangle that is not shown to lie wholly above the horizon and clearly
 * (beyond rounding) on one side of its plane is summed alone: by alone(ctx, t) when given (t: its
 * index in the tri array create was given), else as emitter_facing_phi_by_triangle sums it. The
 * caller's own per-triangle rule then decides the cases rounding decides (a receiver on the
 * emitter's surface, in a triangle's plane). */
double emitter_facing_phi(const EmitterFacing *f, EmitterFacingAt *at, const double p[3], const double n[3],
                          double (*alone)(void *ctx, int t), void *ctx);

/* The same, one triangle at a time (the reference, and tests). */
double emitter_facing_phi_by_triangle(const EmitterFacing *f, const double p[3], const double n[3]);

#endif
