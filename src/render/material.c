/* pbrt-v4 materials -> Lambertian approximations; constant and checkerboard textures. */
#include "render/material.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static vec3 clamp01(vec3 c)
{
    return v3(fminf(fmaxf(c.x, 0.0f), 1.0f), fminf(fmaxf(c.y, 0.0f), 1.0f), fminf(fmaxf(c.z, 0.0f), 1.0f));
}

/* A colour-or-float parameter of a texture (tex1, tex2, value). Texture references are not
 * followed (nested textures are not modelled yet): they give def. */
static vec3 texture_param_rgb(const ParamSet *ps, const char *name, vec3 def)
{
    float rgb[3];
    if (params_rgb(ps, name, rgb)) return v3(rgb[0], rgb[1], rgb[2]);
    const Param *p = params_find(ps, name);
    if (p && p->type == PARAM_FLOAT && p->count >= 1) return v3s(p->floats[0]);
    return def;
}

static int find_texture(const SceneDesc *scene, const char *name)
{
    for (int i = scene->texture_count - 1; i >= 0; --i)
        if (scene->textures[i].name && !strcmp(scene->textures[i].name, name)) return i;
    return -1;
}

static bool seen_before(const char **seen, int *count, int cap, const char *type)
{
    for (int i = 0; i < *count; ++i)
        if (!strcmp(seen[i], type)) return true;
    if (*count < cap) seen[(*count)++] = type;
    return false;
}

bool materials_build(SceneDesc *scene, MaterialTable *table, Diag *err)
{
    (void)err;
    *table = (MaterialTable){0};
    table->default_material = (Material){MATERIAL_DIFFUSE, v3s(0.5f), -1};
    table->texture_count = scene->texture_count;
    table->textures = calloc((size_t)(scene->texture_count > 0 ? scene->texture_count : 1), sizeof(Texture));
    table->material_count = scene->material_count;
    table->materials = calloc((size_t)(scene->material_count > 0 ? scene->material_count : 1), sizeof(Material));
    if (!table->textures || !table->materials) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory building materials");
        materials_free(table);
        return false;
    }
    const char *seen_tex[64], *seen_mat[64];
    int n_seen_tex = 0, n_seen_mat = 0;

    for (int i = 0; i < scene->texture_count; ++i) {
        TextureDesc *td = &scene->textures[i];
        Texture *t = &table->textures[i];
        *t = (Texture){.kind = TEX_CONSTANT, .value = v3s(0.5f)};
        const char *cls = td->tex_class ? td->tex_class : "";
        if (!strcmp(cls, "constant")) {
            t->value = texture_param_rgb(&td->params, "value", v3s(1.0f));
        } else if (!strcmp(cls, "checkerboard")) {
            int dim = params_int(&td->params, "dimension", 2);
            t->kind = dim == 3 ? TEX_CHECKERBOARD_3D : TEX_CHECKERBOARD_2D;
            t->tex1 = texture_param_rgb(&td->params, "tex1", v3s(1.0f));
            t->tex2 = texture_param_rgb(&td->params, "tex2", v3s(0.0f));
            t->uscale = params_float(&td->params, "uscale", 1.0f);
            t->vscale = params_float(&td->params, "vscale", 1.0f);
            t->udelta = params_float(&td->params, "udelta", 0.0f);
            t->vdelta = params_float(&td->params, "vdelta", 0.0f);
            if (!mat4_inverse(&td->world_from_texture, &t->texture_from_world)) t->texture_from_world = mat4_identity();
        } else if (!seen_before(seen_tex, &n_seen_tex, 64, cls)) {
            scene_warn(scene, td->loc, "texture class '%s' is not supported yet; it evaluates to grey 0.5", cls);
        }
    }

    for (int i = 0; i < scene->material_count; ++i) {
        MaterialDesc *md = &scene->materials[i];
        Material *m = &table->materials[i];
        *m = table->default_material;
        const char *type = md->type ? md->type : "";
        if (!strcmp(type, "diffuse")) {
            float rgb[3];
            const char *tex = params_texture(&md->params, "reflectance");
            if (tex) {
                m->texture = find_texture(scene, tex);
                if (m->texture < 0) {
                    /* The parser normally rejects unknown textures; keep rendering if not. */
                    scene_warn(scene, md->loc, "unknown texture '%s'; using reflectance 0.5", tex);
                }
            } else if (params_rgb(&md->params, "reflectance", rgb)) {
                m->reflectance = clamp01(v3(rgb[0], rgb[1], rgb[2]));
            } else {
                const Param *p = params_find(&md->params, "reflectance");
                if (p && p->type == PARAM_FLOAT && p->count >= 1) m->reflectance = clamp01(v3s(p->floats[0]));
            }
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
    free(table->materials);
    free(table->textures);
    *table = (MaterialTable){0};
}

static vec3 texture_eval(const Texture *t, vec2 uv, vec3 p_world)
{
    switch (t->kind) {
    case TEX_CONSTANT: return t->value;
    case TEX_CHECKERBOARD_2D: {
        float s = uv.x * t->uscale + t->udelta, tt = uv.y * t->vscale + t->vdelta;
        long k = (long)floorf(s) + (long)floorf(tt);
        return (k & 1) == 0 ? t->tex1 : t->tex2;
    }
    case TEX_CHECKERBOARD_3D: {
        vec3 p = mat4_apply_point(&t->texture_from_world, p_world);
        long k = (long)floorf(p.x) + (long)floorf(p.y) + (long)floorf(p.z);
        return (k & 1) == 0 ? t->tex1 : t->tex2;
    }
    }
    return v3s(0.5f);
}

vec3 material_albedo(const MaterialTable *table, int m, vec2 uv, vec3 p_world)
{
    const Material *mat = (m >= 0 && m < table->material_count) ? &table->materials[m] : &table->default_material;
    if (mat->texture >= 0 && mat->texture < table->texture_count)
        return clamp01(texture_eval(&table->textures[mat->texture], uv, p_world));
    return mat->reflectance;
}
