/* Lambert's formula (polygon_irradiance.h) over triangles that share vertices and edges, as
 * the triangles of an emitter mesh do (a quad light: two triangles, four vertices, five
 * edges), each receiver's vertex directions and edge angles found once rather than once per
 * triangle: for a quad 4 vertex normalisations instead of 6 and 5 atan2 instead of 6, the
 * atan2s being most of the cost.
 *
 * Bit for bit polygon_projected_solid_angle(p, n, triangle, 3): a triangle wholly above the
 * receiver's horizon takes that function's path with the shared values (equal vertices give
 * equal directions; an edge's angle atan2(|a x b|, a . b) is the same float both ways round,
 * the products and sums being the same under C11's -ffp-contract=off); a triangle that the
 * horizon clips is handed to polygon_projected_solid_angle itself. */
#ifndef WEDGE_RECON_SHARED_TRIANGLES_H
#define WEDGE_RECON_SHARED_TRIANGLES_H

#include <stdbool.h>

typedef struct SharedTriangles SharedTriangles;

/* count triangles, tri[t][k] the vertex k of triangle t (polygon order). Vertices are the same
 * when their coordinates are equal bit for bit. NULL when out of memory. */
SharedTriangles *shared_triangles_create(int count, const double (*tri)[3][3]);
void shared_triangles_destroy(SharedTriangles *s);

/* One receiver's values (one per thread): vertex directions and edge angles, valid for the
 * receiver last given to shared_triangles_receiver. NULL when out of memory. */
typedef struct SharedTrianglesAt SharedTrianglesAt;
SharedTrianglesAt *shared_triangles_at_create(const SharedTriangles *s);
void shared_triangles_at_destroy(SharedTrianglesAt *at);

/* A new receiver at p with unit normal n (the earlier one's values are dropped). */
void shared_triangles_receiver(SharedTrianglesAt *at, const double p[3], const double n[3]);

/* polygon_projected_solid_angle(p, n, tri[t], 3) for the current receiver. */
double shared_triangles_phi(const SharedTriangles *s, SharedTrianglesAt *at, int t);

/* The pieces of that sum, for a caller that sums a mesh's edges its own way (emitter_facing.h).
 * Triangle t's vertices and undirected edges (edge k runs from corner k to corner k + 1), as
 * numbered here: equal vertices, and the same two vertices either way round, share a number. */
int shared_triangles_vertex_count(const SharedTriangles *s);
int shared_triangles_edge_count(const SharedTriangles *s);
void shared_triangles_corners(const SharedTriangles *s, int t, int vert[3], int edge[3]);
/* Vertex v's height n . (v - p) over the current receiver's horizon. */
double shared_triangles_height(const SharedTriangles *s, SharedTrianglesAt *at, int v);
/* Lambert's term of triangle t's edge from corner k to k + 1, theta (n . (a x b)) / |a x b| for
 * the unit directions a, b to its ends (neither at the receiver itself), 0 when they coincide:
 * the term shared_triangles_phi sums, each edge's angle found once a receiver. */
double shared_triangles_edge_term(const SharedTriangles *s, SharedTrianglesAt *at, int t, int k);

#endif
