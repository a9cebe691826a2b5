/* Trowbridge-Reitz (GGX) microfacet distribution; see microfacet.h. */
#include "render/microfacet.h"

#include <math.h>

#include "render/warp.h"

float microfacet_roughness_to_alpha(float roughness)
{
    return roughness > 0.0f && isfinite(roughness) ? sqrtf(roughness) : 0.0f;
}

static float sanitize_roughness(float r) { return r > 0.0f && isfinite(r) ? r : 0.0f; }

Microfacet microfacet_make(float uroughness, float vroughness, bool remap_roughness)
{
    float ru = sanitize_roughness(uroughness), rv = sanitize_roughness(vroughness);
    Microfacet m;
    m.alpha_x = remap_roughness ? microfacet_roughness_to_alpha(ru) : ru;
    m.alpha_y = remap_roughness ? microfacet_roughness_to_alpha(rv) : rv;
    /* as pbrt-v4: unless both axes are smooth (a delta lobe), neither alpha goes below 1e-4:
     * an axis at 0 would make D 0 everywhere off the plane (a black material) */
    if (!microfacet_is_smooth(m)) {
        m.alpha_x = fmaxf(m.alpha_x, MICROFACET_ALPHA_MIN);
        m.alpha_y = fmaxf(m.alpha_y, MICROFACET_ALPHA_MIN);
    }
    return m;
}

float microfacet_D(Microfacet m, vec3 wm)
{
    if (wm.z <= 0.0f) return 0.0f;
    /* With wm a unit vector, GGX's 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi/ax^2 +
     * sin^2 phi/ay^2))^2) simplifies to 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2):
     * no trigonometry, and no division by cos at grazing micro-normals. */
    float sx = wm.x / m.alpha_x, sy = wm.y / m.alpha_y;
    float q = sx * sx + sy * sy + wm.z * wm.z;
    float d = 1.0f / (WEDGE_PI * m.alpha_x * m.alpha_y * q * q);
    return isfinite(d) ? d : 0.0f;
}

float microfacet_lambda(Microfacet m, vec3 w)
{
    float z2 = w.z * w.z;
    if (z2 == 0.0f) return INFINITY; /* grazing: fully masked */
    /* alpha(phi)^2 tan^2(theta) = (x^2 ax^2 + y^2 ay^2) / z^2 */
    float a2t2 = (w.x * w.x * m.alpha_x * m.alpha_x + w.y * w.y * m.alpha_y * m.alpha_y) / z2;
    return 0.5f * (sqrtf(1.0f + a2t2) - 1.0f);
}

float microfacet_G1(Microfacet m, vec3 w) { return 1.0f / (1.0f + microfacet_lambda(m, w)); }

float microfacet_G(Microfacet m, vec3 wo, vec3 wi)
{
    return 1.0f / (1.0f + microfacet_lambda(m, wo) + microfacet_lambda(m, wi));
}

float microfacet_D_visible(Microfacet m, vec3 w, vec3 wm)
{
    float cos_w = fabsf(w.z);
    if (cos_w == 0.0f) return 0.0f;
    /* Only micro-normals facing w are visible; a w below the surface sees the same
     * (upper) micro-normals from the other side, as microfacet_sample_wm assumes. */
    float w_dot_m = v3_dot(w, wm) * (w.z < 0.0f ? -1.0f : 1.0f);
    if (w_dot_m <= 0.0f) return 0.0f;
    return microfacet_G1(m, w) / cos_w * microfacet_D(m, wm) * w_dot_m;
}

vec3 microfacet_sample_wm(Microfacet m, vec3 w, vec2 u)
{
    /* Heitz 2018: in the stretched configuration (alpha = 1) the visible normals of a
     * direction are those of a hemisphere seen from that direction, whose projection is
     * a unit disk with the half facing away foreshortened by (1 + cos)/2. Sample that
     * projected area uniformly, lift the point onto the hemisphere and un-stretch. */
    vec3 wh = v3_normalize(v3(m.alpha_x * w.x, m.alpha_y * w.y, w.z));
    if (wh.z < 0.0f) wh = v3_neg(wh);

    /* Basis (t1, t2, wh) with t1 perpendicular to the plane containing wh and z. */
    float len2 = wh.x * wh.x + wh.y * wh.y;
    vec3 t1 = len2 > 1e-14f ? v3_scale(v3(-wh.y, wh.x, 0.0f), 1.0f / sqrtf(len2)) : v3(1.0f, 0.0f, 0.0f);
    vec3 t2 = v3_cross(wh, t1);

    /* Uniform point on the unit disk (polar warp, keeps the half-disk split simple). */
    float r = sqrtf(u.x), phi = 2.0f * WEDGE_PI * u.y;
    float p1 = r * cosf(phi), p2 = r * sinf(phi);
    /* The half of the disk with p2 < 0 is seen compressed by cos(theta_h): squash it so
     * that its share of the area becomes (1 - cos)/2 of the visible hemisphere's. */
    float h = sqrtf(fmaxf(0.0f, 1.0f - p1 * p1));
    float blend = 0.5f * (1.0f + wh.z);
    p2 = (1.0f - blend) * h + blend * p2;

    float pz = sqrtf(fmaxf(0.0f, 1.0f - p1 * p1 - p2 * p2));
    vec3 nh = v3_add(v3_add(v3_scale(t1, p1), v3_scale(t2, p2)), v3_scale(wh, pz));
    /* Back to the ellipsoid configuration: normals transform with the inverse stretch. */
    vec3 wm = v3_normalize(v3(m.alpha_x * nh.x, m.alpha_y * nh.y, fmaxf(1e-6f, nh.z)));
    return wm;
}

float microfacet_phong_exponent(Microfacet m)
{
    float alpha2 = m.alpha_x * m.alpha_y; /* (geometric-mean alpha)^2 */
    if (microfacet_is_smooth(m) || !(alpha2 > 0.0f)) return MICROFACET_PHONG_MAX;
    /* Walter et al. 2007, sec. 5.2: alpha_b = sqrt(2 / (m + 2))  <=>  m = 2/alpha^2 - 2 */
    float e = 2.0f / alpha2 - 2.0f;
    return fminf(fmaxf(e, 0.0f), MICROFACET_PHONG_MAX);
}
