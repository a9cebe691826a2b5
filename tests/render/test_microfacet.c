/* Trowbridge-Reitz distribution: normalisation of D, the Smith relation between D and
 * Lambda (visible normals integrate to 1), visible-normal sampling against its density
 * (chi-square), roughness remapping and the Blinn-Phong correspondence. */
#include "check.h"
#include "materials_test_util.h"
#include "render/microfacet.h"

/* Integral over the hemisphere of D(wm) cos(theta_m), by a fine (theta, phi) midpoint grid
 * (fine enough for alpha >= 0.1: the peak is ~0.1 rad wide, the grid step 4e-4 rad). */
static double integrate_projected_D(Microfacet m)
{
    const int nt = 4000, np = 256;
    double sum = 0.0, dt = 0.5 * MT_PI / nt, dp = 2.0 * MT_PI / np;
    for (int i = 0; i < nt; ++i) {
        double t = (i + 0.5) * dt;
        for (int j = 0; j < np; ++j) sum += microfacet_D(m, mt_dir(t, (j + 0.5) * dp)) * cos(t) * sin(t);
    }
    return sum * dt * dp;
}

static double integrate_visible(Microfacet m, vec3 w)
{
    const int nt = 2000, np = 256;
    double sum = 0.0, dt = 0.5 * MT_PI / nt, dp = 2.0 * MT_PI / np;
    for (int i = 0; i < nt; ++i) {
        double t = (i + 0.5) * dt;
        for (int j = 0; j < np; ++j) sum += microfacet_D_visible(m, w, mt_dir(t, (j + 0.5) * dp)) * sin(t);
    }
    return sum * dt * dp;
}

typedef struct {
    Microfacet m;
    vec3 w;
} VisCtx;
static bool vis_sample(void *ctx, Pcg32 *rng, vec3 *out)
{
    VisCtx *c = ctx;
    vec2 u = v2(pcg32_float(rng), pcg32_float(rng));
    *out = microfacet_sample_wm(c->m, c->w, u);
    return true;
}
static double vis_pdf(void *ctx, vec3 wm)
{
    VisCtx *c = ctx;
    return microfacet_D_visible(c->m, c->w, wm);
}

static vec3 dir_from_angles(float theta_deg, float phi_deg)
{
    double t = theta_deg * MT_PI / 180.0, p = phi_deg * MT_PI / 180.0;
    return mt_dir(t, p);
}

int main(void)
{
    /* Remapping: pbrt-v4 RoughnessToAlpha is sqrt. */
    CHECK_NEAR(microfacet_roughness_to_alpha(0.25f), 0.5f, 1e-7);
    Microfacet r = microfacet_make(0.04f, 0.09f, true);
    CHECK_NEAR(r.alpha_x, 0.2f, 1e-7);
    CHECK_NEAR(r.alpha_y, 0.3f, 1e-7);
    r = microfacet_make(0.04f, 0.09f, false);
    CHECK_NEAR(r.alpha_x, 0.04f, 1e-9);
    CHECK(microfacet_is_smooth(microfacet_make(0.0f, 0.0f, true)));
    CHECK(microfacet_is_smooth(microfacet_make(-1.0f, NAN, true)));
    CHECK(!microfacet_is_smooth(microfacet_make(1e-4f, 1e-4f, true))); /* alpha 0.01 */
    /* one smooth axis of a rough lobe: alpha 1e-4 there (pbrt-v4), not 0 */
    r = microfacet_make(0.0f, 0.09f, true);
    CHECK(r.alpha_x == MICROFACET_ALPHA_MIN && r.alpha_y == 0.3f);
    r = microfacet_make(0.09f, -1.0f, true);
    CHECK(r.alpha_x == 0.3f && r.alpha_y == MICROFACET_ALPHA_MIN);
    CHECK(microfacet_D(r, v3(0.0f, 0.0f, 1.0f)) > 0.0f);

    /* D is normalised: integral of D(wm) cos(theta_m) = 1 (isotropic and anisotropic). */
    Microfacet ms[] = {{0.1f, 0.1f}, {0.5f, 0.5f}, {1.0f, 1.0f}, {0.15f, 0.6f}};
    for (int i = 0; i < 4; ++i) CHECK_NEAR(integrate_projected_D(ms[i]), 1.0, 2e-3);

    /* Smith: the visible-normal density integrates to 1 for any w (this ties Lambda to D;
     * a wrong Lambda breaks it at oblique w). */
    float thetas[] = {0.0f, 30.0f, 60.0f, 80.0f, 88.0f};
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 5; ++k) {
            vec3 w = dir_from_angles(thetas[k], 37.0f);
            double v = integrate_visible(ms[i], w);
            if (fabs(v - 1.0) > 3e-3) fprintf(stderr, "alpha (%g, %g) theta %g: %g\n", ms[i].alpha_x, ms[i].alpha_y, thetas[k], v);
            CHECK_NEAR(v, 1.0, 3e-3);
        }

    /* G1 closed form at normal incidence is 1; G <= G1 products; G at grazing is 0. */
    CHECK_NEAR(microfacet_G1(ms[1], v3(0, 0, 1)), 1.0, 1e-7);
    CHECK_NEAR(microfacet_G1(ms[1], v3(1, 0, 0)), 0.0, 1e-7);
    {
        vec3 a = dir_from_angles(50, 10), b = dir_from_angles(70, 200);
        float g = microfacet_G(ms[1], a, b);
        CHECK(g <= microfacet_G1(ms[1], a) + 1e-7f && g <= microfacet_G1(ms[1], b) + 1e-7f);
        CHECK(g >= microfacet_G1(ms[1], a) * microfacet_G1(ms[1], b) - 1e-7f);
    }

    /* Sampling matches D_visible (chi-square) for several w, including from below. */
    struct {
        Microfacet m;
        float theta_deg;
    } cases[] = {{{0.2f, 0.2f}, 0.0f}, {{0.5f, 0.5f}, 45.0f}, {{0.8f, 0.8f}, 75.0f}, {{0.2f, 0.6f}, 60.0f}, {{1.0f, 1.0f}, 89.0f}};
    for (int i = 0; i < 5; ++i) {
        VisCtx c = {cases[i].m, dir_from_angles(cases[i].theta_deg, 20.0f)};
        MtChi2 x = mt_chi2(vis_sample, vis_pdf, &c, 300000, 40, 80, 6, 1234 + i);
        char name[96];
        snprintf(name, sizeof name, "vndf alpha (%.1f, %.1f) theta %.0f", cases[i].m.alpha_x, cases[i].m.alpha_y,
                 cases[i].theta_deg);
        CHECK(mt_chi2_ok(name, x));
    }

    /* Blinn-Phong correspondence m = 2/alpha^2 - 2: the normalised Phong distribution
     * (m + 2)/(2 pi) cos^m has the same peak density as GGX, 1 / (pi alpha^2). */
    float alphas[] = {0.05f, 0.1f, 0.3f, 0.7f};
    for (int i = 0; i < 4; ++i) {
        Microfacet m = {alphas[i], alphas[i]};
        float e = microfacet_phong_exponent(m);
        double phong_peak = (e + 2.0) / (2.0 * MT_PI);
        CHECK_NEAR(phong_peak / microfacet_D(m, v3(0, 0, 1)), 1.0, 1e-4);
    }
    CHECK_NEAR(microfacet_phong_exponent((Microfacet){1.0f, 1.0f}), 0.0, 1e-6);
    CHECK_NEAR(microfacet_phong_exponent((Microfacet){2.0f, 2.0f}), 0.0, 1e-6); /* clamped */
    CHECK_NEAR(microfacet_phong_exponent((Microfacet){0.0f, 0.0f}), MICROFACET_PHONG_MAX, 0);
    CHECK(microfacet_phong_exponent((Microfacet){0.1f, 0.1f}) > microfacet_phong_exponent((Microfacet){0.2f, 0.2f}));

    /* No NaN/Inf at degenerate inputs. */
    CHECK(isfinite(microfacet_D((Microfacet){1e-3f, 1e-3f}, v3(0, 0, 1))));
    vec3 wm = microfacet_sample_wm(ms[1], v3(1, 0, 0), v2(0.999f, 0.5f));
    CHECK(isfinite(wm.x) && isfinite(wm.y) && isfinite(wm.z) && wm.z >= 0.0f);
    CHECK_DONE();
}
