/* mesh_from_shape / mesh_triangle_count on small hand-built ShapeDescs: every mesh shape
 * type, pbrt-v4's defaults, and exact error messages. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "geometry/mesh.h"
#include "geometry/ply.h"

#define MAX_PARAMS 8

typedef struct {
    ShapeDesc shape;
    Param items[MAX_PARAMS];
} TestShape;

static const SrcLoc SHAPE_LOC = {"scene.pbrt", 2, 1};

static void shape_init(TestShape *t, const char *type)
{
    memset(t, 0, sizeof *t);
    t->shape.type = type;
    t->shape.params.items = t->items;
    t->shape.material = t->shape.area_light = t->shape.object = -1;
    t->shape.loc = SHAPE_LOC;
}

static Param *add(TestShape *t, ParamType type, const char *name, int count)
{
    Param *p = &t->items[t->shape.params.count++];
    p->type = type;
    p->name = name;
    p->count = count;
    p->loc = (SrcLoc){"scene.pbrt", 3 + t->shape.params.count, 5};
    return p;
}
static void add_floats(TestShape *t, ParamType type, const char *name, const float *v, int n)
{
    add(t, type, name, n)->floats = v;
}
static void add_ints(TestShape *t, const char *name, const int32_t *v, int n)
{
    add(t, PARAM_INTEGER, name, n)->ints = v;
}
static void add_string(TestShape *t, const char *name, const char *const *s)
{
    add(t, PARAM_STRING, name, 1)->strings = s;
}

static const char *build_error(TestShape *t)
{
    static Diag err;
    memset(&err, 0, sizeof err);
    TriMesh m;
    if (mesh_from_shape(&t->shape, &m, &err)) {
        mesh_free(&m);
        return "(no error)";
    }
    CHECK(m.p == NULL && m.index == NULL);
    return err.message;
}

static void trianglemesh(void)
{
    const float P3[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float N3[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float UV3[6] = {0, 0, 1, 0, 0, 1};
    TestShape t;
    shape_init(&t, "trianglemesh");
    add_floats(&t, PARAM_POINT3, "P", P3, 9);
    add_floats(&t, PARAM_NORMAL3, "N", N3, 9);
    add_floats(&t, PARAM_POINT2, "uv", UV3, 6);
    Diag err = {0};
    TriMesh m;
    /* pbrt-v4: "indices" may be omitted when P has exactly three points */
    CHECK(mesh_from_shape(&t.shape, &m, &err));
    CHECK(m.vertex_count == 3 && m.triangle_count == 1);
    CHECK(m.index[0] == 0 && m.index[1] == 1 && m.index[2] == 2);
    CHECK(m.n && m.uv && m.n[2].z == 1.0f && m.uv[2].y == 1.0f && m.p[1].x == 1.0f);
    mesh_free(&m);
    CHECK(mesh_triangle_count(&t.shape, &err) == 1);

    const float P4[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    shape_init(&t, "trianglemesh");
    add_floats(&t, PARAM_POINT3, "P", P4, 12);
    CHECK_STR(build_error(&t),
              "scene.pbrt:2:1: error: trianglemesh: \"integer indices\" is required unless \"P\" has exactly 3 points");
    const int32_t bad[6] = {0, 1, 2, 0, 2, 4};
    add_ints(&t, "indices", bad, 6);
    CHECK_STR(build_error(&t),
              "scene.pbrt:5:5: error: trianglemesh: index 4 (entry 5 of \"indices\") is out of range for 4 vertices");
    CHECK(mesh_triangle_count(&t.shape, &err) == -1);
    t.items[1].count = 5;
    CHECK_STR(build_error(&t),
              "scene.pbrt:5:5: error: trianglemesh: \"indices\" has 5 values, not a multiple of 3");
    const int32_t good[6] = {0, 1, 2, 0, 2, 3};
    t.items[1].ints = good;
    t.items[1].count = 6;
    add_floats(&t, PARAM_NORMAL3, "N", N3, 9);
    CHECK_STR(build_error(&t), "scene.pbrt:6:5: error: trianglemesh: \"N\" has 9 values but \"P\" has 12");
}

/* A bilinear patch p00 p10 p01 p11 becomes two triangles that cover the same corners,
 * keep the orientation dp/du x dp/dv, and (planar case) the same area. */
static void bilinearmesh(void)
{
    const float P[12] = {0, 0, 0, 2, 0, 0, 0, 3, 0, 2, 3, 0}; /* p00 p10 p01 p11 */
    TestShape t;
    shape_init(&t, "bilinearmesh");
    add_floats(&t, PARAM_POINT3, "P", P, 12);
    Diag err = {0};
    TriMesh m;
    CHECK(mesh_from_shape(&t.shape, &m, &err));
    CHECK(m.triangle_count == 2 && m.vertex_count == 4);
    float area = 0;
    int corners_used[4] = {0};
    for (int k = 0; k < 2; k++) {
        const uint32_t *c = m.index + 3 * k;
        vec3 n = v3_cross(v3_sub(m.p[c[1]], m.p[c[0]]), v3_sub(m.p[c[2]], m.p[c[0]]));
        CHECK(n.z > 0); /* dp/du x dp/dv = +x cross +y = +z */
        area += 0.5f * v3_length(n);
        for (int j = 0; j < 3; j++) corners_used[c[j]]++;
    }
    CHECK_NEAR(area, 6.0, 1e-6);
    for (int i = 0; i < 4; i++) CHECK(corners_used[i] > 0);
    mesh_free(&m);
    CHECK(mesh_triangle_count(&t.shape, &err) == 2);

    const int32_t two[8] = {0, 1, 2, 3, 1, 3, 0, 2};
    add_ints(&t, "indices", two, 8);
    CHECK(mesh_triangle_count(&t.shape, &err) == 4);
    t.items[1].count = 6;
    CHECK_STR(build_error(&t),
              "scene.pbrt:5:5: error: bilinearmesh: \"indices\" has 6 values, not a multiple of 4");
}

static int warnings;
static char warning[512];
static void on_warn(void *ctx, SrcLoc loc, const char *text)
{
    (void)ctx;
    warnings++;
    snprintf(warning, sizeof warning, "%s:%d:%d: %s", loc.path, loc.line, loc.col, text);
}

static void plymesh(void)
{
    char dir[64] = "/tmp/wedge-mesh-XXXXXX", path[128];
    if (!mkdtemp(dir)) { perror("mkdtemp"); exit(1); }
    snprintf(path, sizeof path, "%s/quad.ply", dir);
    const vec3 P[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const uint8_t sizes[1] = {4};
    const uint32_t idx[4] = {0, 1, 2, 3};
    PlyWriteDesc w = {4, P, NULL, NULL, 1, sizes, idx, false};
    Diag err = {0};
    CHECK(ply_write(path, PLY_BINARY_BE, &w, &err));

    TestShape t;
    shape_init(&t, "plymesh");
    const char *name[1] = {"quad.ply"};
    add_string(&t, "filename", name);
    t.shape.base_dir = dir; /* relative names resolve against the declaring file's folder */
    CHECK(mesh_triangle_count(&t.shape, &err) == 2);
    TriMesh m;
    warnings = 0;
    const float disp = 0.5f;
    add_floats(&t, PARAM_TEXTURE, "displacement", &disp, 0);
    CHECK(mesh_from_shape_warn(&t.shape, &m, on_warn, NULL, &err));
    CHECK(m.triangle_count == 2 && m.vertex_count == 4);
    CHECK(warnings == 1);
    CHECK_STR(warning, "scene.pbrt:5:5: plymesh: \"displacement\" is ignored (wedge does not displace meshes)");
    mesh_free(&m);

    const char *missing[1] = {"nope.ply"};
    t.items[0].strings = missing;
    char expected[512];
    snprintf(expected, sizeof expected,
             "%s/nope.ply: error: cannot read PLY file: No such file or directory\n"
             "scene.pbrt:2:1: note: PLY file of this shape", dir);
    CHECK_STR(build_error(&t), expected);
    CHECK(mesh_triangle_count(&t.shape, &err) == -1);
    CHECK_STR(err.message, expected);

    unlink(path);
    rmdir(dir);
}

static void loopsubdiv(void)
{
    const float P[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    const int32_t I[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    TestShape t;
    shape_init(&t, "loopsubdiv");
    add_floats(&t, PARAM_POINT3, "P", P, 12);
    add_ints(&t, "indices", I, 12);
    Diag err = {0};
    /* pbrt-v4 default: 3 levels -> 4 * 4^3 triangles */
    CHECK(mesh_triangle_count(&t.shape, &err) == 256);
    TriMesh m;
    CHECK(mesh_from_shape(&t.shape, &m, &err));
    CHECK(m.triangle_count == 256 && m.n != NULL && m.uv == NULL);
    mesh_free(&m);

    const int32_t levels = 2;
    add_ints(&t, "levels", &levels, 1);
    CHECK(mesh_from_shape(&t.shape, &m, &err));
    CHECK(m.triangle_count == 64 && m.vertex_count == 4 + 6 * 5);
    mesh_free(&m);

    const int32_t too_many = 16;
    t.items[2].ints = &too_many;
    CHECK_STR(build_error(&t), "scene.pbrt:6:5: error: loopsubdiv: \"levels\" 16 is outside 0..15");
    const int32_t huge = 13; /* 4 * 4^13 = 2^28 > 2^27 */
    t.items[2].ints = &huge;
    CHECK_STR(build_error(&t),
              "scene.pbrt:6:5: error: loopsubdiv: 13 levels would make more than 134217728 triangles");
    CHECK(mesh_triangle_count(&t.shape, &err) == -1);
    t.items[2].ints = &levels;

    const char *scheme[1] = {"butterfly"};
    add_string(&t, "scheme", scheme);
    CHECK_STR(build_error(&t),
              "scene.pbrt:7:5: error: loopsubdiv: unknown scheme \"butterfly\" (expected \"loop\" or \"catmullclark\")");

    /* Catmull-Clark with "nverts": the cube as six quads, level 2 -> 6 * 4 * 4 quads */
    const float C[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
    const int32_t Q[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 2, 3, 7, 6, 1, 2, 6, 5, 0, 4, 7, 3};
    const int32_t S[6] = {4, 4, 4, 4, 4, 4};
    const char *cc[1] = {"catmullclark"};
    shape_init(&t, "loopsubdiv");
    add_floats(&t, PARAM_POINT3, "P", C, 24);
    add_ints(&t, "indices", Q, 24);
    add_ints(&t, "levels", &levels, 1);
    add_ints(&t, "nverts", S, 6);
    add_string(&t, "scheme", cc);
    CHECK(mesh_triangle_count(&t.shape, &err) == 2 * 96);
    CHECK(mesh_from_shape(&t.shape, &m, &err));
    CHECK(m.triangle_count == 2 * 96 && m.vertex_count == 98);
    mesh_free(&m);
    t.items[4].strings = (const char *const[]){"loop"};
    CHECK_STR(build_error(&t),
              "scene.pbrt:7:5: error: loopsubdiv: face 0 has 4 vertices (the loop scheme needs triangles)");
    t.items[4].strings = cc;
    t.items[3].count = 5;
    CHECK_STR(build_error(&t),
              "scene.pbrt:7:5: error: loopsubdiv: \"nverts\" adds up to 20 but \"indices\" has 24 values");
}

static void not_meshes(void)
{
    TestShape t;
    shape_init(&t, "sphere");
    Diag err = {0};
    CHECK(mesh_triangle_count(&t.shape, &err) == 0);
    CHECK_STR(build_error(&t), "scene.pbrt:2:1: error: shape \"sphere\" is not a triangle mesh");
}

int main(void)
{
    trianglemesh();
    bilinearmesh();
    plymesh();
    loopsubdiv();
    not_meshes();
    CHECK_DONE();
}
