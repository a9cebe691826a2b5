/* Shape validation: everything the geometry module may rely on without re-checking
 * (counts match, indices in range, radii sensible, PLY files present). */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "scene/scene_internal.h"

enum { LOOPSUBDIV_LEVELS_MAX = 10 }; /* 4^10 triangles per input triangle: a wedge limit */

#define FAIL(err, loc, ...) (diag_set((err), WEDGE_EXIT_INPUT, (loc), __VA_ARGS__), false)

/* Adds an integer parameter (for pbrt-v4's implicit indices of a single triangle/patch). */
static bool add_int_param(SceneDesc *scene, ShapeDesc *s, const char *name, const int32_t *v, int n, Diag *err)
{
    Param *items = arena_alloc(&scene->arena, (size_t)(s->params.count + 1) * sizeof *items);
    int32_t *vals = arena_alloc(&scene->arena, (size_t)n * sizeof *vals);
    if (!items || !vals) {
        diag_set(err, WEDGE_EXIT_RUNTIME, s->loc, "out of memory");
        return false;
    }
    if (s->params.count) memcpy(items, s->params.items, (size_t)s->params.count * sizeof *items);
    memcpy(vals, v, (size_t)n * sizeof *vals);
    Param *p = &items[s->params.count];
    memset(p, 0, sizeof *p);
    p->type = PARAM_INTEGER;
    p->name = name;
    p->count = n;
    p->ints = vals;
    p->loc = s->loc;
    p->used = true;
    s->params.items = items;
    s->params.count++;
    return true;
}

/* Shared by trianglemesh, bilinearmesh, loopsubdiv: polygons of `corners` vertices. */
static bool check_mesh(SceneDesc *scene, ShapeDesc *s, int corners, Diag *err)
{
    const Param *P = params_find(&s->params, "P");
    if (!P) return FAIL(err, s->loc, "%s: missing \"point3 P\"", s->type);
    int nverts = P->count / 3;
    const Param *I = params_find(&s->params, "indices");
    if (!I) {
        /* pbrt-v4: a mesh of exactly one polygon may omit its indices. */
        if (nverts == corners && strcmp(s->type, "loopsubdiv")) {
            static const int32_t implicit[4] = {0, 1, 2, 3};
            return add_int_param(scene, s, "indices", implicit, corners, err) && check_mesh(scene, s, corners, err);
        }
        return FAIL(err, s->loc, "%s: missing \"integer indices\"", s->type);
    }
    long faces;
    const Param *nv = corners == 0 ? params_find(&s->params, "nverts") : NULL;
    if (nv) {
        /* Polygons of varying size (wedge's Catmull-Clark loopsubdiv): nverts gives each face's size. */
        long total = 0;
        for (int i = 0; i < nv->count; ++i) {
            if (nv->ints[i] < 3)
                return FAIL(err, nv->loc, "%s: face %d has %d vertices in \"integer nverts\"; a face needs at least 3",
                            s->type, i, (int)nv->ints[i]);
            total += nv->ints[i];
        }
        if (total != I->count)
            return FAIL(err, nv->loc, "%s: \"integer nverts\" adds up to %ld but \"integer indices\" has %d values",
                        s->type, total, I->count);
        faces = nv->count;
    } else {
        if (corners == 0) corners = 3;
        if (I->count % corners != 0)
            return FAIL(err, I->loc, "%s: \"integer indices\" needs a multiple of %d values, got %d", s->type,
                        corners, I->count);
        faces = I->count / corners;
    }
    for (int i = 0; i < I->count; ++i)
        if (I->ints[i] < 0 || I->ints[i] >= nverts)
            return FAIL(err, I->loc, "%s: index %d (value %d of \"integer indices\") is out of range [0, %d)",
                        s->type, (int)I->ints[i], i + 1, nverts);
    const char *per_vertex[][2] = {{"N", "normal N"}, {"S", "vector3 S"}, {"uv", "point2 uv"}};
    for (int k = 0; k < 3; ++k) {
        const Param *q = params_find(&s->params, per_vertex[k][0]);
        if (!q) continue;
        int tuple = k == 2 ? 2 : 3;
        if (q->count / tuple != nverts)
            return FAIL(err, q->loc, "%s: \"%s\" has %d entries but \"point3 P\" has %d vertices", s->type,
                        per_vertex[k][1], q->count / tuple, nverts);
    }
    const Param *f = params_find(&s->params, "faceIndices");
    if (f && f->count != faces)
        return FAIL(err, f->loc, "%s: \"integer faceIndices\" has %d values but the mesh has %ld faces", s->type,
                    f->count, faces);
    return true;
}

bool shape_validate(SceneDesc *scene, ShapeDesc *s, Diag *err)
{
    const char *t = s->type;
    if (!strcmp(t, "trianglemesh")) return check_mesh(scene, s, 3, err);
    if (!strcmp(t, "bilinearmesh")) return check_mesh(scene, s, 4, err);
    if (!strcmp(t, "loopsubdiv")) {
        const Param *l = params_find(&s->params, "levels");
        if (l && (l->ints[0] < 0 || l->ints[0] > LOOPSUBDIV_LEVELS_MAX))
            return FAIL(err, l->loc, "loopsubdiv: \"integer levels\" must be in [0, %d], got %d", LOOPSUBDIV_LEVELS_MAX,
                        (int)l->ints[0]);
        return check_mesh(scene, s, 0, err); /* 0: triangles, or the sizes in "nverts" */
    }
    if (!strcmp(t, "sphere")) {
        const Param *r = params_find(&s->params, "radius");
        if (r && !(r->floats[0] >= 0.0f)) {
            char msg[128];
            snprintf(msg, sizeof msg, "sphere: \"float radius\" must not be negative, got %g", (double)r->floats[0]);
            diag_set(err, WEDGE_EXIT_INPUT, r->loc, "%s", msg);
            return false;
        }
        return true;
    }
    if (!strcmp(t, "disk")) {
        const Param *r = params_find(&s->params, "radius"), *ri = params_find(&s->params, "innerradius");
        float radius = r ? r->floats[0] : 1.0f, inner = ri ? ri->floats[0] : 0.0f;
        if (r && radius < 0.0f) {
            diag_set(err, WEDGE_EXIT_INPUT, r->loc, "disk: \"float radius\" must not be negative, got %g",
                     (double)radius);
            return false;
        }
        if (ri && (inner < 0.0f || inner > radius)) {
            diag_set(err, WEDGE_EXIT_INPUT, ri->loc, "disk: \"float innerradius\" %g must be in [0, radius = %g]",
                     (double)inner, (double)radius);
            return false;
        }
        return true;
    }
    if (!strcmp(t, "plymesh")) {
        const Param *f = params_find(&s->params, "filename");
        if (!f) return FAIL(err, s->loc, "plymesh: missing \"string filename\"");
        const char *name = f->strings[0];
        char path[4096];
        if (name[0] == '/' || !s->base_dir || !strcmp(s->base_dir, "."))
            snprintf(path, sizeof path, "%s", name);
        else
            snprintf(path, sizeof path, "%s/%s", s->base_dir, name);
        struct stat st;
        if (stat(path, &st) != 0) {
            diag_set(err, WEDGE_EXIT_INPUT, f->loc, "cannot open PLY file \"%s\": %s", path, strerror(errno));
            return false;
        }
        if (!S_ISREG(st.st_mode)) {
            diag_set(err, WEDGE_EXIT_INPUT, f->loc, "cannot open PLY file \"%s\": not a regular file", path);
            return false;
        }
        return true;
    }
    return true;
}
