/* Reading pbrt-v4's "conductor", "coateddiffuse" and "dielectric" material parameters into
 * the constants and texture names a GlossyBsdf is built from (bsdf_glossy.h). Kept apart
 * from the BSDFs so that those stay free of scene types; material.c resolves the texture
 * names against its own texture table and calls glossy_params_bsdf per shading point.
 *
 * Parameters and defaults (pbrt-v4 materials.cpp):
 *   all three: float(texture) roughness 0, uroughness / vroughness default roughness,
 *              bool remaproughness true (alpha = sqrt(roughness)).
 *   conductor: spectrum eta "metal-Cu-eta", spectrum k "metal-Cu-k", or spectrum
 *              reflectance instead of eta and k (both given: error, as pbrt-v4).
 *   coateddiffuse: spectrum(texture) reflectance 0.5, float(spectrum) eta 1.5; thickness,
 *              albedo, g, maxdepth, nsamples are read and not modelled (a warning when
 *              albedo is non-zero, since only then does pbrt-v4's coat scatter).
 *   dielectric: float(spectrum) eta 1.5 (a spectrum, e.g. "glass-BK7", uses its green
 *              channel: no dispersion).
 * Texture-valued eta / k are not supported (warning, default used). */
#ifndef WEDGE_RENDER_GLOSSY_PARAMS_H
#define WEDGE_RENDER_GLOSSY_PARAMS_H

#include <stdbool.h>

#include "core/diag.h"
#include "render/bsdf_glossy.h"
#include "scene/scene_desc.h"

typedef struct {
    GlossyKind kind;
    float uroughness, vroughness;       /* constants (used when the *_tex name is NULL) */
    const char *uroughness_tex, *vroughness_tex; /* float texture names, or NULL */
    bool remap_roughness;
    vec3 color;                         /* coateddiffuse base reflectance; conductor reflectance */
    const char *color_tex;              /* texture name for color, or NULL */
    bool conductor_uses_reflectance;    /* conductor: color (reflectance) instead of eta, k */
    vec3 eta_rgb, k_rgb;                /* conductor complex IOR */
    float eta;                          /* coateddiffuse / dielectric IOR */
    float fdr_ext;                      /* coateddiffuse: fresnel_diffuse_reflectance(eta), cached */
} GlossyParams;

/* True when type is one of the three glossy materials. */
bool glossy_material_type(const char *type);

/* Reads md (whose type glossy_material_type accepts). Warnings go to scene (may be NULL).
 * Returns false with err (exit 2, at the material's location) on contradictory input. */
bool glossy_params_read(SceneDesc *scene, const MaterialDesc *md, GlossyParams *gp, Diag *err);

/* The BSDF at a shading point, given the evaluated textures (pass gp->uroughness,
 * gp->vroughness, gp->color when the material has no texture for them). */
GlossyBsdf glossy_params_bsdf(const GlossyParams *gp, float uroughness, float vroughness, vec3 color);

#endif
