/* The indirect-light side of MAAF (seeds/003 Sec. 3 "diffuse global illumination", Sec. 6: the
 * 4D (x, v) bounce case): where a bounce direction sits on the v-plane, its direction-factors
 * for eq. 20, and each pixel's x-filter from its reflector heights. docs/algorithms.md 9.12.
 *
 * Coordinates (per receiver pixel a tangent frame t1, t2, n, fixed by its first sample):
 *   x   the receiver point along t1, t2 (world units)
 *   v   the bounce direction d's point on the plane at unit height along n:
 *       v_a = (d . t_a) / (d . n) (dimensionless, "v units"; FSF's v-plane, AAF-GI's v)
 *   h   a reflector hit at distance t along d is h = t (d . n) above the tangent plane
 * Seen from x, direction v reaches the reflector at x + h v, so the incident light is a
 * function of x + s v with s = h > 0 (world units per v unit): the shadow convention of 9.2
 * (a function of x + s y), so the design and the image pass are the shadow's, with y -> v,
 * Omega_y_max -> Omega_v_max = kappa 2.8 (AAF-GI's diffuse transfer band, seeds/003 Sec. 3),
 * and the wedge [h_min, h_max].
 *
 * The direction-factor of component (p, q) is the component integrated over the direction
 * domain against the transfer, over the samples' density (both the cosine lobe
 * T(v) = (1 + |v|^2)^-2 / pi per unit v area, since diffuse bounces are cosine-sampled):
 *     c_pq(v_k) = int exp(j C.(v - v_k)) g(v1 - v1_k; sv) g(v2 - v2_k; sv) T(v) dv / T(v_k)
 * with C = (C^p, C^q), C^q = Omega_v_max 2q / (2N - 1), sv = Omega_v_max / (2N - 1). The sum
 * over samples of f_k c_pq(v_k) then converges to the transfer-weighted integral of the
 * reconstructed light field (docs/algorithms.md 9.12 derives it), as the light's y-factor
 * (9.6) and the lens factor (9.8) do for a uniform density. T couples v1 and v2, so (as for
 * the disk lens) each component has its own 2D table. */
#ifndef WEDGE_RECON_MAAF_INDIRECT_H
#define WEDGE_RECON_MAAF_INDIRECT_H

#include <stdbool.h>

#include "recon/maaf/maaf_defocus.h" /* MaafLens: a table of complex factors per component */

/* The diffuse transfer's band in v (AAF-GI eq. 18, seeds/003 Sec. 3: Omega_y_max ~ 2.8). */
#define MAAF_INDIRECT_OMEGA_V 2.8f
/* The direction table covers v in [-V, V]^2 (the lens table's layout over [-1, 1]^2, scaled):
 * a cosine-sampled direction lies outside it with probability under 2% (1/65 beyond |v| = 8
 * radially), where the factor has flattened towards its far value. */
#define MAAF_INDIRECT_V_HALF 8.0f
/* The indirect knob's default (--mu; docs/algorithms.md 9.12 has the measurement). */
#define MAAF_INDIRECT_KAPPA_DEFAULT 3.0f
/* The method gives every indirect sample the factors' expectation (maaf_direction_mean: the
 * filter is then the design's x-kernel alone): on the indirect and combined bench scenes the
 * directional factors of the table added bias (docs/algorithms.md 9.12, "No directions at
 * all"). The table and maaf_direction_accumulate below are that measured design, kept with
 * their tests (the table against brute force, the wedge's sign). */
/* The filter at a contact line, where the nearest reflector's height h -> 0 and the design's
 * width with it: AAF-GI eq. 15's pixel term bounds the central band, Omega_x <= alpha(n) / d
 * (d the pixel's footprint, world units), so the filter's std there is 1/alpha(n) pixels, and
 * alpha grows as the fourth root of the pixel's sample count n: the width at which the filter's
 * variance reduction brings n samples' noise down to the bias of a filter across the light's
 * kink at the contact (docs/algorithms.md 9.26). AAF-GI's alpha = 0.3 (seeds/002 Sec. 4.1) at
 * its first pass's 16 rays per pixel (Sec. 5). */
#define MAAF_INDIRECT_CONTACT_ALPHA 0.3f
#define MAAF_INDIRECT_CONTACT_BASE_SPP 16.0f

/* alpha(n) = 0.3 (n / 16)^(1/4) (dimensionless; n below 1 counts as 1). */
float maaf_indirect_contact_alpha(float spp);
/* A pixel's wedge [*h_min, *h_max] (world units) from its window's mean reflector heights:
 * h_min at least the height whose central band (maaf_design_2d: Omega_x = Omega_v_max /
 * ((2N - 1) h)) reaches alpha(spp) / pixel_world, h_max at least h_min. */
void maaf_indirect_heights(float zmin_world, float zmax_world, float omega_v_max, int pairs, float pixel_world, float spp,
                           float *h_min, float *h_max);

/* Fills t (MaafLens layout, coordinates v / MAAF_INDIRECT_V_HALF) with c_pq for the knob kappa
 * (Omega_v_max = kappa MAAF_INDIRECT_OMEGA_V). False when out of memory (t->table NULL). */
bool maaf_direction_design(float kappa, int pairs, MaafLens *t);
/* The design without the table (t->table NULL): pairs, band and the expectations
 * maaf_direction_mean, all that maaf_direction_accumulate reads for samples without a
 * direction. */
void maaf_direction_means(float kappa, int pairs, MaafLens *t);

/* c_pq (component c, half-set order) at v, interpolated from the table. */
void maaf_direction_factor(const MaafLens *t, int c, const float v[2], float out[2]);

/* The factor's expectation over cosine-distributed directions, int of the component over the
 * whole plane: exp(-(C^p^2 + C^q^2) / (2 sv^2)) = exp(-2 (p^2 + q^2)), real. For samples
 * whose direction is unknown (traced without ray geometry) or below the pixel's tangent plane. */
float maaf_direction_mean(int pairs, int c);

/* Adds f4 (r, g, b, 1) of a sample with bounce direction d (unit, world) in the pixel frame
 * (t1, t2, n) to the pixel's sums (8 floats per component); d NULL or not above the plane: the
 * mean factor. */
void maaf_direction_accumulate(const MaafLens *t, const float t1[3], const float t2[3], const float n[3],
                               const float *d, const float f4[4], float *ysum);

/* v of direction d in the frame (false when d is not above the tangent plane). */
bool maaf_direction_coord(const float t1[3], const float t2[3], const float n[3], const float d[3], float v[2]);

#endif
