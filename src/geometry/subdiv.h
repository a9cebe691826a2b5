/* Subdivision surfaces through OpenSubdiv 3.5 Far (the C++ lives in subdiv_shim.cpp).
 *
 * Uniform refinement by `levels`, then every vertex of the last level is pushed to the
 * limit surface, with the limit normal from the cross product of the two limit tangents
 * (Far::PrimvarRefiner::Limit). Boundaries are infinitely sharp creases
 * (VTX_BOUNDARY_EDGE_ONLY), which is pbrt-v4's boundary rule; see docs/geometry.md for
 * the remaining differences from pbrt-v4's own Loop code.
 *
 * Orientation follows pbrt-v4's loopsubdiv: its limit normals point to the side opposite
 * the counter-clockwise normal of the input faces. The output triangles are wound so that
 * their counter-clockwise normal agrees with those shading normals (i.e. each input face's
 * winding is reversed), so geometric and shading normals never disagree. */
#ifndef WEDGE_GEOMETRY_SUBDIV_H
#define WEDGE_GEOMETRY_SUBDIV_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    SUBDIV_LOOP,          /* triangles only */
    SUBDIV_CATMULL_CLARK, /* any polygons; quads after one level */
} SubdivScheme;

enum { SUBDIV_MAX_LEVELS = 15 }; /* OpenSubdiv stores the uniform level in 4 bits */

typedef struct {
    SubdivScheme scheme;
    int levels;              /* >= 0; 0 still projects the cage vertices to the limit */
    int vertex_count;
    const float *p;          /* 3 * vertex_count */
    int face_count;
    const int *face_size;    /* vertices per face, or NULL: all triangles */
    const int *index;        /* sum of face sizes, each in [0, vertex_count) */
} SubdivInput;

typedef struct {
    int vertex_count, triangle_count;
    float *p;                /* 3 * vertex_count limit positions */
    float *n;                /* 3 * vertex_count unit limit normals */
    uint32_t *index;         /* 3 * triangle_count */
} SubdivOutput;

/* Triangles the refinement will produce (without refining), or -1 when it overflows. */
long subdiv_triangle_count(SubdivScheme scheme, int levels, int face_count, const int *face_size);

/* Refines; on failure returns false and writes a message (no location) into msg.
 * The caller validates the input (indices in range, face sizes, levels). free() the
 * output arrays (or subdiv_output_free). */
bool subdiv_refine(const SubdivInput *in, SubdivOutput *out, char *msg, size_t msg_size);
void subdiv_output_free(SubdivOutput *out);

#ifdef __cplusplus
}
#endif

#endif
