/* Tessellated shapes -> object-space triangle meshes (mesh.h).
 *
 * The parser already validates shape parameters, but this module is the last line before
 * Embree and is also called on hand-built ShapeDescs, so every count and index is checked
 * again here: a bad mesh is an error message, never an out-of-bounds read. */
#include "geometry/mesh.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geometry/ply.h"
#include "geometry/subdiv.h"

void mesh_free(TriMesh *mesh)
{
    if (!mesh) return;
    free(mesh->p);
    free(mesh->n);
    free(mesh->uv);
    free(mesh->index);
    memset(mesh, 0, sizeof *mesh);
}

/* Location of a parameter if present, else of the shape. */
static SrcLoc param_loc(const ShapeDesc *s, const char *name)
{
    const Param *p = params_find(&s->params, name);
    return p ? p->loc : s->loc;
}

static bool all_finite(const float *v, int count)
{
    for (int i = 0; i < count; i++)
        if (!isfinite(v[i])) return false;
    return true;
}

/* ---- vertex data shared by trianglemesh, bilinearmesh and loopsubdiv ---- */

typedef struct {
    const float *p;     /* 3 * vertex_count */
    const float *n;     /* 3 * vertex_count or NULL */
    const float *uv;    /* 2 * vertex_count or NULL */
    int vertex_count;
    const int32_t *index;
    int index_count;
    int32_t default_index[4]; /* used when "indices" may be omitted */
} MeshParams;

/* Reads P, indices, N and uv. corner_count is 3 (triangles) or 4 (bilinear patches):
 * "indices" may be omitted when P has exactly that many points (pbrt-v4), and its length
 * must be a multiple of it. corner_count 0 means: indices required, any length. */
static bool get_mesh_params(const ShapeDesc *s, int corner_count, bool allow_n_uv, MeshParams *m,
                            Diag *err)
{
    memset(m, 0, sizeof *m);
    const ParamSet *ps = &s->params;
    int np = 0, ni = 0;
    m->p = params_floats(ps, "P", &np);
    if (!m->p || np == 0) {
        diag_set(err, WEDGE_EXIT_INPUT, s->loc, "%s: \"point3 P\" is required", s->type);
        return false;
    }
    if (np / 3 > INT_MAX / 4) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "P"), "%s: too many points in \"P\"", s->type);
        return false;
    }
    if (np % 3 != 0) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "P"),
                 "%s: \"P\" has %d values, not a multiple of 3", s->type, np);
        return false;
    }
    if (!all_finite(m->p, np)) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "P"), "%s: \"P\" has a non-finite value", s->type);
        return false;
    }
    m->vertex_count = np / 3;
    m->index = params_ints(ps, "indices", &ni);
    m->index_count = ni;
    if (!m->index || ni == 0) {
        if (corner_count > 0 && m->vertex_count == corner_count) {
            for (int i = 0; i < corner_count; i++) m->default_index[i] = i;
            m->index = m->default_index;
            m->index_count = corner_count;
        } else {
            if (corner_count > 0)
                diag_set(err, WEDGE_EXIT_INPUT, s->loc,
                         "%s: \"integer indices\" is required unless \"P\" has exactly %d points",
                         s->type, corner_count);
            else
                diag_set(err, WEDGE_EXIT_INPUT, s->loc, "%s: \"integer indices\" is required", s->type);
            return false;
        }
    }
    if (corner_count > 0 && m->index_count % corner_count != 0) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "indices"),
                 "%s: \"indices\" has %d values, not a multiple of %d", s->type, m->index_count,
                 corner_count);
        return false;
    }
    for (int i = 0; i < m->index_count; i++)
        if (m->index[i] < 0 || m->index[i] >= m->vertex_count) {
            diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "indices"),
                     "%s: index %d (entry %d of \"indices\") is out of range for %d vertices",
                     s->type, (int)m->index[i], i, m->vertex_count);
            return false;
        }
    if (!allow_n_uv) return true;
    int nn = 0, nuv = 0;
    m->n = params_floats(ps, "N", &nn);
    if (m->n && nn != np) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "N"),
                 "%s: \"N\" has %d values but \"P\" has %d", s->type, nn, np);
        return false;
    }
    if (m->n && !all_finite(m->n, nn)) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "N"), "%s: \"N\" has a non-finite value", s->type);
        return false;
    }
    m->uv = params_floats(ps, "uv", &nuv);
    if (m->uv && nuv != 2 * m->vertex_count) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "uv"),
                 "%s: \"uv\" has %d values but %d vertices need %d", s->type, nuv,
                 m->vertex_count, 2 * m->vertex_count);
        return false;
    }
    if (m->uv && !all_finite(m->uv, nuv)) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "uv"), "%s: \"uv\" has a non-finite value", s->type);
        return false;
    }
    return true;
}

static bool oom(const ShapeDesc *s, TriMesh *mesh, Diag *err)
{
    mesh_free(mesh);
    diag_set(err, WEDGE_EXIT_RUNTIME, s->loc, "%s: out of memory", s->type);
    return false;
}

/* Copies vertex attributes and allocates the index array. */
static bool alloc_mesh(const ShapeDesc *s, const MeshParams *m, int triangle_count, TriMesh *mesh,
                       Diag *err)
{
    size_t nv = (size_t)m->vertex_count;
    mesh->vertex_count = m->vertex_count;
    mesh->triangle_count = triangle_count;
    mesh->p = malloc(nv * sizeof *mesh->p);
    mesh->index = malloc(3 * (size_t)triangle_count * sizeof *mesh->index);
    if (m->n) mesh->n = malloc(nv * sizeof *mesh->n);
    if (m->uv) mesh->uv = malloc(nv * sizeof *mesh->uv);
    if (!mesh->p || !mesh->index || (m->n && !mesh->n) || (m->uv && !mesh->uv)) return oom(s, mesh, err);
    for (size_t i = 0; i < nv; i++) {
        mesh->p[i] = v3(m->p[3 * i], m->p[3 * i + 1], m->p[3 * i + 2]);
        if (m->n) mesh->n[i] = v3(m->n[3 * i], m->n[3 * i + 1], m->n[3 * i + 2]);
        if (m->uv) mesh->uv[i] = v2(m->uv[2 * i], m->uv[2 * i + 1]);
    }
    return true;
}

static bool triangle_mesh(const ShapeDesc *s, TriMesh *mesh, Diag *err)
{
    MeshParams m;
    if (!get_mesh_params(s, 3, true, &m, err)) return false;
    if (!alloc_mesh(s, &m, m.index_count / 3, mesh, err)) return false;
    for (int i = 0; i < m.index_count; i++) mesh->index[i] = (uint32_t)m.index[i];
    return true;
}

/* A bilinear patch has corners p00 p10 p01 p11 (pbrt-v4 order). It becomes the two
 * triangles (p00 p10 p11) and (p00 p11 p01), split along the p00-p11 diagonal; both keep
 * the patch's orientation (their normals point along dp/du x dp/dv). */
static bool bilinear_mesh(const ShapeDesc *s, TriMesh *mesh, Diag *err)
{
    MeshParams m;
    if (!get_mesh_params(s, 4, true, &m, err)) return false;
    int patches = m.index_count / 4;
    if (!alloc_mesh(s, &m, 2 * patches, mesh, err)) return false;
    for (int q = 0; q < patches; q++) {
        const int32_t *c = m.index + 4 * q;
        uint32_t *t = mesh->index + 6 * q;
        t[0] = (uint32_t)c[0], t[1] = (uint32_t)c[1], t[2] = (uint32_t)c[3];
        t[3] = (uint32_t)c[0], t[4] = (uint32_t)c[3], t[5] = (uint32_t)c[2];
    }
    return true;
}

/* ---- plymesh ---- */

static bool ply_path(const ShapeDesc *s, char *path, size_t size, Diag *err)
{
    const char *name = params_string(&s->params, "filename", NULL);
    if (!name || !*name) {
        diag_set(err, WEDGE_EXIT_INPUT, s->loc, "plymesh: \"string filename\" is required");
        return false;
    }
    int n;
    if (name[0] == '/' || !s->base_dir || !*s->base_dir) n = snprintf(path, size, "%s", name);
    else n = snprintf(path, size, "%s/%s", s->base_dir, name);
    if (n < 0 || (size_t)n >= size) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "filename"), "plymesh: file name too long");
        return false;
    }
    return true;
}

static void note_shape(const ShapeDesc *s, Diag *err)
{
    if (s->loc.path && s->loc.line > 0)
        diag_append(err, "%s:%d:%d: note: PLY file of this shape", s->loc.path, s->loc.line, s->loc.col);
}

static bool ply_mesh(const ShapeDesc *s, TriMesh *mesh, MeshWarnFn warn, void *warn_ctx, Diag *err)
{
    char path[4096];
    if (!ply_path(s, path, sizeof path, err)) return false;
    if (params_find(&s->params, "displacement") && warn)
        warn(warn_ctx, param_loc(s, "displacement"),
             "plymesh: \"displacement\" is ignored (wedge does not displace meshes)");
    params_float(&s->params, "displacement.edgelength", 1.0f); /* ignored with displacement */
    if (!ply_read(path, mesh, warn, warn_ctx, err)) {
        note_shape(s, err);
        return false;
    }
    return true;
}

/* ---- loopsubdiv (and its wedge-specific Catmull-Clark scheme) ---- */

typedef struct {
    MeshParams m;
    SubdivScheme scheme;
    int levels;
    int face_count;
    const int32_t *face_size; /* "integer nverts", or NULL: triangles */
} SubdivParams;

static bool get_subdiv_params(const ShapeDesc *s, SubdivParams *sp, Diag *err)
{
    memset(sp, 0, sizeof *sp);
    const ParamSet *ps = &s->params;
    const char *scheme = params_string(ps, "scheme", "loop");
    if (strcmp(scheme, "loop") == 0) sp->scheme = SUBDIV_LOOP;
    else if (strcmp(scheme, "catmullclark") == 0) sp->scheme = SUBDIV_CATMULL_CLARK;
    else {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "scheme"),
                 "loopsubdiv: unknown scheme \"%s\" (expected \"loop\" or \"catmullclark\")", scheme);
        return false;
    }
    sp->levels = params_int(ps, "levels", 3); /* pbrt-v4 default */
    if (sp->levels < 0 || sp->levels > SUBDIV_MAX_LEVELS) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "levels"),
                 "loopsubdiv: \"levels\" %d is outside 0..%d", sp->levels, SUBDIV_MAX_LEVELS);
        return false;
    }
    int nf = 0;
    sp->face_size = params_ints(ps, "nverts", &nf);
    /* indices: triangles unless "nverts" gives the polygon sizes */
    if (!get_mesh_params(s, sp->face_size ? 0 : 3, false, &sp->m, err)) return false;
    if (!sp->face_size) {
        sp->face_count = sp->m.index_count / 3;
    } else {
        long sum = 0;
        for (int f = 0; f < nf; f++) {
            if (sp->face_size[f] < 3 || (sp->scheme == SUBDIV_LOOP && sp->face_size[f] != 3)) {
                diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "nverts"),
                         "loopsubdiv: face %d has %d vertices (%s)", f, (int)sp->face_size[f],
                         sp->scheme == SUBDIV_LOOP ? "the loop scheme needs triangles"
                                                   : "a face needs at least 3");
                return false;
            }
            sum += sp->face_size[f];
        }
        if (sum != sp->m.index_count) {
            diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "nverts"),
                     "loopsubdiv: \"nverts\" adds up to %ld but \"indices\" has %d values", sum,
                     sp->m.index_count);
            return false;
        }
        sp->face_count = nf;
    }
    return true;
}

static long subdiv_count(const ShapeDesc *s, const SubdivParams *sp, Diag *err)
{
    long count = subdiv_triangle_count(sp->scheme, sp->levels, sp->face_count, sp->face_size);
    if (count < 0 || count > MESH_MAX_TRIANGLES) {
        diag_set(err, WEDGE_EXIT_INPUT, param_loc(s, "levels"),
                 "loopsubdiv: %d levels would make more than %ld triangles", sp->levels,
                 MESH_MAX_TRIANGLES);
        return -1;
    }
    return count;
}

static bool subdiv_mesh(const ShapeDesc *s, TriMesh *mesh, Diag *err)
{
    SubdivParams sp;
    if (!get_subdiv_params(s, &sp, err) || subdiv_count(s, &sp, err) < 0) return false;
    SubdivInput in = {sp.scheme, sp.levels, sp.m.vertex_count, sp.m.p, sp.face_count,
                      sp.face_size, sp.m.index};
    SubdivOutput out;
    char msg[512];
    if (!subdiv_refine(&in, &out, msg, sizeof msg)) {
        diag_set(err, WEDGE_EXIT_INPUT, s->loc, "loopsubdiv: %s", msg);
        return false;
    }
    size_t nv = (size_t)out.vertex_count;
    mesh->vertex_count = out.vertex_count;
    mesh->triangle_count = out.triangle_count;
    mesh->p = malloc(nv * sizeof *mesh->p);
    mesh->n = malloc(nv * sizeof *mesh->n);
    if (!mesh->p || !mesh->n) {
        subdiv_output_free(&out);
        return oom(s, mesh, err);
    }
    for (size_t i = 0; i < nv; i++) {
        mesh->p[i] = v3(out.p[3 * i], out.p[3 * i + 1], out.p[3 * i + 2]);
        mesh->n[i] = v3(out.n[3 * i], out.n[3 * i + 1], out.n[3 * i + 2]);
    }
    mesh->index = out.index; /* same layout: take ownership */
    out.index = NULL;
    subdiv_output_free(&out);
    return true;
}

/* ---- entry points ---- */

bool mesh_from_shape_warn(const ShapeDesc *shape, TriMesh *mesh, MeshWarnFn warn, void *warn_ctx,
                          Diag *err)
{
    memset(mesh, 0, sizeof *mesh);
    const char *type = shape->type ? shape->type : "";
    if (strcmp(type, "trianglemesh") == 0) return triangle_mesh(shape, mesh, err);
    if (strcmp(type, "bilinearmesh") == 0) return bilinear_mesh(shape, mesh, err);
    if (strcmp(type, "plymesh") == 0) return ply_mesh(shape, mesh, warn, warn_ctx, err);
    if (strcmp(type, "loopsubdiv") == 0) return subdiv_mesh(shape, mesh, err);
    diag_set(err, WEDGE_EXIT_INPUT, shape->loc, "shape \"%s\" is not a triangle mesh", type);
    return false;
}

bool mesh_from_shape(const ShapeDesc *shape, TriMesh *mesh, Diag *err)
{
    return mesh_from_shape_warn(shape, mesh, NULL, NULL, err);
}

long mesh_triangle_count(const ShapeDesc *shape, Diag *err)
{
    const char *type = shape->type ? shape->type : "";
    MeshParams m;
    if (strcmp(type, "trianglemesh") == 0)
        return get_mesh_params(shape, 3, false, &m, err) ? m.index_count / 3 : -1;
    if (strcmp(type, "bilinearmesh") == 0)
        return get_mesh_params(shape, 4, false, &m, err) ? 2 * (m.index_count / 4) : -1;
    if (strcmp(type, "plymesh") == 0) {
        char path[4096];
        if (!ply_path(shape, path, sizeof path, err)) return -1;
        long count = ply_count_triangles(path, err);
        if (count < 0) note_shape(shape, err);
        return count;
    }
    if (strcmp(type, "loopsubdiv") == 0) {
        SubdivParams sp;
        return get_subdiv_params(shape, &sp, err) ? subdiv_count(shape, &sp, err) : -1;
    }
    if (strcmp(type, "sphere") == 0 || strcmp(type, "disk") == 0) return 0;
    diag_set(err, WEDGE_EXIT_INPUT, shape->loc, "unknown shape type \"%s\"", type);
    return -1;
}
