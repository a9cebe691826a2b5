/* Materials and the textures they read. For now only pbrt-v4 "diffuse" (Lambert) is
 * modelled; every other material type renders as diffuse grey 0.5 with one warning per
 * type. The BSDF interface (eval / sample / pdf in a local frame) is what a glossy model
 * will plug into. */
#ifndef WEDGE_RENDER_MATERIAL_H
#define WEDGE_RENDER_MATERIAL_H

#include <stdbool.h>

#include "core/diag.h"
#include "core/vec.h"
#include "scene/scene_desc.h"

typedef enum { TEX_CONSTANT, TEX_CHECKERBOARD_2D, TEX_CHECKERBOARD_3D } TextureKind;

typedef struct {
    TextureKind kind;
    vec3 value;                 /* constant */
    vec3 tex1, tex2;            /* checkerboard */
    float uscale, vscale, udelta, vdelta;
    Mat4 texture_from_world;    /* 3D checkerboard */
} Texture;

typedef enum { MATERIAL_DIFFUSE } MaterialKind;

typedef struct {
    MaterialKind kind;
    vec3 reflectance;           /* used when texture < 0 */
    int texture;                /* index into MaterialTable.textures, or -1 */
} Material;

typedef struct {
    Material *materials;        /* one per SceneDesc material */
    int material_count;
    Material default_material;  /* pbrt-v4's default: diffuse 0.5 */
    Texture *textures;
    int texture_count;
} MaterialTable;

/* Converts the scene's materials and textures; unsupported ones become grey with a
 * warning added to the scene (one per material type / texture class). */
bool materials_build(SceneDesc *scene, MaterialTable *table, Diag *err);
void materials_free(MaterialTable *table);

/* Diffuse reflectance of material index m (-1 = default) at uv / p_world, clamped to [0,1]. */
vec3 material_albedo(const MaterialTable *table, int m, vec2 uv, vec3 p_world);

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
