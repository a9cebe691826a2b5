/* Glossy BSDFs for pbrt-v4's "conductor", "coateddiffuse" and "dielectric" materials, built
 * on the Trowbridge-Reitz distribution of microfacet.h. docs/materials.md puts each model
 * next to pbrt-v4's definition and lists what is approximated.
 *
 * Conventions (as bsdf_diffuse_f / bsdf_diffuse_pdf in material.h): everything is in the
 * local shading frame, z = shading normal; wo (towards the viewer / the previous vertex)
 * and wi (towards the light / the next vertex) are unit vectors; f excludes the cosine
 * factor; pdfs are per unit solid angle of wi. Dielectric transmission carries the
 * radiance scaling 1/eta'^2 (pbrt-v4's TransportMode::Radiance): use these BSDFs for
 * camera paths. Reflection-only models (conductor, coateddiffuse) answer for wo below
 * the surface as if it were mirrored above (pbrt-v4 does the same through |cos|). */
#ifndef WEDGE_RENDER_BSDF_GLOSSY_H
#define WEDGE_RENDER_BSDF_GLOSSY_H

#include <stdbool.h>

#include "core/vec.h"
#include "render/microfacet.h"

typedef enum { GLOSSY_CONDUCTOR, GLOSSY_COATED_DIFFUSE, GLOSSY_DIELECTRIC } GlossyKind;

typedef struct {
    GlossyKind kind;
    Microfacet distrib;  /* conductor: the surface; coateddiffuse: the coat; dielectric: the interface */
    vec3 eta, k;         /* conductor: complex index of refraction per rgb channel */
    float eta_d;         /* coateddiffuse / dielectric: real IOR, inside over outside */
    vec3 base;           /* coateddiffuse: Lambert reflectance under the coat, in [0,1] */
    float fdr_ext;       /* coateddiffuse: hemispherical Fresnel reflectance of the coat seen
                          * from outside (fresnel_diffuse_reflectance(eta_d)) */
} GlossyBsdf;

/* One sampled direction. f and pdf follow the usual estimator f |cos_i| / pdf. For a
 * delta lobe, f is the lobe's weight divided by |cos_i| and pdf is the probability of
 * having picked that lobe (as pbrt-v4), so the same estimator applies. */
typedef struct {
    vec3 wi;
    vec3 f;
    float pdf;
    bool delta;          /* wi came from a specular (Dirac) lobe: no MIS, no eval */
    bool transmission;   /* wi is on the other side of the surface */
} GlossySample;

/* Albedo split for the filters' demodulation (AAF-GI divides the irradiance by these):
 * diffuse = hemispherical reflectance of the Lambert part, glossy = of the specular part,
 * both for the viewing direction wo. */
typedef struct {
    vec3 diffuse;
    vec3 glossy;
} GlossyAlbedo;

/* ---- Fresnel ---- */

/* Unpolarised Fresnel reflectance of a dielectric interface (pbrt-v4 FrDielectric):
 * cos_i > 0 means the light arrives from the outside (eta = n_inside / n_outside); a
 * negative cos_i is from the inside. Total internal reflection gives 1. */
float fresnel_dielectric(float cos_i, float eta);
/* Fresnel reflectance of a conductor with complex IOR eta + i k (pbrt-v4 FrComplex),
 * cos_i in [0,1]. */
float fresnel_complex(float cos_i, float eta, float k);
vec3 fresnel_complex_rgb(float cos_i, vec3 eta, vec3 k);
/* Cosine-weighted hemispherical average of fresnel_dielectric seen from outside:
 * 2 * integral_0^1 F(mu, eta) mu dmu (numerical quadrature; about 128 Fresnel evaluations,
 * so cache it per material). */
float fresnel_diffuse_reflectance(float eta);

/* ---- construction ---- */

/* A conductor with complex IOR eta + i k per channel (relative to the outside medium). */
GlossyBsdf glossy_conductor(Microfacet d, vec3 eta, vec3 k);
/* pbrt-v4's "reflectance" parameterisation of a conductor: r is clamped to [0, 0.9999],
 * eta = 1 and k = 2 sqrt(r) / sqrt(1 - r), which makes the normal-incidence Fresnel
 * reflectance exactly r (it is not Schlick's approximation: the full complex Fresnel
 * curve of that (eta, k) is used at other angles). */
GlossyBsdf glossy_conductor_reflectance(Microfacet d, vec3 r);
/* pbrt-v4 coateddiffuse: base reflectance under a dielectric coat of IOR eta (default 1.5)
 * and the coat's distribution (default roughness 0 = smooth). thickness, albedo and g are
 * not modelled. fdr_ext < 0 computes fresnel_diffuse_reflectance(eta) here. */
GlossyBsdf glossy_coated_diffuse(Microfacet coat, vec3 base, float eta, float fdr_ext);
/* pbrt-v4 dielectric (eta default 1.5): smooth or rough reflection + transmission. */
GlossyBsdf glossy_dielectric(Microfacet d, float eta);

/* ---- evaluation ---- */

/* f(wo, wi) of the non-delta lobes (delta lobes contribute 0 here). */
vec3 glossy_f(const GlossyBsdf *b, vec3 wo, vec3 wi);
/* The diffuse lobe's share of glossy_f(wo, wi): coateddiffuse's base as seen through the coat
 * (its `f` without the coat's microfacet term), 0 for conductors and dielectrics. Between 0
 * and glossy_f, so glossy_f - glossy_f_diffuse is the glossy lobes' share (the filters'
 * per-lobe split of the first hit's direct light, SampleRecord.direct_glossy). */
vec3 glossy_f_diffuse(const GlossyBsdf *b, vec3 wo, vec3 wi);
/* Solid-angle density with which glossy_sample produces wi (non-delta lobes only, including
 * the probability of choosing that lobe). */
float glossy_pdf(const GlossyBsdf *b, vec3 wo, vec3 wi);
/* Samples wi given wo; u_lobe picks the lobe, u the direction (all in [0,1)). Returns false
 * when no direction results (below the surface, total internal reflection, zero pdf). */
bool glossy_sample(const GlossyBsdf *b, vec3 wo, float u_lobe, vec2 u, GlossySample *s);

/* True when every lobe is a delta (nothing to evaluate, no light sampling worth doing). */
bool glossy_is_delta(const GlossyBsdf *b);
/* False for dielectrics: the filters pass their light through unfiltered (issue 4). */
bool glossy_is_filterable(const GlossyBsdf *b);
/* Diffuse and glossy albedo for demodulation, for the direction wo. */
GlossyAlbedo glossy_albedo(const GlossyBsdf *b, vec3 wo);
/* Equivalent Blinn-Phong exponent of the glossy lobe (microfacet_phong_exponent of its
 * distribution; MICROFACET_PHONG_MAX for delta lobes and dielectrics). */
float glossy_phong_exponent(const GlossyBsdf *b);

#endif
