/* PLY polygon files (Turk 1994 format): our own bounds-checked reader and a small writer.
 *
 * Reader subset (what pbrt-v4's plymesh reads):
 *   - encodings ascii, binary_little_endian, binary_big_endian (version 1.0);
 *   - element "vertex": x y z (required), nx ny nz (optional, all three), texture
 *     coordinates as u v, s t, texture_u texture_v or texture_s texture_t (optional);
 *   - element "face": a list property "vertex_indices" (or "vertex_index") with any integer
 *     count and index types; triangles are kept, quads v0 v1 v2 v3 are split into
 *     (v0 v1 v2) and (v0 v2 v3) (the diagonal p00-p11 of pbrt-v4's bilinear patch
 *     v0 v1 v3 v2); faces with another vertex count are skipped with one warning, as
 *     pbrt-v4 does;
 *   - every other element and property (scalars and lists of any type) is skipped.
 * Every read is bounds-checked: row counts and list lengths are checked against the bytes
 * left in the file before anything is allocated, indices against the vertex count, and
 * numbers must be finite. Errors read "PATH: error: WHAT" or, where a line is known (the
 * header, ASCII data), "PATH:LINE:COL: error: WHAT". */
#ifndef WEDGE_GEOMETRY_PLY_H
#define WEDGE_GEOMETRY_PLY_H

#include <stdbool.h>
#include <stdint.h>

#include "core/diag.h"
#include "geometry/mesh.h"

typedef enum {
    PLY_ASCII,
    PLY_BINARY_LE,
    PLY_BINARY_BE,
} PlyFormat;

/* What the header says, without reading the data. */
typedef struct {
    PlyFormat format;
    long vertex_count;
    long face_count;     /* rows of the face element (polygons, not triangles) */
    bool has_normals, has_uv;
} PlyInfo;

bool ply_read_info(const char *path, PlyInfo *info, Diag *err);

/* Triangles the file yields after splitting quads and skipping other polygons. Reads the
 * header and the face lengths only (no vertex data is decoded or stored). */
long ply_count_triangles(const char *path, Diag *err);

/* Reads the whole mesh into malloc'd arrays (mesh_free releases them). warn may be NULL. */
bool ply_read(const char *path, TriMesh *mesh, MeshWarnFn warn, void *warn_ctx, Diag *err);

/* A polygon mesh to write: face_size NULL means every face is a triangle. */
typedef struct {
    int vertex_count;
    const vec3 *p;
    const vec3 *n;          /* or NULL */
    const vec2 *uv;         /* or NULL */
    int face_count;
    const uint8_t *face_size; /* vertices per face, or NULL (all 3) */
    const uint32_t *index;  /* sum of face sizes */
    /* Tests: also write properties and an element the reader must skip (a double before
     * x, lists on vertex and face, an "edge" element between vertex and face), and use
     * the alternative names "vertex_index" (uint counts) and "s t". */
    bool extra;
} PlyWriteDesc;

bool ply_write(const char *path, PlyFormat format, const PlyWriteDesc *mesh, Diag *err);

#endif
