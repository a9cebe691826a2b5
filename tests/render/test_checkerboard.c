/* The 2D checkerboard texture (render/material.c), whose common case texture_eval answers
 * on its own and whose nested case goes to the general evaluation (issue 22):
 *  - closed form: at the centre of cell (i, j) of a checkerboard scaled by (us, vs) and
 *    shifted by (ud, vd) the value is tex1 when i + j is even and tex2 when odd, for
 *    negative cells too (floor, not truncation);
 *  - a checkerboard whose tex2 is another checkerboard shows that one's value in its odd
 *    cells (the nested path), and a textured diffuse material's albedo is the texture
 *    clamped to [0, 1] (material_diffuse_albedo and material_albedo agree);
 *  - a reference cycle deeper than TEXTURE_MAX_DEPTH ends in the constant 0.5;
 *  - a diffuse material whose reflectance is a 2D checkerboard of two constants is marked
 *    Material.checker by materials_build, and its inline albedo (material_checker_albedo,
 *    which make_vertex takes for it) equals material_diffuse_albedo bit for bit on a dense
 *    grid of uv that crosses cell edges and negative cells, a constant above 1 clamped; a
 *    checkerboard with a textured argument, a 3D one and an untextured material are not
 *    marked. Teeth: the u and v offsets swapped, the parity inverted or the clamp left out
 *    fail the comparison. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "render/material.h"
#include "scene/scene_desc.h"

static Texture checker(float us, float vs, float ud, float vd, TexRef a, TexRef b)
{
    Texture t = {0};
    t.kind = TEX_CHECKERBOARD_2D;
    t.uscale = us, t.vscale = vs, t.udelta = ud, t.vdelta = vd;
    t.arg[0] = a, t.arg[1] = b;
    return t;
}

static TexRef constant(vec3 v) { return (TexRef){-1, v}; }
static TexRef texture(int i) { return (TexRef){i, v3s(0.0f)}; }

static bool same3(vec3 a, vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

static bool same_bits3(vec3 a, vec3 b) { return memcmp(&a, &b, sizeof a) == 0; }

/* The materials of a parsed scene: material_checker_albedo against material_diffuse_albedo. */
static void checker_materials(void)
{
    static const char *SCENE =
        "Camera \"perspective\"\n"
        "WorldBegin\n"
        "Texture \"board\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 7 ] \"float vscale\" [ 3 ]\n"
        "  \"float udelta\" [ 0.3 ] \"float vdelta\" [ -0.45 ] \"rgb tex1\" [ 0.8 0.75 0.1 ] \"rgb tex2\" [ 0.2 1.5 0 ]\n"
        "Texture \"nested\" \"spectrum\" \"checkerboard\" \"texture tex1\" \"board\" \"rgb tex2\" [ 0.1 0.1 0.1 ]\n"
        "Texture \"solid\" \"spectrum\" \"checkerboard\" \"integer dimension\" [ 3 ]\n"
        "MakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"texture reflectance\" \"board\"\n"
        "MakeNamedMaterial \"b\" \"string type\" \"diffuse\" \"texture reflectance\" \"nested\"\n"
        "MakeNamedMaterial \"c\" \"string type\" \"diffuse\" \"texture reflectance\" \"solid\"\n"
        "MakeNamedMaterial \"d\" \"string type\" \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n";
    SceneDesc scene;
    Diag err = {0};
    if (!scene_parse_string(SCENE, strlen(SCENE), "<test>", NULL, &scene, &err)) {
        fprintf(stderr, "parse failed: %s\n", err.message);
        CHECK(false);
        return;
    }
    MaterialTable table;
    CHECK(materials_build(&scene, &table, &err));
    CHECK(table.material_count == 4);
    if (table.material_count == 4) {
        const Material *board = &table.materials[0];
        CHECK(board->checker);
        CHECK(!table.materials[1].checker && !table.materials[2].checker && !table.materials[3].checker);
        int wrong = 0, tex2_cells = 0;
        for (int i = -300; i <= 300; ++i)
            for (int j = -200; j <= 200; ++j) {
                /* steps that land on cell edges (k / 7 - 0.3 / 7 in u) and between them */
                vec2 uv = v2((float)i / 140.0f, (float)j / 60.0f);
                vec3 want = material_diffuse_albedo(&table, board, uv, v3s(0.0f));
                wrong += !same_bits3(material_checker_albedo(board, uv), want);
                tex2_cells += want.y == 1.0f;
            }
        printf("checker materials: %d wrong of 241001, %d in tex2's cells\n", wrong, tex2_cells);
        CHECK(wrong == 0);
        CHECK(tex2_cells > 100000 && tex2_cells < 141001);
    }
    materials_free(&table);
    scene_desc_free(&scene);
}

int main(void)
{
    const vec3 A = v3(0.8f, 0.7f, 0.6f), B = v3(0.1f, 0.2f, 1.5f), C = v3(0.3f, 0.4f, 0.5f);
    Texture tex[3];
    /* 0: a checkerboard of constants, shifted; 1: one of 0 and the constant C (nested) */
    tex[0] = checker(4.0f, 2.0f, 0.25f, -0.5f, constant(A), constant(B));
    tex[1] = checker(2.0f, 2.0f, 0.0f, 0.0f, constant(C), texture(0));
    /* 2: refers to itself, so evaluation has to stop at the depth limit */
    tex[2] = checker(1.0f, 1.0f, 0.0f, 0.0f, texture(2), texture(2));
    Material mat = {0};
    mat.kind = MATERIAL_DIFFUSE;
    mat.texture = 0;
    MaterialTable table = {&mat, 1, {0}, tex, 3};

    int wrong = 0, cells = 0;
    for (int i = -6; i < 6; ++i)
        for (int j = -5; j < 5; ++j) {
            /* the centre of cell (i, j) of texture 0: s = u us + ud = i + 0.5 */
            vec2 uv = v2((i + 0.5f - 0.25f) / 4.0f, (j + 0.5f + 0.5f) / 2.0f);
            vec3 want = ((i + j) % 2 == 0) ? A : B;
            wrong += !same3(texture_eval(&table, 0, uv, v3s(0.0f), 0), want);
            /* the albedo clamps B's 1.5 to 1 */
            vec3 clamped = v3(fminf(want.x, 1.0f), fminf(want.y, 1.0f), fminf(want.z, 1.0f));
            wrong += !same3(material_diffuse_albedo(&table, &mat, uv, v3s(0.0f)), clamped);
            wrong += !same3(material_albedo(&table, 0, uv, v3s(0.0f)), clamped);
            ++cells;
        }
    printf("checkerboard: %d cells, %d wrong values\n", cells, wrong);
    CHECK(wrong == 0);

    /* texture 1: cell (i, j) of its own 2 x 2 scaling shows C when i + j is even, else
     * texture 0 at the same uv */
    int nested_wrong = 0, nested_odd = 0;
    for (int i = -4; i < 4; ++i)
        for (int j = -4; j < 4; ++j) {
            vec2 uv = v2((i + 0.3f) / 2.0f, (j + 0.6f) / 2.0f);
            bool odd = (i + j) % 2 != 0;
            vec3 want = odd ? texture_eval(&table, 0, uv, v3s(0.0f), 0) : C;
            nested_wrong += !same3(texture_eval(&table, 1, uv, v3s(0.0f), 0), want);
            nested_odd += odd;
        }
    printf("nested checkerboard: %d odd cells, %d wrong values\n", nested_odd, nested_wrong);
    CHECK(nested_wrong == 0 && nested_odd > 0);

    CHECK(same3(texture_eval(&table, 2, v2(0.5f, 0.5f), v3s(0.0f), 0), v3s(0.5f)));
    CHECK(same3(texture_eval(&table, 3, v2(0.5f, 0.5f), v3s(0.0f), 0), v3s(0.5f))); /* no such texture */
    checker_materials();
    CHECK_DONE();
}
