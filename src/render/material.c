/* pbrt-v4 materials and textures (see material.h, docs/materials.md). */
#include "render/material.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static vec3 clamp01(vec3 c) { return v3(clamp01f(c.x), clamp01f(c.y), clamp01f(c.z)); }

/* The latest texture called name declared before texture index `before` (pbrt-v4 only
 * lets a texture refer to ones already declared; that also rules out cycles). */
static int find_texture_before(const SceneDesc *scene, const char *name, int before)
{
    for (int i = before - 1; i >= 0; --i)
        if (scene->textures[i].name && !strcmp(scene->textures[i].name, name)) return i;
    return -1;
}

static int find_texture(const SceneDesc *scene, const char *name)
{
    return find_texture_before(scene, name, scene->texture_count);
}

/* A colour-or-float-or-texture argument. An unknown texture name gives def with a warning. */
static TexRef texref_param(SceneDesc *scene, const ParamSet *ps, const char *name, vec3 def, int before, SrcLoc loc)
{
    TexRef r = {-1, def};
    const char *tex = params_texture(ps, name);
    if (tex) {
        r.tex = find_texture_before(scene, tex, before);
        if (r.tex < 0) scene_warn(scene, loc, "unknown texture '%s' for \"%s\"; using its default", tex, name);
        return r;
    }
    float rgb[3];
    if (params_rgb(ps, name, rgb)) {
        r.value = v3(rgb[0], rgb[1], rgb[2]);
        return r;
    }
    const Param *p = params_find(ps, name);
    if (p && p->type == PARAM_FLOAT && p->count >= 1) r.value = v3s(p->floats[0]);
    return r;
}

static bool seen_before(const char **seen, int *count, int cap, const char *type)
{
    for (int i = 0; i < *count; ++i)
        if (!strcmp(seen[i], type)) return true;
    if (*count < cap) seen[(*count)++] = type;
    return false;
}

/* Re-issues an io error at the scene location that asked for the file (the io message
 * already names the file). */
static void relocate_error(Diag *err, SrcLoc loc, const char *path)
{
    char inner[sizeof err->message];
    const char *what = strstr(err->message, "error: ");
    snprintf(inner, sizeof inner, "%s", what ? what + 7 : err->message);
    size_t len = strlen(inner);
    while (len && inner[len - 1] == '\n') inner[--len] = '\0';
    if (strstr(inner, path))
        diag_set(err, WEDGE_EXIT_INPUT, loc, "%s", inner);
    else
        diag_set(err, WEDGE_EXIT_INPUT, loc, "imagemap '%s': %s", path, inner);
}

static bool build_imagemap(SceneDesc *scene, TextureDesc *td, Texture *t, Diag *err)
{
    const ParamSet *ps = &td->params;
    const char *file = params_string(ps, "filename", NULL);
    if (!file || !*file) {
        diag_set(err, WEDGE_EXIT_INPUT, td->loc, "imagemap texture '%s' needs a \"filename\"", td->name ? td->name : "");
        return false;
    }
    char path[4096];
    if (file[0] == '/' || !td->base_dir || !*td->base_dir)
        snprintf(path, sizeof path, "%s", file);
    else
        snprintf(path, sizeof path, "%s/%s", td->base_dir, file);
    t->image = calloc(1, sizeof *t->image);
    if (!t->image) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory loading '%s'", path);
        return false;
    }
    if (!image_texture_load(t->image, path, params_string(ps, "encoding", NULL), err)) {
        if (err->exit_code != WEDGE_EXIT_RUNTIME) relocate_error(err, td->loc, path);
        return false;
    }
    ImageTexture *img = t->image;
    const char *wrap = params_string(ps, "wrap", "repeat");
    if (!tex_wrap_parse(wrap, &img->wrap)) {
        diag_set(err, WEDGE_EXIT_INPUT, td->loc, "unknown imagemap wrap mode '%s' (expected repeat, clamp or black)",
                 wrap);
        return false;
    }
    img->scale = params_float(ps, "scale", 1.0f);
    img->invert = params_bool(ps, "invert", false);
    img->uscale = params_float(ps, "uscale", 1.0f);
    img->vscale = params_float(ps, "vscale", 1.0f);
    img->udelta = params_float(ps, "udelta", 0.0f);
    img->vdelta = params_float(ps, "vdelta", 0.0f);
    const char *filter = params_string(ps, "filter", "bilinear");
    img->nearest = !strcmp(filter, "point");
    (void)params_float(ps, "maxanisotropy", 8.0f); /* MIP-map filtering is not modelled */
    (void)scene;
    return true;
}

static bool build_textures(SceneDesc *scene, MaterialTable *table, Diag *err)
{
    const char *seen_tex[64];
    int n_seen_tex = 0;
    for (int i = 0; i < scene->texture_count; ++i) {
        TextureDesc *td = &scene->textures[i];
        Texture *t = &table->textures[i];
        *t = (Texture){.kind = TEX_CONSTANT, .value = v3s(0.5f)};
        t->is_float = td->value_type && !strcmp(td->value_type, "float");
        const ParamSet *ps = &td->params;
        const char *cls = td->tex_class ? td->tex_class : "";
        t->uscale = params_float(ps, "uscale", 1.0f);
        t->vscale = params_float(ps, "vscale", 1.0f);
        t->udelta = params_float(ps, "udelta", 0.0f);
        t->vdelta = params_float(ps, "vdelta", 0.0f);
        if (!strcmp(cls, "constant")) {
            t->value = texref_param(scene, ps, "value", v3s(1.0f), i, td->loc).value;
        } else if (!strcmp(cls, "checkerboard")) {
            int dim = params_int(ps, "dimension", 2);
            t->kind = dim == 3 ? TEX_CHECKERBOARD_3D : TEX_CHECKERBOARD_2D;
            t->arg[0] = texref_param(scene, ps, "tex1", v3s(1.0f), i, td->loc);
            t->arg[1] = texref_param(scene, ps, "tex2", v3s(0.0f), i, td->loc);
            t->tex1 = t->arg[0].value, t->tex2 = t->arg[1].value;
            if (!mat4_inverse(&td->world_from_texture, &t->texture_from_world)) t->texture_from_world = mat4_identity();
        } else if (!strcmp(cls, "imagemap")) {
            t->kind = TEX_IMAGEMAP;
            if (!build_imagemap(scene, td, t, err)) return false;
        } else if (!strcmp(cls, "scale")) {
            t->kind = TEX_SCALE;
            t->arg[0] = texref_param(scene, ps, "tex", v3s(1.0f), i, td->loc);
            t->arg[1] = texref_param(scene, ps, "scale", v3s(1.0f), i, td->loc);
        } else if (!strcmp(cls, "mix")) {
            t->kind = TEX_MIX;
            t->arg[0] = texref_param(scene, ps, "tex1", v3s(0.0f), i, td->loc);
            t->arg[1] = texref_param(scene, ps, "tex2", v3s(1.0f), i, td->loc);
            t->arg[2] = texref_param(scene, ps, "amount", v3s(0.5f), i, td->loc);
        } else if (!seen_before(seen_tex, &n_seen_tex, 64, cls)) {
            scene_warn(scene, td->loc, "texture class '%s' is not supported yet; it evaluates to grey 0.5", cls);
        }
    }
    return true;
}

/* The material named name, declared before index before (else anywhere), or -1. */
static int find_material(const SceneDesc *scene, const char *name, int before)
{
    for (int i = before - 1; i >= 0; --i)
        if (scene->materials[i].name && !strcmp(scene->materials[i].name, name)) return i;
    for (int i = scene->material_count - 1; i >= before; --i)
        if (scene->materials[i].name && !strcmp(scene->materials[i].name, name)) return i;
    return -1;
}

static int texture_index_or_warn(SceneDesc *scene, const char *name, SrcLoc loc)
{
    if (!name) return -1;
    int t = find_texture(scene, name);
    /* The parser normally rejects unknown textures; keep rendering if not. */
    if (t < 0) scene_warn(scene, loc, "unknown texture '%s'; using the parameter's default", name);
    return t;
}

/* Material.checker and its fields for a diffuse material m whose texture is a 2D
 * checkerboard of two constants: what texture_eval reads of it, and its two values clamped
 * as material_diffuse_albedo clamps them. */
static void set_checker(const MaterialTable *table, Material *m)
{
    if (!material_textured(table, m)) return;
    const Texture *t = &table->textures[m->texture];
    if (t->kind != TEX_CHECKERBOARD_2D || t->arg[0].tex >= 0 || t->arg[1].tex >= 0) return;
    m->checker = true;
    m->checker_map[0] = t->uscale, m->checker_map[1] = t->vscale;
    m->checker_map[2] = t->udelta, m->checker_map[3] = t->vdelta;
    m->checker_albedo[0] = clamp01(t->arg[0].value);
    m->checker_albedo[1] = clamp01(t->arg[1].value);
}

bool materials_build(SceneDesc *scene, MaterialTable *table, Diag *err)
{
    *table = (MaterialTable){0};
    table->default_material = (Material){.kind = MATERIAL_DIFFUSE, .reflectance = v3s(0.5f), .texture = -1};
    table->texture_count = scene->texture_count;
    table->textures = calloc((size_t)(scene->texture_count > 0 ? scene->texture_count : 1), sizeof(Texture));
    table->material_count = scene->material_count;
    table->materials = calloc((size_t)(scene->material_count > 0 ? scene->material_count : 1), sizeof(Material));
    if (!table->textures || !table->materials) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory building materials");
        materials_free(table);
        return false;
    }
    if (!build_textures(scene, table, err)) {
        materials_free(table);
        return false;
    }

    const char *seen_mat[64];
    int n_seen_mat = 0;
    for (int i = 0; i < scene->material_count; ++i) {
        MaterialDesc *md = &scene->materials[i];
        Material *m = &table->materials[i];
        *m = table->default_material;
        m->color_tex = m->urough_tex = m->vrough_tex = -1;
        m->mix[0] = m->mix[1] = -1;
        const char *type = md->type ? md->type : "";
        if (!strcmp(type, "diffuse")) {
            float rgb[3];
            const char *tex = params_texture(&md->params, "reflectance");
            if (tex) {
                m->texture = texture_index_or_warn(scene, tex, md->loc);
                set_checker(table, m);
            } else if (params_rgb(&md->params, "reflectance", rgb)) {
                m->reflectance = clamp01(v3(rgb[0], rgb[1], rgb[2]));
            } else {
                const Param *p = params_find(&md->params, "reflectance");
                if (p && p->type == PARAM_FLOAT && p->count >= 1) m->reflectance = clamp01(v3s(p->floats[0]));
            }
        } else if (glossy_material_type(type)) {
            m->kind = MATERIAL_GLOSSY;
            if (!glossy_params_read(scene, md, &m->glossy, err)) {
                materials_free(table);
                return false;
            }
            m->color_tex = texture_index_or_warn(scene, m->glossy.color_tex, md->loc);
            m->urough_tex = texture_index_or_warn(scene, m->glossy.uroughness_tex, md->loc);
            m->vrough_tex = texture_index_or_warn(scene, m->glossy.vroughness_tex, md->loc);
        } else if (!strcmp(type, "mix")) {
            /* pbrt-v4 MixMaterial: "string materials" [ A B ], "float amount" (texture) 0.5 */
            m->kind = MATERIAL_MIX;
            const Param *names = params_find(&md->params, "materials");
            if (!names || names->type != PARAM_STRING || names->count != 2) {
                diag_set(err, WEDGE_EXIT_INPUT, md->loc, "mix material needs two names in \"string materials\"");
                materials_free(table);
                return false;
            }
            for (int k = 0; k < 2; ++k) {
                const char *nm = names->strings[k];
                m->mix[k] = find_material(scene, nm, i);
                if (m->mix[k] < 0 || m->mix[k] == i) {
                    scene_warn(scene, md->loc, "mix material: unknown material '%s'; using diffuse grey 0.5", nm);
                    m->mix[k] = -1;
                }
            }
            m->mix_amount = texref_param(scene, &md->params, "amount", v3s(0.5f), scene->texture_count, md->loc);
        } else if (strcmp(type, "interface") && !seen_before(seen_mat, &n_seen_mat, 64, type)) {
            /* ("interface" shapes are left out of the scene by the tracer, with a warning) */
            scene_warn(scene, md->loc, "material type '%s' is not supported yet; rendering it as diffuse grey 0.5",
                       type);
        }
    }
    return true;
}

void materials_free(MaterialTable *table)
{
    for (int i = 0; table->textures && i < table->texture_count; ++i) {
        if (table->textures[i].image) {
            image_texture_free(table->textures[i].image);
            free(table->textures[i].image);
        }
    }
    free(table->materials);
    free(table->textures);
    *table = (MaterialTable){0};
}

vec3 texref_eval(const MaterialTable *table, TexRef r, vec2 uv, vec3 p_world, int depth)
{
    if (r.tex < 0) return r.value;
    return texture_eval(table, r.tex, uv, p_world, depth + 1);
}

static vec3 texture_eval_nested(const MaterialTable *table, const Texture *t, vec2 uv, vec3 p_world, int depth);

/* The argument (tex1 or tex2) a 2D checkerboard shows at uv. */
static inline TexRef checkerboard_2d_arg(const Texture *t, vec2 uv)
{
    float s = uv.x * t->uscale + t->udelta, tt = uv.y * t->vscale + t->vdelta;
    long k = material_floor_to_long(s) + material_floor_to_long(tt);
    return t->arg[(k & 1) == 0 ? 0 : 1];
}

/* The common cases (a constant, a 2D checkerboard of two constants) are answered here, in a
 * function small enough to need no stack frame; the others, which evaluate further textures,
 * in texture_eval_nested (the same operations either way). */
vec3 texture_eval(const MaterialTable *table, int i, vec2 uv, vec3 p_world, int depth)
{
    if (i < 0 || i >= table->texture_count || depth > TEXTURE_MAX_DEPTH) return v3s(0.5f);
    const Texture *t = &table->textures[i];
    if (t->kind == TEX_CONSTANT) return t->value;
    if (t->kind == TEX_CHECKERBOARD_2D) {
        TexRef r = checkerboard_2d_arg(t, uv);
        if (r.tex < 0) return r.value; /* texref_eval's constant */
    }
    return texture_eval_nested(table, t, uv, p_world, depth);
}

static __attribute__((noinline)) vec3 texture_eval_nested(const MaterialTable *table, const Texture *t, vec2 uv,
                                                         vec3 p_world, int depth)
{
    switch (t->kind) {
    case TEX_CONSTANT: return t->value;
    case TEX_CHECKERBOARD_2D: return texref_eval(table, checkerboard_2d_arg(t, uv), uv, p_world, depth);
    case TEX_CHECKERBOARD_3D: {
        vec3 p = mat4_apply_point(&t->texture_from_world, p_world);
        long k = material_floor_to_long(p.x) + material_floor_to_long(p.y) + material_floor_to_long(p.z);
        return texref_eval(table, t->arg[(k & 1) == 0 ? 0 : 1], uv, p_world, depth);
    }
    case TEX_IMAGEMAP:
        if (t->is_float) return v3s(image_texture_eval_float(t->image, uv));
        return image_texture_eval(t->image, uv);
    case TEX_SCALE: {
        /* pbrt-v4 ScaleTexture: tex * scale (scale is a float texture) */
        vec3 a = texref_eval(table, t->arg[0], uv, p_world, depth);
        float s = texref_eval(table, t->arg[1], uv, p_world, depth).x;
        return v3_scale(a, s);
    }
    case TEX_MIX: {
        /* pbrt-v4 MixTexture: (1 - amount) tex1 + amount tex2 */
        float a = texref_eval(table, t->arg[2], uv, p_world, depth).x;
        vec3 t1 = texref_eval(table, t->arg[0], uv, p_world, depth);
        vec3 t2 = texref_eval(table, t->arg[1], uv, p_world, depth);
        return v3_add(v3_scale(t1, 1.0f - a), v3_scale(t2, a));
    }
    }
    return v3s(0.5f);
}

/* A hash of the hit point and direction mapped to [0,1): the "random" choice of a mix
 * material that stays the same for every evaluation at one hit (as pbrt-v4's HashFloat of
 * p, wo and the two materials). */
static float hash_float(vec3 p, vec3 w, int a, int b)
{
    float in[6] = {p.x, p.y, p.z, w.x, w.y, w.z};
    uint64_t h = 0x9e3779b97f4a7c15ull ^ ((uint64_t)(uint32_t)a << 32) ^ (uint32_t)b;
    for (int i = 0; i < 6; ++i) {
        uint32_t bits;
        memcpy(&bits, &in[i], sizeof bits);
        h ^= bits;
        /* splitmix64 finaliser */
        h += 0x9e3779b97f4a7c15ull;
        h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
        h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
        h ^= h >> 31;
    }
    return (float)(h >> 40) * (1.0f / 16777216.0f);
}

int material_resolve(const MaterialTable *table, int m, vec2 uv, vec3 p_world, vec3 wo_world)
{
    for (int depth = 0; depth < TEXTURE_MAX_DEPTH; ++depth) {
        const Material *mat = material_get(table, m);
        if (mat->kind != MATERIAL_MIX) return m;
        float amount = texref_eval(table, mat->mix_amount, uv, p_world, 0).x;
        if (amount <= 0.0f)
            m = mat->mix[0];
        else if (amount >= 1.0f)
            m = mat->mix[1];
        else
            m = amount < hash_float(p_world, wo_world, mat->mix[0], mat->mix[1]) ? mat->mix[0] : mat->mix[1];
    }
    return -1; /* nesting too deep (only a cycle of mixes gets here) */
}

GlossyBsdf material_glossy_bsdf(const MaterialTable *table, const Material *m, vec2 uv, vec3 p_world)
{
    const GlossyParams *gp = &m->glossy;
    float ur = m->urough_tex >= 0 ? texture_eval(table, m->urough_tex, uv, p_world, 0).x : gp->uroughness;
    float vr = m->vrough_tex >= 0 ? texture_eval(table, m->vrough_tex, uv, p_world, 0).x : gp->vroughness;
    vec3 color = m->color_tex >= 0 ? clamp01(texture_eval(table, m->color_tex, uv, p_world, 0)) : gp->color;
    return glossy_params_bsdf(gp, ur, vr, color);
}

bool material_reads_uv(const MaterialTable *table, int m)
{
    const Material *mat = material_get(table, m);
    switch (mat->kind) {
    case MATERIAL_DIFFUSE: return material_textured(table, mat);
    case MATERIAL_GLOSSY: return mat->color_tex >= 0 || mat->urough_tex >= 0 || mat->vrough_tex >= 0;
    default: return true; /* a mix's amount or parts may be textured */
    }
}

bool material_table_lambert_only(const MaterialTable *table)
{
    if (table->default_material.kind == MATERIAL_GLOSSY) return false;
    for (int m = 0; m < table->material_count; ++m)
        if (table->materials[m].kind == MATERIAL_GLOSSY) return false;
    return true;
}

vec3 material_albedo(const MaterialTable *table, int m, vec2 uv, vec3 p_world)
{
    const Material *mat = material_get(table, m);
    if (mat->kind == MATERIAL_GLOSSY) {
        if (mat->glossy.kind != GLOSSY_COATED_DIFFUSE) return v3s(0.0f);
        return mat->color_tex >= 0 ? clamp01(texture_eval(table, mat->color_tex, uv, p_world, 0)) : mat->glossy.color;
    }
    if (mat->kind == MATERIAL_MIX) return v3s(0.5f);
    if (material_textured(table, mat)) return material_diffuse_albedo(table, mat, uv, p_world);
    return mat->reflectance;
}

vec3 material_diffuse_albedo(const MaterialTable *table, const Material *mat, vec2 uv, vec3 p_world)
{
    return clamp01(texture_eval(table, mat->texture, uv, p_world, 0));
}
