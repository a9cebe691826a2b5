/* Points in Morton (Z-curve) order within their bounding box, so that neighbours in the order
 * are neighbours in space: the leaves of the trees over a mesh light's vertices
 * (maaf_vertex_extent.c) and triangles (emitter_facing.c) are then compact. */
#ifndef WEDGE_RECON_MORTON_ORDER_H
#define WEDGE_RECON_MORTON_ORDER_H

/* The permutation of the n points pt[i] into Morton order (10 bits an axis over their finite
 * bounding box; a point with a non-finite coordinate counts as the box's low corner there; ties
 * keep the index order), malloc'd; NULL when n < 1 or out of memory. */
int *morton_order(int n, const double (*pt)[3]);

#endif
