/* pbrt-v4 glossy material parameters -> GlossyParams; see glossy_params.h. */
#include "render/glossy_params.h"

#include <math.h>
#include <string.h>

#include "scene/spectrum.h"

bool glossy_material_type(const char *type)
{
    return type && (!strcmp(type, "conductor") || !strcmp(type, "coateddiffuse") || !strcmp(type, "dielectric"));
}

static void warn(SceneDesc *scene, SrcLoc loc, const char *msg, const char *name)
{
    if (scene) scene_warn(scene, loc, msg, name);
}

/* A float-or-texture parameter: the texture name (constant left at def), or the constant. */
static float float_or_texture(const ParamSet *ps, const char *name, float def, const char **tex)
{
    *tex = params_texture(ps, name);
    return *tex ? def : params_float(ps, name, def);
}

/* A real index of refraction given as a float or as a spectrum (green channel). */
static float read_ior(SceneDesc *scene, const MaterialDesc *md, float def)
{
    const Param *p = params_find(&md->params, "eta");
    if (!p) return def;
    float eta = def;
    if (p->type == PARAM_FLOAT) {
        eta = params_float(&md->params, "eta", def);
    } else if (p->type == PARAM_TEXTURE) {
        (void)params_texture(&md->params, "eta");
        warn(scene, p->loc, "textured \"%s\" is not supported; using 1.5", "eta");
    } else {
        float rgb[3];
        if (params_rgb(&md->params, "eta", rgb)) eta = rgb[1];
    }
    if (!(eta > 0.0f) || !isfinite(eta)) {
        warn(scene, p->loc, "\"%s\" must be positive; using 1.5", "eta");
        eta = 1.5f;
    }
    return eta;
}

static vec3 rgb_or(const ParamSet *ps, const char *name, vec3 def)
{
    float rgb[3];
    if (params_rgb(ps, name, rgb)) return v3(rgb[0], rgb[1], rgb[2]);
    const Param *p = params_find(ps, name);
    if (p && p->type == PARAM_FLOAT && p->count >= 1) return v3s(p->floats[0]);
    return def;
}

static vec3 named_rgb(const char *name)
{
    float rgb[3] = {1.0f, 1.0f, 1.0f};
    if (!spectrum_named_rgb(name, rgb)) spectrum_unknown_substitute(name, rgb);
    return v3(rgb[0], rgb[1], rgb[2]);
}

bool glossy_params_read(SceneDesc *scene, const MaterialDesc *md, GlossyParams *gp, Diag *err)
{
    const ParamSet *ps = &md->params;
    *gp = (GlossyParams){0};
    const char *type = md->type ? md->type : "";
    if (!strcmp(type, "conductor")) gp->kind = GLOSSY_CONDUCTOR;
    else if (!strcmp(type, "coateddiffuse")) gp->kind = GLOSSY_COATED_DIFFUSE;
    else gp->kind = GLOSSY_DIELECTRIC;

    const char *rough_tex = NULL;
    float rough = float_or_texture(ps, "roughness", 0.0f, &rough_tex);
    gp->uroughness = float_or_texture(ps, "uroughness", rough, &gp->uroughness_tex);
    gp->vroughness = float_or_texture(ps, "vroughness", rough, &gp->vroughness_tex);
    if (!params_find(ps, "uroughness")) gp->uroughness_tex = rough_tex;
    if (!params_find(ps, "vroughness")) gp->vroughness_tex = rough_tex;
    gp->remap_roughness = params_bool(ps, "remaproughness", true);

    switch (gp->kind) {
    case GLOSSY_CONDUCTOR: {
        const Param *eta = params_find(ps, "eta"), *k = params_find(ps, "k"), *refl = params_find(ps, "reflectance");
        if (refl && (eta || k)) {
            diag_set(err, WEDGE_EXIT_INPUT, md->loc,
                     "conductor: give either \"reflectance\" or \"eta\" and \"k\", not both (as pbrt-v4)");
            return false;
        }
        gp->eta_rgb = named_rgb("metal-Cu-eta");
        gp->k_rgb = named_rgb("metal-Cu-k");
        if (refl) {
            gp->conductor_uses_reflectance = true;
            gp->color_tex = params_texture(ps, "reflectance");
            gp->color = gp->color_tex ? v3s(0.5f) : rgb_or(ps, "reflectance", v3s(0.5f));
        } else {
            if (eta && eta->type == PARAM_TEXTURE) {
                (void)params_texture(ps, "eta");
                warn(scene, eta->loc, "textured \"%s\" is not supported; using metal-Cu", "eta");
            } else {
                gp->eta_rgb = rgb_or(ps, "eta", gp->eta_rgb);
            }
            if (k && k->type == PARAM_TEXTURE) {
                (void)params_texture(ps, "k");
                warn(scene, k->loc, "textured \"%s\" is not supported; using metal-Cu", "k");
            } else {
                gp->k_rgb = rgb_or(ps, "k", gp->k_rgb);
            }
        }
        break;
    }
    case GLOSSY_COATED_DIFFUSE: {
        gp->color_tex = params_texture(ps, "reflectance");
        gp->color = gp->color_tex ? v3s(0.5f) : rgb_or(ps, "reflectance", v3s(0.5f));
        gp->eta = read_ior(scene, md, 1.5f);
        gp->fdr_ext = fresnel_diffuse_reflectance(gp->eta);
        /* read so that they are not reported unused; pbrt-v4's random-walk layer model */
        (void)params_float(ps, "thickness", 0.01f);
        (void)params_float(ps, "g", 0.0f);
        (void)params_int(ps, "maxdepth", 10);
        (void)params_int(ps, "nsamples", 1);
        const Param *albedo = params_find(ps, "albedo");
        if (albedo) {
            vec3 a = albedo->type == PARAM_TEXTURE ? v3s(1.0f) : rgb_or(ps, "albedo", v3s(0.0f));
            if (albedo->type == PARAM_TEXTURE) (void)params_texture(ps, "albedo");
            if (v3_max_component(a) > 0.0f)
                warn(scene, albedo->loc, "coateddiffuse \"%s\" (scattering inside the coat) is not modelled; ignored",
                     "albedo");
        }
        break;
    }
    case GLOSSY_DIELECTRIC: gp->eta = read_ior(scene, md, 1.5f); break;
    }
    return true;
}

GlossyBsdf glossy_params_bsdf(const GlossyParams *gp, float uroughness, float vroughness, vec3 color)
{
    Microfacet d = microfacet_make(uroughness, vroughness, gp->remap_roughness);
    switch (gp->kind) {
    case GLOSSY_CONDUCTOR:
        return gp->conductor_uses_reflectance ? glossy_conductor_reflectance(d, color)
                                              : glossy_conductor(d, gp->eta_rgb, gp->k_rgb);
    case GLOSSY_COATED_DIFFUSE: return glossy_coated_diffuse(d, color, gp->eta, gp->fdr_ext);
    case GLOSSY_DIELECTRIC: return glossy_dielectric(d, gp->eta);
    }
    return glossy_dielectric(d, 1.5f);
}
