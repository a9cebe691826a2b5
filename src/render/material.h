/* Materials and the textures they read (docs/materials.md).
 *
 * Materials: pbrt-v4 "diffuse" (Lambert), the glossy "coateddiffuse", "conductor" and
 * "dielectric" (bsdf_glossy.h, parameters read by glossy_params.h), and "mix" (one of two
 * materials chosen per hit, deterministically, as pbrt-v4's MixMaterial). "interface"
 * shapes are left out by the tracer (media are not modelled). Other types render as
 * diffuse grey 0.5 with one warning per type.
 *
 * Textures: constant, checkerboard (2D and 3D), imagemap (image_texture.h), scale and mix.
 * Texture arguments (checkerboard tex1/tex2, scale tex/scale, mix tex1/tex2/amount) are
 * either constants or references to textures declared earlier; evaluation recurses with a
 * depth guard. Float textures are stored as grey triples (x = the float). */
#ifndef WEDGE_RENDER_MATERIAL_H
#define WEDGE_RENDER_MATERIAL_H

#include <stdbool.h>

#include "core/diag.h"
#include "core/vec.h"
#include "render/bsdf_glossy.h"
#include "render/glossy_params.h"
#include "render/image_texture.h"
#include "scene/scene_desc.h"

typedef enum {
    TEX_CONSTANT,
    TEX_CHECKERBOARD_2D,
    TEX_CHECKERBOARD_3D,
    TEX_IMAGEMAP,
    TEX_SCALE,
    TEX_MIX
} TextureKind;

/* A texture argument: a texture (index into MaterialTable.textures) or a constant. */
typedef struct {
    int tex;                    /* >= 0: texture index; -1: use value */
    vec3 value;
} TexRef;

/* Deepest texture nesting evaluated; deeper references give the constant 0.5 (references
 * only point to earlier textures, so there are no cycles; the guard bounds the stack). */
#define TEXTURE_MAX_DEPTH 16

typedef struct {
    TextureKind kind;
    bool is_float;              /* declared "float": evaluates to (v, v, v) */
    vec3 value;                 /* constant */
    vec3 tex1, tex2;            /* checkerboard constants (arg[0], arg[1] when not textured) */
    float uscale, vscale, udelta, vdelta;
    Mat4 texture_from_world;    /* 3D checkerboard */
    TexRef arg[3];              /* checkerboard: tex1, tex2; scale: tex, scale; mix: tex1, tex2, amount */
    ImageTexture *image;        /* imagemap, owned */
} Texture;

typedef enum { MATERIAL_DIFFUSE, MATERIAL_GLOSSY, MATERIAL_MIX } MaterialKind;

typedef struct {
    MaterialKind kind;
    vec3 reflectance;           /* diffuse: used when texture < 0 */
    int texture;                /* diffuse: index into MaterialTable.textures, or -1 */
    GlossyParams glossy;        /* MATERIAL_GLOSSY */
    int color_tex, urough_tex, vrough_tex; /* glossy: texture indices or -1 */
    int mix[2];                 /* MATERIAL_MIX: material indices (-1: the default material) */
    TexRef mix_amount;          /* MATERIAL_MIX: probability of choosing mix[1] */
    /* diffuse whose reflectance texture is a 2D checkerboard of two constants (checker):
     * the board's uscale, vscale, udelta, vdelta and its two reflectances clamped to [0, 1],
     * for material_checker_albedo */
    bool checker;
    float checker_map[4];
    vec3 checker_albedo[2];
} Material;

typedef struct {
    Material *materials;        /* one per SceneDesc material */
    int material_count;
    Material default_material;  /* pbrt-v4's default: diffuse 0.5 */
    Texture *textures;
    int texture_count;
} MaterialTable;

/* Converts the scene's materials and textures; unsupported ones become grey with a
 * warning added to the scene (one per material type / texture class). A missing or
 * unreadable imagemap file is an error at the texture's location (exit 2). */
bool materials_build(SceneDesc *scene, MaterialTable *table, Diag *err);
void materials_free(MaterialTable *table);

/* Material m of the table; -1 (or any index out of range) is the default material. */
static inline const Material *material_get(const MaterialTable *table, int m)
{
    return (m >= 0 && m < table->material_count) ? &table->materials[m] : &table->default_material;
}

/* Whether a diffuse material's reflectance comes from one of the table's textures (else it
 * is the constant `reflectance`). */
static inline bool material_textured(const MaterialTable *table, const Material *m)
{
    return m->texture >= 0 && m->texture < table->texture_count;
}

/* (long)floorf(x) without floorf's library call (it is one without SSE4.1): truncation
 * rounds towards zero, one step down below zero when it moved x. The same integer for every
 * x the conversion holds (beyond them both are the same out-of-range conversion). */
static inline long material_floor_to_long(float x)
{
    long k = (long)x;
    return (float)k > x ? k - 1 : k;
}

/* The albedo of a checker material (Material.checker) at uv: material_diffuse_albedo's value,
 * inline and without the texture table (the board's cell parity picks one of the two
 * clamped constants, as the checkerboard texture picks tex1 or tex2). */
static inline vec3 material_checker_albedo(const Material *m, vec2 uv)
{
    float s = uv.x * m->checker_map[0] + m->checker_map[2], t = uv.y * m->checker_map[1] + m->checker_map[3];
    long k = material_floor_to_long(s) + material_floor_to_long(t);
    return m->checker_albedo[k & 1];
}

/* Whether shading material m (material_get's index) may read a hit's uv: a texture
 * anywhere in it (a mix always, conservatively). False: the hit's uv can be left 0. */
bool material_reads_uv(const MaterialTable *table, int m);

/* Whether every material of the table, the default one included, is diffuse (a mix's
 * parts are materials of the table): then no hit is shaded by a glossy BSDF. */
bool material_table_lambert_only(const MaterialTable *table);

/* Texture i (or the constant of r) at uv / p_world. */
vec3 texture_eval(const MaterialTable *table, int i, vec2 uv, vec3 p_world, int depth);
vec3 texref_eval(const MaterialTable *table, TexRef r, vec2 uv, vec3 p_world, int depth);

/* Resolves mix materials at a hit: returns the index of the concrete (diffuse or glossy)
 * material hit point p_world seen from direction wo_world uses, or -1 for the default. */
int material_resolve(const MaterialTable *table, int m, vec2 uv, vec3 p_world, vec3 wo_world);

/* Diffuse reflectance of concrete material index m (-1 = default) at uv / p_world, clamped
 * to [0,1]. For a glossy material: its diffuse base (coateddiffuse) or 0. */
vec3 material_albedo(const MaterialTable *table, int m, vec2 uv, vec3 p_world);
/* The same for a diffuse material mat whose reflectance is a texture (material_textured),
 * given by pointer: its texture at uv / p_world clamped to [0,1], without material_albedo's
 * look-up and tests of the material's kind (make_vertex knows both). */
vec3 material_diffuse_albedo(const MaterialTable *table, const Material *mat, vec2 uv, vec3 p_world);

/* The glossy BSDF of material m (kind MATERIAL_GLOSSY) with its textures evaluated. */
GlossyBsdf material_glossy_bsdf(const MaterialTable *table, const Material *m, vec2 uv, vec3 p_world);

/* Lambertian BSDF in the local shading frame (z = shading normal, wo and wi both unit
 * vectors). f = albedo/pi on the same side, 0 otherwise (no transmission). */
static inline vec3 bsdf_diffuse_f(vec3 albedo, float cos_wo, float cos_wi)
{
    if (cos_wo * cos_wi <= 0.0f) return v3s(0.0f);
    return v3_scale(albedo, 0.318309886f);
}
static inline float bsdf_diffuse_pdf(float cos_wo, float cos_wi)
{
    if (cos_wo * cos_wi <= 0.0f) return 0.0f;
    return fabsf(cos_wi) * 0.318309886f;
}

#endif
