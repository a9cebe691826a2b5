/* The glossy BSDFs and the environment map used together the way the integrator will:
 * reflected radiance Lo(wo) = int Le(wi) f(wo, wi) |cos_i| dwi estimated by multiple
 * importance sampling (light sample + BSDF sample, power heuristic, delta lobes taken
 * without MIS) must match a brute-force quadrature of the same integral (delta lobes added
 * in closed form). This checks that GlossySample's f / pdf / delta conventions and
 * envmap_sample / envmap_pdf combine into an unbiased estimator. The delta lobes of the
 * smooth conductor and dielectric come from the Fresnel equations written out here in double
 * complex arithmetic (not from glossy_sample, which would check the code against itself). */
#include <complex.h>

#include "check.h"
#include "materials_test_util.h"
#include "render/bsdf_glossy.h"
#include "render/envmap.h"
#include "render/warp.h"

static float *make_sky(int n)
{
    float *rgb = malloc((size_t)n * n * 3 * sizeof(float));
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            float *p = rgb + 3 * ((size_t)y * n + x);
            vec3 w = envmap_equal_area_to_dir(v2((x + 0.5f) / n, (y + 0.5f) / n));
            float sky = 0.3f + 0.7f * fmaxf(w.z, 0.0f);
            p[0] = 0.5f * sky, p[1] = 0.7f * sky, p[2] = sky;
            if (w.z < -0.2f) p[0] = p[1] = p[2] = 0.05f; /* dark ground */
            if (v3_dot(w, v3_normalize(v3(0.5f, 0.2f, 0.8f))) > 0.97f) p[0] = p[1] = p[2] = 40.0f; /* sun */
        }
    return rgb;
}

/* Unpolarised Fresnel reflectance at an interface of relative complex index eta (the
 * conductor's n + i k, or a dielectric's real eta), from the incident cosine. */
static double fresnel_closed_form(double cos_i, double complex eta)
{
    double sin2_i = 1.0 - cos_i * cos_i;
    double complex cos_t = csqrt(1.0 - sin2_i / (eta * eta));
    double complex r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    double complex r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (creal(r_par * conj(r_par)) + creal(r_perp * conj(r_perp)));
}

typedef enum { DELTA_BY_SAMPLING, DELTA_CONDUCTOR, DELTA_DIELECTRIC } DeltaRef;

/* The delta lobes in closed form, green channel: a smooth conductor of normal reflectance r
 * (eta 1, k^2 = 4 r / (1 - r)) reflects F into the mirror direction; a smooth dielectric of
 * index eta (wo outside) reflects F and transmits (1 - F) / eta^2 along Snell's direction
 * (radiance is compressed into the smaller solid angle, pbrt-v4's Radiance transport). */
static double delta_closed_form(DeltaRef kind, double param, const Envmap *e, vec3 wo)
{
    vec3 mirror = v3(-wo.x, -wo.y, wo.z);
    double cos_i = wo.z;
    if (kind == DELTA_CONDUCTOR) {
        double k = 2.0 * sqrt(param) / sqrt(1.0 - param);
        return envmap_Le(e, mirror).y * fresnel_closed_form(cos_i, 1.0 + k * I);
    }
    double eta = param, F = fresnel_closed_form(cos_i, eta);
    double sin_t = sqrt(1.0 - cos_i * cos_i) / eta, cos_t = sqrt(1.0 - sin_t * sin_t);
    double s = sqrt(wo.x * wo.x + wo.y * wo.y); /* the transmitted ray leaves on the far side */
    vec3 refracted = v3((float)(-wo.x / s * sin_t), (float)(-wo.y / s * sin_t), (float)-cos_t);
    return envmap_Le(e, mirror).y * F + envmap_Le(e, refracted).y * (1.0 - F) / (eta * eta);
}

/* Quadrature of the non-delta part plus the delta lobes' closed forms (green channel). */
static double reference(const GlossyBsdf *b, const Envmap *e, vec3 wo, DeltaRef delta, double param)
{
    const int nt = 600, np = 1200;
    double sum = 0.0, dt = MT_PI / nt, dp = 2.0 * MT_PI / np;
    for (int i = 0; i < nt; ++i) {
        double t = (i + 0.5) * dt;
        for (int j = 0; j < np; ++j) {
            vec3 wi = mt_dir(t, (j + 0.5) * dp);
            vec3 f = glossy_f(b, wo, wi);
            if (f.y > 0.0f) sum += envmap_Le(e, wi).y * f.y * fabs(wi.z) * sin(t) * dt * dp;
        }
    }
    if (delta != DELTA_BY_SAMPLING) return sum + delta_closed_form(delta, param, e, wo);
    /* delta lobes (at most one reflection and one transmission): a delta sample's f |cos|
     * is the lobe's weight, whatever the probability of choosing it */
    bool seen_r = false, seen_t = false;
    for (int k = 0; k < 2; ++k) {
        GlossySample s;
        float ul = k == 0 ? 0.0f : 0x1.fffffep-1f; /* first and last lobe of the choice */
        if (!glossy_sample(b, wo, ul, v2(0.5f, 0.5f), &s) || !s.delta) continue;
        if (s.transmission ? seen_t : seen_r) continue;
        if (s.transmission) seen_t = true;
        else seen_r = true;
        sum += envmap_Le(e, s.wi).y * s.f.y * fabs(s.wi.z);
    }
    return sum;
}

static double estimate(const GlossyBsdf *b, const Envmap *e, vec3 wo, int n, uint64_t seed, double *stderr_out)
{
    Pcg32 rng;
    pcg32_seed(&rng, seed, 11);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        double v = 0.0;
        /* light sampling (never hits a delta lobe: glossy_f is 0 there) */
        vec3 wl, Le;
        float pl;
        if (!glossy_is_delta(b) && envmap_sample(e, v2(pcg32_float(&rng), pcg32_float(&rng)), &wl, &Le, &pl)) {
            vec3 f = glossy_f(b, wo, wl);
            float pb = glossy_pdf(b, wo, wl);
            if (f.y > 0.0f) v += Le.y * f.y * fabs(wl.z) / pl * mis_power(pl, pb);
        } else {
            (void)pcg32_float(&rng), (void)pcg32_float(&rng);
        }
        /* BSDF sampling */
        GlossySample s;
        float ul = pcg32_float(&rng);
        vec2 u = v2(pcg32_float(&rng), pcg32_float(&rng));
        if (glossy_sample(b, wo, ul, u, &s)) {
            double w = s.delta ? 1.0 : mis_power(s.pdf, envmap_pdf(e, s.wi));
            v += envmap_Le(e, s.wi).y * s.f.y * fabs(s.wi.z) / s.pdf * w;
        }
        sum += v, sum2 += v * v;
    }
    double mean = sum / n;
    *stderr_out = sqrt(fmax(0.0, sum2 / n - mean * mean) / n);
    return mean;
}

int main(void)
{
    Diag err = {0};
    float *sky = make_sky(64);
    Envmap e;
    if (!envmap_init(&e, 64, 64, sky, 1.0f, &err)) return 1;
    struct {
        const char *name;
        GlossyBsdf b;
        float theta_deg;
        DeltaRef delta;
        double param; /* the closed form's reflectance or eta */
    } cases[] = {
        {"rough conductor", glossy_conductor((Microfacet){0.3f, 0.3f}, v3(0.2f, 0.9f, 1.1f), v3(3.6f, 2.6f, 2.3f)), 35,
         DELTA_BY_SAMPLING, 0},
        {"anisotropic conductor", glossy_conductor_reflectance((Microfacet){0.2f, 0.5f}, v3s(0.8f)), 60,
         DELTA_BY_SAMPLING, 0},
        {"smooth conductor", glossy_conductor_reflectance((Microfacet){0, 0}, v3s(0.8f)), 40, DELTA_CONDUCTOR, 0.8},
        {"rough coateddiffuse", glossy_coated_diffuse((Microfacet){0.3f, 0.3f}, v3(0.6f, 0.4f, 0.2f), 1.5f, -1), 30,
         DELTA_BY_SAMPLING, 0},
        {"smooth coateddiffuse", glossy_coated_diffuse((Microfacet){0, 0}, v3(0.6f, 0.4f, 0.2f), 1.5f, -1), 70,
         DELTA_BY_SAMPLING, 0},
        {"rough dielectric", glossy_dielectric((Microfacet){0.4f, 0.4f}, 1.5f), 45, DELTA_BY_SAMPLING, 0},
        {"rough dielectric from inside", glossy_dielectric((Microfacet){0.4f, 0.4f}, 1.5f), 140, DELTA_BY_SAMPLING, 0},
        {"smooth dielectric", glossy_dielectric((Microfacet){0, 0}, 1.5f), 50, DELTA_DIELECTRIC, 1.5},
    };
    for (int c = 0; c < 8; ++c) {
        vec3 wo = mt_dir(cases[c].theta_deg * MT_PI / 180.0, 0.3);
        double ref = reference(&cases[c].b, &e, wo, cases[c].delta, cases[c].param), se;
        double est = estimate(&cases[c].b, &e, wo, 40000, 100 + c, &se);
        bool ok = fabs(est - ref) <= 4.0 * se + 2e-3 * ref;
        fprintf(stderr, "%-30s reference %9.5f  MIS %9.5f +- %.5f %s\n", cases[c].name, ref, est, se, ok ? "" : "<-- FAIL");
        CHECK(ok);
        CHECK(ref > 0.0);
    }
    envmap_free(&e);
    free(sky);
    CHECK_DONE();
}
