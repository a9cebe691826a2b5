/* Triangle meshes in object space: what every tessellated shape becomes before it is
 * handed to Embree (trianglemesh, bilinearmesh, plymesh, loopsubdiv). Spheres and disks
 * are not meshes: the tracer intersects them exactly. */
#ifndef WEDGE_GEOMETRY_MESH_H
#define WEDGE_GEOMETRY_MESH_H

#include <stdbool.h>
#include <stdint.h>

#include "core/diag.h"
#include "core/vec.h"
#include "scene/scene_desc.h"

typedef struct {
    int vertex_count, triangle_count;
    vec3 *p;          /* vertex_count positions */
    vec3 *n;          /* vertex_count shading normals, or NULL */
    vec2 *uv;         /* vertex_count texture coordinates, or NULL */
    uint32_t *index;  /* 3 * triangle_count vertex indices, all < vertex_count */
} TriMesh;

/* Builds the object-space triangle mesh of a tessellated shape (malloc'd arrays).
 * Returns false with err filled (exit 2, location of the shape or data file) on bad data;
 * shapes that are not meshes (sphere, disk) are an error here. */
bool mesh_from_shape(const ShapeDesc *shape, TriMesh *mesh, Diag *err);
/* Number of triangles the shape will have after loading (reads PLY headers, subdivides
 * counts analytically where possible); -1 on error (err filled). Spheres/disks count 0. */
long mesh_triangle_count(const ShapeDesc *shape, Diag *err);
void mesh_free(TriMesh *mesh);

/* ---- additions (geometry engineer) ---- */

/* Receives one warning about a shape's data: loc names the shape or the data file, text
 * has no "warning:" prefix (e.g. pass it on with scene_warn(scene, loc, "%s", text)). */
typedef void (*MeshWarnFn)(void *ctx, SrcLoc loc, const char *text);

/* mesh_from_shape that also reports warnings (skipped PLY polygons, ignored parameters
 * such as plymesh "displacement"); warn may be NULL (warnings dropped). */
bool mesh_from_shape_warn(const ShapeDesc *shape, TriMesh *mesh, MeshWarnFn warn, void *warn_ctx,
                          Diag *err);

/* Largest triangle count a single shape may produce (subdivision levels beyond it are an
 * error rather than an out-of-memory crash). */
#define MESH_MAX_TRIANGLES (1L << 27)

#endif
