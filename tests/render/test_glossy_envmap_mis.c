/* The glossy BSDFs and the environment map used together the way the integrator will:
 * reflected radiance Lo(wo) = int Le(wi) f(wo, wi) |cos_i| dwi estimated by multiple
 * importance sampling (light sample + BSDF sample, power heuristic, delta lobes taken
 * without MIS) must match a brute-force quadrature of the same integral (delta lobes added
 * in closed form). This checks that GlossySample's f / pdf / delta conventions and
 * envmap_sample / envmap_pdf combine into an unbiased estimator. */
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

/* Quadrature of the non-delta part plus the delta lobes' closed forms (green channel). */
static double reference(const GlossyBsdf *b, const Envmap *e, vec3 wo)
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
    } cases[] = {
        {"rough conductor", glossy_conductor((Microfacet){0.3f, 0.3f}, v3(0.2f, 0.9f, 1.1f), v3(3.6f, 2.6f, 2.3f)), 35},
        {"anisotropic conductor", glossy_conductor_reflectance((Microfacet){0.2f, 0.5f}, v3s(0.8f)), 60},
        {"smooth conductor", glossy_conductor_reflectance((Microfacet){0, 0}, v3s(0.8f)), 40},
        {"rough coateddiffuse", glossy_coated_diffuse((Microfacet){0.3f, 0.3f}, v3(0.6f, 0.4f, 0.2f), 1.5f, -1), 30},
        {"smooth coateddiffuse", glossy_coated_diffuse((Microfacet){0, 0}, v3(0.6f, 0.4f, 0.2f), 1.5f, -1), 70},
        {"rough dielectric", glossy_dielectric((Microfacet){0.4f, 0.4f}, 1.5f), 45},
        {"rough dielectric from inside", glossy_dielectric((Microfacet){0.4f, 0.4f}, 1.5f), 140},
        {"smooth dielectric", glossy_dielectric((Microfacet){0, 0}, 1.5f), 50},
    };
    for (int c = 0; c < 8; ++c) {
        vec3 wo = mt_dir(cases[c].theta_deg * MT_PI / 180.0, 0.3);
        double ref = reference(&cases[c].b, &e, wo), se;
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
