/* Conductor, coated diffuse and dielectric BSDFs; see bsdf_glossy.h and docs/materials.md. */
#include "render/bsdf_glossy.h"

#include <complex.h>
#include <math.h>

#include "render/warp.h"

#define INV_PI 0.318309886f

/* ---------------------------------------------------------------- Fresnel */

float fresnel_dielectric(float cos_i, float eta)
{
    cos_i = fminf(fmaxf(cos_i, -1.0f), 1.0f);
    if (cos_i < 0.0f) { /* arriving from inside: swap the media */
        eta = 1.0f / eta;
        cos_i = -cos_i;
    }
    float sin2_i = 1.0f - cos_i * cos_i;
    float sin2_t = sin2_i / (eta * eta); /* Snell */
    if (sin2_t >= 1.0f) return 1.0f;    /* total internal reflection */
    float cos_t = sqrtf(fmaxf(0.0f, 1.0f - sin2_t));
    float r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_par * r_par + r_perp * r_perp);
}

float fresnel_complex(float cos_i, float eta, float k)
{
    /* The dielectric formulas with a complex index n = eta + i k (the transmitted angle
     * becomes complex too); reflectance is the mean squared modulus of the two
     * polarisations' amplitude ratios. */
    cos_i = fminf(fmaxf(cos_i, 0.0f), 1.0f);
    double complex n = (double)eta + (double)k * I;
    double ci = cos_i;
    double complex sin2_t = (1.0 - ci * ci) / (n * n);
    double complex cos_t = csqrt(1.0 - sin2_t);
    double complex r_par = (n * ci - cos_t) / (n * ci + cos_t);
    double complex r_perp = (ci - n * cos_t) / (ci + n * cos_t);
    double r = 0.5 * (creal(r_par * conj(r_par)) + creal(r_perp * conj(r_perp)));
    return isfinite(r) ? (float)fmin(fmax(r, 0.0), 1.0) : 1.0f;
}

vec3 fresnel_complex_rgb(float cos_i, vec3 eta, vec3 k)
{
    return v3(fresnel_complex(cos_i, eta.x, k.x), fresnel_complex(cos_i, eta.y, k.y),
              fresnel_complex(cos_i, eta.z, k.z));
}

float fresnel_diffuse_reflectance(float eta)
{
    /* 2 int_0^1 F(mu) mu dmu = int_0^1 F(sqrt(t)) dt with t = mu^2: the integrand is smooth
     * from outside (no total internal reflection), midpoint rule with 128 nodes. */
    const int n = 128;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        double t = (i + 0.5) / n;
        sum += fresnel_dielectric((float)sqrt(t), eta);
    }
    return (float)(sum / n);
}

/* ---------------------------------------------------------------- helpers */

static inline float abs_cos(vec3 w) { return fabsf(w.z); }
static inline bool same_hemisphere(vec3 a, vec3 b) { return a.z * b.z > 0.0f; }
static inline vec3 reflect_about(vec3 wo, vec3 n) { return v3_sub(v3_scale(n, 2.0f * v3_dot(wo, n)), wo); }
static inline vec3 mirror_z(vec3 w) { return v3(w.x, w.y, -w.z); }
static inline float mean3(vec3 c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

/* Refracts wo (pointing away from the surface) through the interface with normal n; eta is
 * inside over outside with n pointing outside. Returns false on total internal
 * reflection; *etap is the relative IOR actually crossed (eta or 1/eta). */
static bool refract_dir(vec3 wo, vec3 n, float eta, float *etap, vec3 *wt)
{
    float cos_i = v3_dot(n, wo);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
        n = v3_neg(n);
    }
    float sin2_i = fmaxf(0.0f, 1.0f - cos_i * cos_i);
    float sin2_t = sin2_i / (eta * eta);
    if (sin2_t >= 1.0f) return false;
    float cos_t = sqrtf(1.0f - sin2_t);
    *wt = v3_add(v3_scale(v3_neg(wo), 1.0f / eta), v3_scale(n, cos_i / eta - cos_t));
    *etap = eta;
    return true;
}

static vec3 sanitize_rgb(vec3 c)
{
    if (!isfinite(c.x) || !isfinite(c.y) || !isfinite(c.z)) return v3s(0.0f);
    return v3(fmaxf(c.x, 0.0f), fmaxf(c.y, 0.0f), fmaxf(c.z, 0.0f));
}

/* ---------------------------------------------------------------- construction */

GlossyBsdf glossy_conductor(Microfacet d, vec3 eta, vec3 k)
{
    GlossyBsdf b = {0};
    b.kind = GLOSSY_CONDUCTOR;
    b.distrib = d;
    b.eta = eta;
    b.k = k;
    return b;
}

static float reflectance_to_k(float r)
{
    r = fminf(fmaxf(r, 0.0f), 0.9999f); /* pbrt-v4 clamps too: r = 1 would need k = inf */
    return 2.0f * sqrtf(r) / sqrtf(1.0f - r);
}

GlossyBsdf glossy_conductor_reflectance(Microfacet d, vec3 r)
{
    /* F(0) = ((eta-1)^2 + k^2) / ((eta+1)^2 + k^2) = k^2 / (4 + k^2) at eta = 1, which is r
     * for k^2 = 4 r / (1 - r). */
    return glossy_conductor(d, v3s(1.0f), v3(reflectance_to_k(r.x), reflectance_to_k(r.y), reflectance_to_k(r.z)));
}

GlossyBsdf glossy_coated_diffuse(Microfacet coat, vec3 base, float eta, float fdr_ext)
{
    GlossyBsdf b = {0};
    b.kind = GLOSSY_COATED_DIFFUSE;
    b.distrib = coat;
    b.eta_d = eta > 0.0f && isfinite(eta) ? eta : 1.5f;
    b.base = v3(fminf(fmaxf(base.x, 0.0f), 1.0f), fminf(fmaxf(base.y, 0.0f), 1.0f), fminf(fmaxf(base.z, 0.0f), 1.0f));
    b.fdr_ext = fdr_ext >= 0.0f ? fdr_ext : fresnel_diffuse_reflectance(b.eta_d);
    return b;
}

GlossyBsdf glossy_dielectric(Microfacet d, float eta)
{
    GlossyBsdf b = {0};
    b.kind = GLOSSY_DIELECTRIC;
    b.distrib = d;
    b.eta_d = eta > 0.0f && isfinite(eta) ? eta : 1.5f;
    return b;
}

/* ---------------------------------------------------------------- microfacet reflection */

/* Torrance-Sparrow reflection for wo, wi both above: D(wm) F G / (4 cos_o cos_i) without F. */
static float microfacet_reflection_noF(Microfacet d, vec3 wo, vec3 wi, vec3 *wm_out)
{
    vec3 wm = v3_add(wo, wi);
    if (v3_length2(wm) == 0.0f || wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    wm = v3_normalize(wm);
    *wm_out = wm;
    return microfacet_D(d, wm) * microfacet_G(d, wo, wi) / (4.0f * wo.z * wi.z);
}

/* Density of wi = reflect(wo, wm) with wm drawn from the visible normals of wo. */
static float microfacet_reflection_pdf(Microfacet d, vec3 wo, vec3 wi)
{
    vec3 wm = v3_add(wo, wi);
    if (v3_length2(wm) == 0.0f || wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    wm = v3_normalize(wm);
    /* dwm/dwi = 1 / (4 |wo.wm|) for reflection */
    return microfacet_D_visible(d, wo, wm) / (4.0f * fabsf(v3_dot(wo, wm)));
}

/* ---------------------------------------------------------------- conductor */

static vec3 conductor_f(const GlossyBsdf *b, vec3 wo, vec3 wi)
{
    if (microfacet_is_smooth(b->distrib)) return v3s(0.0f);
    vec3 wm;
    float s = microfacet_reflection_noF(b->distrib, wo, wi, &wm);
    if (s <= 0.0f) return v3s(0.0f);
    return v3_scale(fresnel_complex_rgb(fabsf(v3_dot(wo, wm)), b->eta, b->k), s);
}

static bool conductor_sample(const GlossyBsdf *b, vec3 wo, vec2 u, GlossySample *s)
{
    if (microfacet_is_smooth(b->distrib)) {
        vec3 wi = v3(-wo.x, -wo.y, wo.z);
        float c = abs_cos(wi);
        if (c == 0.0f) return false;
        *s = (GlossySample){wi, v3_scale(fresnel_complex_rgb(c, b->eta, b->k), 1.0f / c), 1.0f, true, false};
        return true;
    }
    vec3 wm = microfacet_sample_wm(b->distrib, wo, u);
    vec3 wi = reflect_about(wo, wm);
    if (wi.z <= 0.0f) return false; /* reflected below the macro-surface: no light */
    float pdf = microfacet_reflection_pdf(b->distrib, wo, wi);
    if (!(pdf > 0.0f)) return false;
    *s = (GlossySample){wi, conductor_f(b, wo, wi), pdf, false, false};
    return true;
}

/* ---------------------------------------------------------------- coated diffuse */

/* Base (Lambert under the coat) term. Light enters through the coat (1 - F(cos_i)), is
 * scattered by the base, bounces between base and coat (internal reflectance fdr_int, a
 * geometric series in base * fdr_int) and leaves (1 - F(cos_o)); the radiance inside is
 * eta^2 times denser (1/eta^2 on the way out). fdr_int follows from fdr_ext by
 * reciprocity, 1 - fdr_int = (1 - fdr_ext) / eta^2, which makes a white base under a
 * smooth coat reflect exactly 1 - F(cos_o) on top of the coat's F(cos_o). */
static vec3 coated_base_scale(const GlossyBsdf *b)
{
    float eta2 = b->eta_d * b->eta_d;
    float fdr_int = 1.0f - (1.0f - b->fdr_ext) / eta2;
    vec3 denom = v3(1.0f - b->base.x * fdr_int, 1.0f - b->base.y * fdr_int, 1.0f - b->base.z * fdr_int);
    return v3(b->base.x / (eta2 * denom.x), b->base.y / (eta2 * denom.y), b->base.z / (eta2 * denom.z));
}

static vec3 coated_base_f(const GlossyBsdf *b, vec3 wo, vec3 wi)
{
    if (wo.z <= 0.0f || wi.z <= 0.0f) return v3s(0.0f);
    float t = (1.0f - fresnel_dielectric(wo.z, b->eta_d)) * (1.0f - fresnel_dielectric(wi.z, b->eta_d));
    return v3_scale(coated_base_scale(b), t * INV_PI);
}

/* Probability of sampling the coat lobe: proportional to the energies of coat (F(cos_o))
 * and base ((1 - F(cos_o)) times the base's diffuse albedo), kept away from 0 and 1
 * whenever both lobes carry energy. */
static float coated_coat_prob(const GlossyBsdf *b, vec3 wo)
{
    float F = fresnel_dielectric(wo.z, b->eta_d);
    float base = mean3(coated_base_scale(b)) * (1.0f - b->fdr_ext) * (1.0f - F);
    if (!(base > 0.0f)) return 1.0f;
    float p = F / (F + base);
    return fminf(fmaxf(p, 0.05f), 0.95f);
}

static vec3 coated_f(const GlossyBsdf *b, vec3 wo, vec3 wi)
{
    if (wo.z < 0.0f) wo = mirror_z(wo), wi = mirror_z(wi);
    vec3 f = coated_base_f(b, wo, wi);
    if (!microfacet_is_smooth(b->distrib)) {
        vec3 wm;
        float s = microfacet_reflection_noF(b->distrib, wo, wi, &wm);
        /* The coat's Fresnel term is evaluated at max(wo.wm, cos_o, cos_i) rather than at
         * wo.wm alone: never above F(cos_o), so the coat reflects at most F(cos_o) (times
         * the Smith loss) and the base's (1 - F(cos_o)) share keeps the sum <= 1 for
         * every roughness; still symmetric in wo and wi. With plain F(wo.wm) a white base
         * under a rough coat measured up to 5e-4 above 1 (alpha 0.1, 44 degrees). */
        if (s > 0.0f) {
            float cos_f = fmaxf(fabsf(v3_dot(wo, wm)), fmaxf(wo.z, wi.z));
            f = v3_add(f, v3s(s * fresnel_dielectric(cos_f, b->eta_d)));
        }
    }
    return f;
}

static float coated_pdf(const GlossyBsdf *b, vec3 wo, vec3 wi)
{
    if (wo.z < 0.0f) wo = mirror_z(wo), wi = mirror_z(wi);
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float pc = coated_coat_prob(b, wo);
    float pdf = (1.0f - pc) * wi.z * INV_PI;
    if (!microfacet_is_smooth(b->distrib)) pdf += pc * microfacet_reflection_pdf(b->distrib, wo, wi);
    return pdf;
}

static bool coated_sample(const GlossyBsdf *b, vec3 wo, float u_lobe, vec2 u, GlossySample *s)
{
    bool flipped = wo.z < 0.0f;
    if (flipped) wo = mirror_z(wo);
    if (wo.z == 0.0f) return false;
    float pc = coated_coat_prob(b, wo);
    bool smooth = microfacet_is_smooth(b->distrib);
    vec3 wi;
    if (u_lobe < pc) {
        if (smooth) {
            wi = v3(-wo.x, -wo.y, wo.z);
            float F = fresnel_dielectric(wo.z, b->eta_d);
            *s = (GlossySample){wi, v3s(F / wi.z), pc, true, false};
            if (flipped) s->wi = mirror_z(s->wi);
            return true;
        }
        wi = reflect_about(wo, microfacet_sample_wm(b->distrib, wo, u));
    } else {
        wi = warp_cosine_hemisphere(u);
    }
    if (wi.z <= 0.0f) return false;
    float pdf = coated_pdf(b, wo, wi);
    if (!(pdf > 0.0f)) return false;
    *s = (GlossySample){wi, coated_f(b, wo, wi), pdf, false, false};
    if (flipped) s->wi = mirror_z(s->wi);
    return true;
}

/* ---------------------------------------------------------------- dielectric */

/* The generalized half vector of a reflection or refraction pair (Walter et al. 2007,
 * eq. 16), faced towards +z; false for degenerate or back-facing configurations. */
static bool dielectric_half_vector(const GlossyBsdf *b, vec3 wo, vec3 wi, vec3 *wm, float *etap, bool *reflect)
{
    float co = wo.z, ci = wi.z;
    if (co == 0.0f || ci == 0.0f) return false;
    *reflect = co * ci > 0.0f;
    *etap = 1.0f;
    if (!*reflect) *etap = co > 0.0f ? b->eta_d : 1.0f / b->eta_d;
    vec3 h = v3_add(v3_scale(wi, *etap), wo);
    if (v3_length2(h) == 0.0f) return false;
    h = v3_normalize(h);
    if (h.z < 0.0f) h = v3_neg(h);
    /* Micro-normals that face away from either direction cannot connect them. */
    if (v3_dot(h, wi) * ci < 0.0f || v3_dot(h, wo) * co < 0.0f) return false;
    *wm = h;
    return true;
}

static vec3 dielectric_f(const GlossyBsdf *b, vec3 wo, vec3 wi)
{
    if (b->eta_d == 1.0f || microfacet_is_smooth(b->distrib)) return v3s(0.0f);
    vec3 wm;
    float etap;
    bool reflect;
    if (!dielectric_half_vector(b, wo, wi, &wm, &etap, &reflect)) return v3s(0.0f);
    float F = fresnel_dielectric(v3_dot(wo, wm), b->eta_d);
    float D = microfacet_D(b->distrib, wm), G = microfacet_G(b->distrib, wo, wi);
    if (reflect) return v3s(D * G * F / fabsf(4.0f * wi.z * wo.z));
    /* Walter et al. 2007, eq. 21, with the radiance compression 1 / etap^2. */
    float dwi = v3_dot(wi, wm), dwo = v3_dot(wo, wm);
    float denom = (dwi + dwo / etap) * (dwi + dwo / etap) * wi.z * wo.z;
    if (denom == 0.0f) return v3s(0.0f);
    float ft = D * (1.0f - F) * G * fabsf(dwi * dwo / denom) / (etap * etap);
    return v3s(isfinite(ft) ? ft : 0.0f);
}

static float dielectric_pdf(const GlossyBsdf *b, vec3 wo, vec3 wi)
{
    if (b->eta_d == 1.0f || microfacet_is_smooth(b->distrib)) return 0.0f;
    vec3 wm;
    float etap;
    bool reflect;
    if (!dielectric_half_vector(b, wo, wi, &wm, &etap, &reflect)) return 0.0f;
    float R = fresnel_dielectric(v3_dot(wo, wm), b->eta_d), T = 1.0f - R;
    float dvis = microfacet_D_visible(b->distrib, wo, wm);
    if (reflect) return dvis / (4.0f * fabsf(v3_dot(wo, wm))) * R / (R + T);
    float dwi = v3_dot(wi, wm), dwo = v3_dot(wo, wm);
    float denom = (dwi + dwo / etap) * (dwi + dwo / etap);
    if (denom == 0.0f) return 0.0f;
    float pdf = dvis * fabsf(dwi) / denom * T / (R + T); /* dwm/dwi of refraction */
    return isfinite(pdf) ? pdf : 0.0f;
}

static bool dielectric_sample(const GlossyBsdf *b, vec3 wo, float u_lobe, vec2 u, GlossySample *s)
{
    float eta = b->eta_d;
    if (wo.z == 0.0f) return false;
    if (eta == 1.0f || microfacet_is_smooth(b->distrib)) {
        float R = fresnel_dielectric(wo.z, eta), T = 1.0f - R;
        if (eta == 1.0f) R = 0.0f, T = 1.0f;
        if (u_lobe < R / (R + T)) {
            vec3 wi = v3(-wo.x, -wo.y, wo.z);
            *s = (GlossySample){wi, v3s(R / abs_cos(wi)), R / (R + T), true, false};
            return true;
        }
        float etap;
        vec3 wi;
        if (!refract_dir(wo, v3(0.0f, 0.0f, 1.0f), eta, &etap, &wi) || wi.z == 0.0f) return false;
        float ft = T / abs_cos(wi) / (etap * etap);
        *s = (GlossySample){wi, v3s(ft), T / (R + T), true, true};
        return true;
    }
    vec3 wm = microfacet_sample_wm(b->distrib, wo, u);
    float R = fresnel_dielectric(v3_dot(wo, wm), eta), T = 1.0f - R;
    vec3 wi;
    bool transmit = false;
    if (u_lobe < R / (R + T)) {
        wi = reflect_about(wo, wm);
        if (!same_hemisphere(wo, wi)) return false;
    } else {
        float etap;
        if (!refract_dir(wo, wm, eta, &etap, &wi)) return false;
        if (same_hemisphere(wo, wi) || wi.z == 0.0f) return false;
        transmit = true;
    }
    float pdf = dielectric_pdf(b, wo, wi);
    if (!(pdf > 0.0f)) return false;
    *s = (GlossySample){wi, dielectric_f(b, wo, wi), pdf, false, transmit};
    return true;
}

/* ---------------------------------------------------------------- dispatch */

vec3 glossy_f(const GlossyBsdf *b, vec3 wo, vec3 wi)
{
    vec3 f = v3s(0.0f);
    switch (b->kind) {
    case GLOSSY_CONDUCTOR:
        if (wo.z < 0.0f) wo = mirror_z(wo), wi = mirror_z(wi);
        f = conductor_f(b, wo, wi);
        break;
    case GLOSSY_COATED_DIFFUSE: f = coated_f(b, wo, wi); break;
    case GLOSSY_DIELECTRIC: f = dielectric_f(b, wo, wi); break;
    }
    return sanitize_rgb(f);
}

vec3 glossy_f_diffuse(const GlossyBsdf *b, vec3 wo, vec3 wi)
{
    if (b->kind != GLOSSY_COATED_DIFFUSE) return v3s(0.0f);
    if (wo.z < 0.0f) wo = mirror_z(wo), wi = mirror_z(wi); /* as coated_f */
    return sanitize_rgb(coated_base_f(b, wo, wi));
}

float glossy_pdf(const GlossyBsdf *b, vec3 wo, vec3 wi)
{
    float pdf = 0.0f;
    switch (b->kind) {
    case GLOSSY_CONDUCTOR:
        if (microfacet_is_smooth(b->distrib)) return 0.0f;
        if (wo.z < 0.0f) wo = mirror_z(wo), wi = mirror_z(wi);
        pdf = microfacet_reflection_pdf(b->distrib, wo, wi);
        break;
    case GLOSSY_COATED_DIFFUSE: pdf = coated_pdf(b, wo, wi); break;
    case GLOSSY_DIELECTRIC: pdf = dielectric_pdf(b, wo, wi); break;
    }
    return isfinite(pdf) && pdf > 0.0f ? pdf : 0.0f;
}

bool glossy_sample(const GlossyBsdf *b, vec3 wo, float u_lobe, vec2 u, GlossySample *s)
{
    bool ok = false;
    switch (b->kind) {
    case GLOSSY_CONDUCTOR: {
        bool flipped = wo.z < 0.0f;
        if (flipped) wo = mirror_z(wo);
        ok = conductor_sample(b, wo, u, s);
        if (ok && flipped) s->wi = mirror_z(s->wi);
        break;
    }
    case GLOSSY_COATED_DIFFUSE: ok = coated_sample(b, wo, u_lobe, u, s); break;
    case GLOSSY_DIELECTRIC: ok = dielectric_sample(b, wo, u_lobe, u, s); break;
    }
    if (!ok) return false;
    s->f = sanitize_rgb(s->f);
    return isfinite(s->pdf) && s->pdf > 0.0f;
}

bool glossy_is_delta(const GlossyBsdf *b)
{
    switch (b->kind) {
    case GLOSSY_CONDUCTOR: return microfacet_is_smooth(b->distrib);
    case GLOSSY_COATED_DIFFUSE: return false; /* the base is always diffuse */
    case GLOSSY_DIELECTRIC: return b->eta_d == 1.0f || microfacet_is_smooth(b->distrib);
    }
    return false;
}

bool glossy_is_filterable(const GlossyBsdf *b) { return b->kind != GLOSSY_DIELECTRIC; }

GlossyAlbedo glossy_albedo(const GlossyBsdf *b, vec3 wo)
{
    GlossyAlbedo a = {v3s(0.0f), v3s(0.0f)};
    float c = fminf(fabsf(wo.z), 1.0f);
    switch (b->kind) {
    case GLOSSY_CONDUCTOR:
        /* The specular albedo at wo: exact for a smooth conductor, the Fresnel term at the
         * macro-normal for a rough one (ignores the Smith energy loss). */
        a.glossy = fresnel_complex_rgb(c, b->eta, b->k);
        break;
    case GLOSSY_COATED_DIFFUSE: {
        float F = fresnel_dielectric(c, b->eta_d);
        a.glossy = v3s(F);
        /* Exact hemispherical integral of coated_base_f: (1 - F(cos_o)) times
         * base (1 - fdr_ext) / (eta^2 (1 - base fdr_int)). */
        a.diffuse = v3_scale(coated_base_scale(b), (1.0f - F) * (1.0f - b->fdr_ext));
        break;
    }
    case GLOSSY_DIELECTRIC: a.glossy = v3s(1.0f); break; /* no absorption: R + T = 1 */
    }
    return a;
}

float glossy_phong_exponent(const GlossyBsdf *b)
{
    if (b->kind == GLOSSY_DIELECTRIC) return MICROFACET_PHONG_MAX;
    return microfacet_phong_exponent(b->distrib);
}
