/* Axis-aligned filter parameters (see aaf_params.h and docs/algorithms.md). */
#include "recon/aaf/aaf_params.h"

#include <float.h>
#include <math.h>

/* Smallest length we divide by: far below any pixel or distance a scene has, large enough
 * that 1/x stays finite in float. */
#define TINY_WORLD 1.0e-30f

static float finite_or(float x, float fallback) { return isfinite(x) ? x : fallback; }
/* A length we may divide by: NaN, 0 and negatives become TINY_WORLD, +inf becomes HUGE_WORLD. */
#define HUGE_WORLD 1.0e30f
static float positive_or_tiny(float x)
{
    if (!(x > TINY_WORLD)) return TINY_WORLD;
    return x < HUGE_WORLD ? x : HUGE_WORLD;
}
/* mu must be > 0; mu = +inf is allowed and means "no filtering". */
static float sane_mu(float mu) { return (mu > 1.0e-6f) ? mu : 1.0e-6f; }

/* ---------------------------------------------------------------- soft shadows */

AafShadowConfig aaf_shadow_config_default(void)
{
    AafShadowConfig c = {3.0f, 1.0f, 2.0f}; /* AAF-shadow Sec. 6: k = 3, alpha = 1, mu = 2 */
    return c;
}

/* AAF-shadow eq. 4. */
static float slope_from_distances(float d1_world, float d2_world)
{
    if (!(d2_world > 0.0f)) return AAF_SLOPE_MAX; /* occluder at the light (or NaN): steepest */
    float s = d1_world / d2_world - 1.0f;
    if (!(s > 0.0f)) return 0.0f;                 /* includes NaN from d1 = inf, d2 = inf */
    return s < AAF_SLOPE_MAX ? s : AAF_SLOPE_MAX;
}

void aaf_shadow_slopes(float d1_world, float d2min_world, float d2max_world, float *s1, float *s2)
{
    *s1 = slope_from_distances(d1_world, d2min_world);
    *s2 = slope_from_distances(d1_world, d2max_world);
    if (*s2 > *s1) { /* d2min > d2max given: keep s1 the steepest */
        float t = *s1;
        *s1 = *s2;
        *s2 = t;
    }
}

/* AAF-shadow eq. 6: Omega_x^max = alpha (d2max/d1) Omega_pix = alpha/(1 + s2) / d. */
float aaf_shadow_omega_x_max(float alpha, float s2, float pixel_world)
{
    return alpha / ((1.0f + s2) * positive_or_tiny(pixel_world));
}

/* AAF-shadow eq. 8: the light band Omega_L = 1/sigma, carried along the shallowest wedge line
 * Omega_y = s2 Omega_x, ends at Omega_x = Omega_L/s2; never beyond the occlusion band. */
float aaf_shadow_omega_x_f(float sigma_light_world, float s2, float omega_x_max)
{
    if (!(s2 > 0.0f)) return omega_x_max; /* occluder on the receiver: only the pixel band */
    float induced = 1.0f / (positive_or_tiny(sigma_light_world) * s2);
    return fminf(finite_or(induced, FLT_MAX), omega_x_max);
}

/* AAF-shadow eq. 13 (footnote 4: the width is 1/(k Omega_x^f), not Omega_x^f/k). */
float aaf_shadow_beta_world(float s2, float sigma_light_world, float pixel_world, const AafShadowConfig *c)
{
    float omega_x_max = aaf_shadow_omega_x_max(c->alpha, s2, pixel_world);
    float omega_x_f = aaf_shadow_omega_x_f(sigma_light_world, s2, omega_x_max);
    float beta = 1.0f / (c->k * sane_mu(c->mu) * omega_x_f);
    return finite_or(beta, 0.0f);
}

/* AAF-shadow eqs. 7, 14 (packing (a)), 15 and 21. */
float aaf_shadow_spp(float s1, float s2, float sigma_light_world, float pixel_world, const AafShadowConfig *c)
{
    float d = positive_or_tiny(pixel_world);
    float sigma = positive_or_tiny(sigma_light_world);
    float mu = sane_mu(c->mu);
    float omega_pix = 1.0f / d;
    float omega_l = 1.0f / sigma;
    float omega_x_max = aaf_shadow_omega_x_max(c->alpha, s2, d);
    float omega_y_max = c->alpha * (s1 / (1.0f + s1)) * omega_pix; /* eq. 7: 1 - d2min/d1 */
    float omega_x_f = mu * aaf_shadow_omega_x_f(sigma, s2, omega_x_max);
    float omega_x_star = omega_x_f + omega_x_max;
    float omega_y_star = omega_l + fminf(s1 * omega_x_f, omega_y_max);
    /* Per-pixel count = (Omega_x^*)^2 A_p (Omega_y^*)^2 A_l with A_p = d^2, A_l = (2 sigma)^2. */
    float nx = omega_x_star * d;
    float ny = omega_y_star * 2.0f * sigma;
    float n = nx * nx * ny * ny;
    return isnan(n) ? FLT_MAX : n;
}

/* ---------------------------------------------------------------- indirect light */

AafIndirectConfig aaf_indirect_config_default(void)
{
    /* AAF-GI Sec. 5: alpha 0.3, the 2% zmin clamp. Deviations, measured (docs/algorithms.md,
     * "Indirect light: what limited the gain"): the cap is 16 mu samples per pixel instead of
     * 100 mu, and mu defaults to 2 instead of the paper's 0.9. */
    AafIndirectConfig c = {0.3f, 2.0f, 0.02f, 16.0f};
    return c;
}

float aaf_indirect_omega_h_diffuse(void) { return 2.8f; } /* AAF-GI eq. 18 */

float aaf_indirect_omega_h_glossy(float m) /* AAF-GI eq. 18 */
{
    if (!(m > 0.0f)) m = 0.0f;
    return 3.6f + 0.084f * fminf(m, 1.0e6f);
}

float aaf_indirect_gamma_diffuse(void) { return 0.4f; } /* AAF-GI Sec. 4.3 */

float aaf_indirect_gamma_glossy(float m) /* AAF-GI Sec. 4.3 */
{
    if (!(m > 0.0f)) return 1.0f; /* no lobe: no importance-sampling gain assumed */
    /* 80% of a Blinn-Phong lobe's energy within acos(c^(1/m)) of its axis, c = cos(pi/4). */
    double c = sqrt(0.5);
    double theta = acos(pow(c, 1.0 / (double)m));
    double g = theta / (M_PI / 2.0);
    return (float)(g > 1.0 ? 1.0 : g);
}

float aaf_indirect_clamp_zmin(float zmin_world, float scene_size_world, float frac)
{
    float floor_world = finite_or(scene_size_world * frac, 0.0f);
    if (!(zmin_world >= floor_world)) zmin_world = floor_world; /* also NaN */
    return positive_or_tiny(zmin_world);
}

/* AAF-GI eq. 15. */
float aaf_indirect_omega_x_r(float zmin_world, float omega_h, float pixel_world, float alpha, float mu)
{
    float by_reflector = omega_h / positive_or_tiny(zmin_world); /* zmin = inf -> ~0 */
    float by_pixel = alpha / positive_or_tiny(pixel_world);
    return sane_mu(mu) * fminf(finite_or(by_reflector, FLT_MAX), by_pixel);
}

/* AAF-GI eq. 16. An infinitely distant reflector (omega 0) would allow an infinite width; we
 * return +inf's stand-in FLT_MAX and let the filter's radius cap bound it. */
float aaf_indirect_beta_world(float zmin_world, float omega_h, float pixel_world, const AafIndirectConfig *c)
{
    float omega_r = aaf_indirect_omega_x_r(zmin_world, omega_h, pixel_world, c->alpha, c->mu);
    if (!(omega_r > 0.0f)) return FLT_MAX;
    return finite_or(2.0f / omega_r, FLT_MAX);
}

float aaf_indirect_spp_cap(const AafIndirectConfig *c)
{
    float mu = sane_mu(c->mu), grow = mu > 2.0f ? 0.5f * mu : 1.0f;
    float cap = c->spp_cap_per_mu * mu * grow * grow;
    return isfinite(cap) ? cap : FLT_MAX;
}

/* AAF-GI eqs. 19-21. */
float aaf_indirect_spp(float zmin_world, float zmax_world, float omega_h, float gamma,
                       float pixel_world, const AafIndirectConfig *c)
{
    float d = positive_or_tiny(pixel_world);
    if (!(zmax_world >= zmin_world)) zmax_world = zmin_world;
    float omega_r = aaf_indirect_omega_x_r(zmin_world, omega_h, d, c->alpha, c->mu);
    float omega_x_star = omega_r + c->alpha / d;
    float omega_v_star = omega_h + finite_or(zmax_world * omega_r, FLT_MAX);
    float nx = omega_x_star * d;
    float n = gamma * nx * nx * omega_v_star * omega_v_star;
    return (isnan(n) || n > FLT_MAX) ? FLT_MAX : n;
}

/* ---------------------------------------------------------------- defocus */

AafDefocusConfig aaf_defocus_config_default(void)
{
    /* k, alpha as AAF-shadow; mu 1 (measured, docs/algorithms.md); the background is assumed lit
     * until the caller knows the scene has no light at infinity */
    AafDefocusConfig c = {3.0f, 1.0f, 1.0f, false};
    return c;
}

void aaf_defocus_abs_slopes(float s_min_px, float s_max_px, float *abs_min_px, float *abs_max_px)
{
    s_min_px = finite_or(s_min_px, 0.0f);
    s_max_px = finite_or(s_max_px, 0.0f);
    if (s_min_px > s_max_px) {
        float t = s_min_px;
        s_min_px = s_max_px;
        s_max_px = t;
    }
    float a = fabsf(s_min_px), b = fabsf(s_max_px);
    *abs_max_px = fmaxf(a, b);
    /* Straddling the focal plane: some line of the wedge is vertical (slope 0). */
    *abs_min_px = (s_min_px <= 0.0f && s_max_px >= 0.0f) ? 0.0f : fminf(a, b);
}

/* Critical (mu = 1) spatial band of the axis-aligned (x, u) filter, radians per pixel. */
static float defocus_omega_x_f0(float abs_min_px, float alpha)
{
    float omega_u = 1.0f / AAF_LENS_SIGMA_U;
    float induced = abs_min_px > 0.0f ? omega_u / abs_min_px : FLT_MAX;
    return fminf(induced, alpha);
}

float aaf_defocus_beta_px(float s_min_px, float s_max_px, const AafDefocusConfig *c)
{
    float amin, amax;
    aaf_defocus_abs_slopes(s_min_px, s_max_px, &amin, &amax);
    float beta = 1.0f / (c->k * sane_mu(c->mu) * defocus_omega_x_f0(amin, c->alpha));
    return finite_or(beta, 0.0f);
}

float aaf_defocus_spp(float s_min_px, float s_max_px, const AafDefocusConfig *c)
{
    float amin, amax;
    aaf_defocus_abs_slopes(s_min_px, s_max_px, &amin, &amax);
    float omega_u = 1.0f / AAF_LENS_SIGMA_U;
    float omega_x_f = sane_mu(c->mu) * defocus_omega_x_f0(amin, c->alpha);
    float omega_x_star = omega_x_f + c->alpha; /* pixel spacing 1: A_p = 1 px^2 */
    float omega_u_star = omega_u + fminf(amax * omega_x_f, amax * c->alpha);
    float nu = omega_u_star * 2.0f * AAF_LENS_SIGMA_U;
    float n = omega_x_star * omega_x_star * nu * nu;
    return (isnan(n) || n > FLT_MAX) ? FLT_MAX : n;
}

/* ---------------------------------------------------------------- common */

int aaf_clamp_spp(float n, int n_min, float n_max)
{
    if (!(n_max <= (float)AAF_SPP_HARD_MAX)) n_max = (float)AAF_SPP_HARD_MAX; /* also NaN */
    if (n_max < (float)n_min) n_max = (float)n_min;
    if (isnan(n) || n > n_max) n = n_max;
    if (n < (float)n_min) n = (float)n_min;
    return (int)ceilf(n);
}
