/* Axis-aligned filter (AAF) parameters: filter widths and sample counts per pixel, one
 * function per paper equation (derivations in docs/algorithms.md).
 *
 *   soft shadows  AAF-shadow (seeds/001): slopes eq. 4, pixel band eq. 6, filter band eq. 8,
 *                 width eq. 13, samples eq. 21 (general form of the packing of Sec. 5)
 *   indirect      AAF-GI (seeds/002): filter band eq. 15, width eq. 16, BRDF band eq. 18,
 *                 samples eq. 21 with the importance factor gamma, 2% zmin clamp, 100 mu cap
 *   defocus       the (x, u) double wedge of the thin lens, derived like AAF-shadow with the
 *                 lens aperture in the role of the light (Mehta et al. 2014 is not in seeds/)
 *
 * Units: world lengths in scene units (suffix _world), screen lengths in pixels (_px),
 * angular frequencies in radians per unit of the corresponding coordinate.
 * Every function is total: non-finite or degenerate inputs give finite, documented results
 * (never NaN). mu > 0 is the consistency knob: width ~ 1/mu, so width -> 0 as mu -> inf. */
#ifndef WEDGE_RECON_AAF_PARAMS_H
#define WEDGE_RECON_AAF_PARAMS_H

#include <stdbool.h>

/* ---- soft shadows (AAF-shadow) ---- */

typedef struct {
    float k;      /* Gaussian energy spread factor, eq. 13 (paper: 3) */
    float alpha;  /* geometry band / pixel band, eq. 5 (paper: 1) */
    float mu;     /* filter-band scale, Sec. 5.2 (paper: 2) */
} AafShadowConfig;

AafShadowConfig aaf_shadow_config_default(void);

/* Eq. 4: s1 = d1/d2min - 1 (steepest slope, occluder nearest the light), s2 = d1/d2max - 1
 * (shallowest, occluder nearest the receiver). d1 light->receiver, d2 light->occluder. Slopes
 * are clamped to [0, AAF_SLOPE_MAX]: d2 -> 0 (occluder at the light) gives the maximum,
 * d2 >= d1 (occluder at or behind the receiver, rounding) gives 0. */
#define AAF_SLOPE_MAX 1.0e6f
void aaf_shadow_slopes(float d1_world, float d2min_world, float d2max_world, float *s1, float *s2);

/* Eq. 6: spatial band of the occlusion, alpha/(1 + s2) * Omega_pix, Omega_pix = 1/d (1/world),
 * d the world size of the pixel at the receiver. */
float aaf_shadow_omega_x_max(float alpha, float s2, float pixel_world);

/* Eq. 8 (critical, mu = 1): Omega_x^f = min(Omega_L/s2, Omega_x^max), Omega_L = 1/sigma. */
float aaf_shadow_omega_x_f(float sigma_light_world, float s2, float omega_x_max);

/* Eq. 13: beta = 1/(k mu Omega_x^f) = (1/(k mu)) max(sigma s2, 1/Omega_x^max), world units. */
float aaf_shadow_beta_world(float s2, float sigma_light_world, float pixel_world, const AafShadowConfig *c);

/* Eq. 21 in the general form of Sec. 5 (packing (a) of Fig. 4 with its min() clauses):
 *   Omega_x^* = mu Omega_x^f + Omega_x^max,  Omega_y^* = Omega_L + min(s1 mu Omega_x^f, Omega_y^max)
 *   n = (Omega_x^* d)^2 (Omega_y^* 2 sigma)^2    (A_p = d^2, A_l = (2 sigma)^2)
 * which equals the paper's closed form eq. 21 whenever Omega_L/s2 <= Omega_x^max and
 * s1 mu Omega_x^f <= Omega_y^max (eq. 7), and stays finite for s2 -> 0. Not clamped. */
float aaf_shadow_spp(float s1, float s2, float sigma_light_world, float pixel_world, const AafShadowConfig *c);

/* ---- indirect light (AAF-GI) ---- */

typedef struct {
    float alpha;            /* Omega_x^max = alpha/d, eq. 15 (paper: 0.3) */
    float mu;               /* eq. 15 and 21 (paper: 0.9 in their renders; we default to 2) */
    float zmin_clamp_frac;  /* zmin >= this * scene size, Sec. 5 (paper: 2%) */
    float spp_cap_per_mu;   /* n <= this * mu up to mu 2, Sec. 5 (paper: 100; we use 16,
                             * measured); faster beyond (aaf_indirect_spp_cap) */
} AafIndirectConfig;

AafIndirectConfig aaf_indirect_config_default(void);

/* Eq. 18: transfer-function band limits (radians per unit v): diffuse 2.8; Blinn-Phong
 * exponent m: 3.6 + 0.084 m. */
float aaf_indirect_omega_h_diffuse(void);
float aaf_indirect_omega_h_glossy(float blinn_phong_m);

/* Sec. 4.3 importance-sampling factor: diffuse 0.4; Blinn-Phong acos(c^(1/m))/(pi/2) with
 * c = cos(pi/4). */
float aaf_indirect_gamma_diffuse(void);
float aaf_indirect_gamma_glossy(float blinn_phong_m);

/* Sec. 5: zmin clamped to at least frac * scene size (zmin = 0 would mean no filter). */
float aaf_indirect_clamp_zmin(float zmin_world, float scene_size_world, float frac);

/* Eq. 15: Omega_x^r = mu min(Omega_h/zmin, alpha/d) (1/world). */
float aaf_indirect_omega_x_r(float zmin_world, float omega_h, float pixel_world, float alpha, float mu);

/* Eq. 16: beta = 2/Omega_x^r (the Fourier filter's standard deviation is Omega_x^r/2). */
float aaf_indirect_beta_world(float zmin_world, float omega_h, float pixel_world, const AafIndirectConfig *c);

/* The most samples a pixel gets (Sec. 5's cap, our form): spp_cap_per_mu * mu up to the default
 * mu = 2, then growing as mu^3, so that the samples under a capped pixel's filter (n beta^2,
 * beta ~ 1/mu by eq. 16) grow like mu and its filtered variance falls as a budget raises mu.
 * With the paper's linear cap they fell like 1/mu, and a larger --spp budget gave a larger
 * error (docs/algorithms.md, "Indirect light at large budgets"). */
float aaf_indirect_spp_cap(const AafIndirectConfig *c);

/* Eqs. 19-21 (general form): Omega_x^* = Omega_x^r + alpha/d, Omega_v^* = Omega_h + zmax Omega_x^r,
 * n = gamma (Omega_x^* d)^2 (Omega_v^*)^2, which is eq. 21 when Omega_h/zmin <= alpha/d.
 * Not clamped (see aaf_clamp_spp). */
float aaf_indirect_spp(float zmin_world, float zmax_world, float omega_h, float gamma,
                       float pixel_world, const AafIndirectConfig *c);

/* ---- defocus (thin lens, (x, u) light field) ---- */

typedef struct {
    float k;      /* as AAF-shadow eq. 13 (3) */
    float alpha;  /* pixel band fraction (1) */
    float mu;     /* (2) */
    /* No light at infinity: a primary ray that escapes sees zero radiance, so a pixel whose
     * pass-1 rays all escaped has an empty spectrum and keeps its pass-1 samples. */
    bool black_background;
} AafDefocusConfig;

AafDefocusConfig aaf_defocus_config_default(void);

/* The lens aperture, in lens coordinates u on the unit disk, is modelled as a Gaussian with the
 * disk's per-axis standard deviation 1/2, so Omega_u = 2 and its effective width 2 sigma_u = 1. */
#define AAF_LENS_SIGMA_U 0.5f

/* Smallest and largest |slope| of a signed slope range [s_min, s_max] (CoC radius in pixels per
 * unit lens coordinate, negative in front of the focal plane). A range that straddles 0 has
 * smallest |slope| 0: that pixel cannot be filtered. */
void aaf_defocus_abs_slopes(float s_min_px, float s_max_px, float *abs_min_px, float *abs_max_px);

/* Filter width in pixels: (1/(k mu)) max(sigma_u |s|min, 1/alpha), the analogue of eq. 13. */
float aaf_defocus_beta_px(float s_min_px, float s_max_px, const AafDefocusConfig *c);

/* Samples per pixel, the analogue of eq. 21 in its general form:
 *   Omega_x^f = mu min(Omega_u/|s|min, alpha), Omega_x^* = Omega_x^f + alpha,
 *   Omega_u^* = Omega_u + min(|s|max Omega_x^f, |s|max alpha), n = (Omega_x^*)^2 (Omega_u^* 2 sigma_u)^2. */
float aaf_defocus_spp(float s_min_px, float s_max_px, const AafDefocusConfig *c);

/* ---- common ---- */

/* Rounds a sample count up and clamps it to [n_min, n_max]; NaN -> n_max (be safe), and
 * n_max itself is capped at AAF_SPP_HARD_MAX. */
#define AAF_SPP_HARD_MAX 65536
int aaf_clamp_spp(float n, int n_min, float n_max);

#endif
