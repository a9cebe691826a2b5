/* Triangle corners welded into vertices: corners with coordinates equal bit for bit are one vertex
 * (a -0 copy of 0 is kept apart), as an emitter mesh's triangles share them. Shared by Lambert's
 * formula over a mesh's triangles (shared_triangles.h) and over its boundary (emitter_boundary.h). */
#ifndef WEDGE_RECON_VERTEX_WELD_H
#define WEDGE_RECON_VERTEX_WELD_H

/* For the count triangles tri[t][k]: vert[3 t + k] the vertex of corner k of triangle t, pos[v] the
 * vertex's coordinates (both arrays of 3 count entries), numbered in the order of the sorted
 * coordinates. Returns the vertex count, or -1 out of memory. */
int vertex_weld(int count, const double (*tri)[3][3], double (*pos)[3], int *vert);

#endif
