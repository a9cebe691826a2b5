/* The extent of a mesh light's vertices along a pair of axes, without visiting every vertex.
 *
 * MAAF measures a mesh light's samples along each triangle's own axes, over the extent of the
 * whole shape (maaf_lights.c); a curved mesh has as many axes as triangles, and projecting every
 * vertex onto each made the light table quadratic in the mesh (40,000 triangles: over a second).
 * Here the vertices are put in Morton order under a binary tree of bounding spheres, and each
 * of the four extremes is found by branch and bound: a node whose sphere cannot reach past the
 * extreme found so far (with a margin for float rounding) is passed over. The result is the minimum and maximum of exactly the float values
 * the plain loop computes, so it is the same bit for bit. */
#ifndef WEDGE_RECON_MAAF_VERTEX_EXTENT_H
#define WEDGE_RECON_MAAF_VERTEX_EXTENT_H

typedef struct MaafVertexExtent MaafVertexExtent;

/* The vertices verts[0..n) (copied, reordered inside). NULL when n < 1 or out of memory. */
MaafVertexExtent *maaf_vertex_extent_create(const float (*verts)[3], int n);
void maaf_vertex_extent_destroy(MaafVertexExtent *x);

/* lo[a], hi[a]: the least and greatest (v - centre) . t_a over the vertices, each product
 * evaluated as maaf_vertex_extent_plain does (NaNs passed over; +-INFINITY when none is a number).
 * x remembers where the extremes were found and starts the next call there (one caller at a
 * time): calls along nearby axes, a mesh's triangles in order, cost far less; the results do not
 * depend on it. */
void maaf_vertex_extent_along(MaafVertexExtent *x, const float centre[3], const float t1[3], const float t2[3],
                              float lo[2], float hi[2]);

/* The same by visiting every vertex (the reference, and the path for few vertices). */
void maaf_vertex_extent_plain(const float (*verts)[3], int n, const float centre[3], const float t1[3],
                              const float t2[3], float lo[2], float hi[2]);

#endif
