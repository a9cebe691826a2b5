/* Trowbridge-Reitz (GGX) microfacet distribution, as pbrt-v4's TrowbridgeReitzDistribution:
 * normal distribution D, Smith masking Lambda / G1 / height-correlated G, and sampling of
 * the distribution of normals visible from a direction (Heitz 2018, "Sampling the GGX
 * Distribution of Visible Normals", JCGT 7(4)).
 *
 * Everything lives in the local shading frame: z is the shading normal, x and y the
 * tangent directions that alpha_x and alpha_y refer to. Directions are unit vectors. */
#ifndef WEDGE_RENDER_MICROFACET_H
#define WEDGE_RENDER_MICROFACET_H

#include <stdbool.h>

#include "core/vec.h"

typedef struct {
    float alpha_x, alpha_y; /* slope-space roughness along x and y (not the pbrt "roughness") */
} Microfacet;

/* pbrt-v4 calls a distribution with max(alpha) below this "effectively smooth" and
 * switches to a perfectly specular (delta) lobe. */
#define MICROFACET_SMOOTH_ALPHA 1e-3f
/* Smallest alpha of a rough lobe's axis (pbrt-v4's TrowbridgeReitzDistribution). */
#define MICROFACET_ALPHA_MIN 1e-4f

/* pbrt-v4's TrowbridgeReitzDistribution::RoughnessToAlpha: alpha = sqrt(roughness). Used
 * when a material's "remaproughness" is true (the default); otherwise roughness is alpha. */
float microfacet_roughness_to_alpha(float roughness);

/* Builds the distribution from the material parameters uroughness / vroughness. Negative
 * or non-finite inputs are treated as 0 (smooth). */
Microfacet microfacet_make(float uroughness, float vroughness, bool remap_roughness);

static inline bool microfacet_is_smooth(Microfacet m)
{
    return fmaxf(m.alpha_x, m.alpha_y) < MICROFACET_SMOOTH_ALPHA;
}

/* D(wm): density of micro-normals per unit projected macro-surface area, so that
 * integral D(wm) cos(theta_m) dwm = 1 over the upper hemisphere. wm.z <= 0 gives 0. */
float microfacet_D(Microfacet m, vec3 wm);

/* Smith's auxiliary function Lambda(w) (the masking integral over slopes). */
float microfacet_lambda(Microfacet m, vec3 w);
/* Smith masking of direction w: G1 = 1 / (1 + Lambda(w)). */
float microfacet_G1(Microfacet m, vec3 w);
/* Height-correlated masking-shadowing: G = 1 / (1 + Lambda(wo) + Lambda(wi)). */
float microfacet_G(Microfacet m, vec3 wo, vec3 wi);

/* Distribution of normals visible from w: D_w(wm) = G1(w) max(0, w.wm) D(wm) / |w.z|
 * (Heitz 2014, eq. 15 of "Understanding the masking-shadowing function"). It integrates to
 * 1 over wm and is the density (per solid angle of wm) that microfacet_sample_wm draws.
 * For w below the surface (w.z < 0) the upper micro-normals are seen from below: max(0,
 * -w.wm) replaces max(0, w.wm). */
float microfacet_D_visible(Microfacet m, vec3 w, vec3 wm);

/* Draws a micro-normal from D_w (w flipped to the upper hemisphere first, so the result
 * always has wm.z >= 0). u in [0,1)^2. */
vec3 microfacet_sample_wm(Microfacet m, vec3 w, vec2 u);

/* The "equivalent Blinn-Phong exponent" of this lobe for the AAF-GI band limit (002, eq. 18:
 * Omega_h = 3.6 + 0.084 m). Walter et al. 2007 ("Microfacet models for refraction through
 * rough surfaces", section 5.2) relate a Phong exponent to a Beckmann width by
 * alpha_b = sqrt(2 / (m + 2)), i.e. m = 2 / alpha^2 - 2; we apply it to the GGX alpha (the
 * two distributions have the same alpha scale near the peak, where both are
 * ~ exp(-tan^2/alpha^2)-like). Anisotropic lobes use the geometric mean sqrt(ax ay).
 * Clamped to [0, MICROFACET_PHONG_MAX]; smooth lobes return MICROFACET_PHONG_MAX. */
#define MICROFACET_PHONG_MAX 1.0e4f
float microfacet_phong_exponent(Microfacet m);

#endif
