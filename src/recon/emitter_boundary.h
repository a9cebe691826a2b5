/* A planar mesh emitter's projected solid angle through its boundary alone.
 *
 * Lambert's formula (polygon_irradiance.h) sums, over a polygon's edges, a term that changes
 * sign with the edge's direction. A mesh whose triangles lie in one plane and are wound the same
 * way crosses each interior edge once in each direction, so the interior terms cancel and the
 * triangles' signed sums add up to the sum over the boundary edges alone. When the receiver sees
 * the whole plane from one side (every triangle's sum has the same sign) and no triangle reaches
 * below its horizon (no clipping), the sum of the triangles' projected solid angles is therefore
 * half the absolute boundary sum: a 40 x 40 quad grid's 160 boundary edges instead of its 4,800
 * edges. Where the receiver's horizon cuts the plane, the boundary's loops are clipped to it as a
 * single polygon is: the clipped pieces of the triangles tile the clipped surface, whose
 * boundary is the clipped loops. */
#ifndef WEDGE_RECON_EMITTER_BOUNDARY_H
#define WEDGE_RECON_EMITTER_BOUNDARY_H

#include <stdbool.h>

typedef struct EmitterBoundary EmitterBoundary;

/* The boundary of triangles tri[0..count) (world, each in its winding), vertices the same when
 * their coordinates are equal bit for bit. NULL when the triangles are not one planar surface
 * wound one way (every edge used once, or twice in opposite directions; no degenerate
 * triangle), when the boundary has no fewer edges than the interior (the triangles' own sum is
 * then as cheap), or out of memory. */
EmitterBoundary *emitter_boundary_create(int count, const double (*tri)[3][3]);
void emitter_boundary_destroy(EmitterBoundary *b);

/* Its boundary edges (for reports and tests). */
int emitter_boundary_edge_count(const EmitterBoundary *b);

/* The projected solid angle (steradians) of the part of the surface above the horizon of a
 * receiver at p with unit normal n, into *phi; false, *phi untouched, when a boundary point (or
 * a crossing of the horizon) is at p itself (sum the triangles instead). */
bool emitter_boundary_phi(const EmitterBoundary *b, const double p[3], const double n[3], double *phi);

#endif
