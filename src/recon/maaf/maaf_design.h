/* Multiple axis-aligned filters (MAAF, seeds/003) in one 2D subspace (Omega_x, Omega_y): the
 * Fourier design of Sec. 4 (eqs. 6-10) and its primal form (eqs. 11-13). Derivation with units
 * in docs/algorithms.md, "MAAF".
 *
 * The spectrum to cover is the double wedge between the lines Omega_y = s Omega_x for s in
 * [s_min, s_max] (s > 0), clipped at |Omega_y| <= Omega_y_max. Its height 2 Omega_y_max is cut
 * into 2N - 1 equal bands; band p (p = -(N-1) .. N-1) gets one axis-aligned Gaussian centred at
 * (C_x^p, C_y^p) with per-axis standard deviations (sigma_x^p, sigma_y^p) equal to the half
 * extents of the box that bounds the wedge inside the band, and a weight mu_p. Band -p mirrors
 * band p through the origin, so only p >= 0 is stored.
 *
 * Units: x is a receiver coordinate (world units along one axis of the light's plane), y the
 * coordinate on the light along the same axis (world units); Omega_x, Omega_y are angular
 * frequencies (radians per world unit). The slopes s are dimensionless.
 *
 * Conventions (the ones the sign of the phase depends on):
 *   Fourier transform  F(Omega) = integral f(x) exp(-j Omega x) dx
 *   Fourier Gaussian   G(Omega; sigma) = exp(-Omega^2 / (2 sigma^2))     (peak 1)
 *   primal Gaussian    g(x; sigma) = (sigma / sqrt(2 pi)) exp(-sigma^2 x^2 / 2)
 *                      = the inverse transform of G(.; sigma): primal standard deviation
 *                      1 / sigma (eq. 12's remark: widths are reciprocal)
 *   primal kernel      w(x, y) = sum_p mu_p exp(j (C_x^p x + C_y^p y)) g(x; sigma_x^p) g(y; sigma_y^p)
 *                      = mu_0 g g + sum_{p >= 1} 2 mu_p cos(C_x^p x + C_y^p y) g g   (eq. 12)
 * whose Fourier transform is exactly W(Omega_x, Omega_y) = sum_p mu_p G G (eq. 9). */
#ifndef WEDGE_RECON_MAAF_DESIGN_H
#define WEDGE_RECON_MAAF_DESIGN_H

#include <stdbool.h>

/* N pairs (the central filter counts as one), 2N - 1 filters per 2D subspace. */
#define MAAF_PAIRS_MAX 5
/* The default N per subspace (docs/algorithms.md 9.22): the light's axes 2, the lens's and the
 * bounce's 3. With fewer bands the light's central band covers the part of the wedge that the
 * integral over the light keeps, so the offset bands' biased light factors carry less of it:
 * half the bias at 20-25% more variance on the soft-shadow scenes, the lens the other way. */
#define MAAF_PAIRS_LIGHT_DEFAULT 2
#define MAAF_PAIRS_LENS_DEFAULT 3
#define MAAF_PAIRS_BOUNCE_DEFAULT 3

/* N per 2D subspace of a frame: the light's axes (soft shadows), the lens's (defocus), the
 * bounce direction's (indirect light). */
typedef struct {
    int light, lens, bounce;
} MaafPairs;

/* The counts from the method's options: all > 0 (--maaf-pairs) sets every subspace, then
 * light, lens, bounce > 0 set their own; the rest take the defaults. Each clamped to
 * [1, MAAF_PAIRS_MAX]. */
MaafPairs maaf_pairs_choose(int all, int light, int lens, int bounce);

/* One component p >= 0 (its mirror -p has centre (-C_x, -C_y), the same widths and weight). */
typedef struct {
    float cx, cy;     /* centre, radians per world unit (eqs. 6, 7) */
    float sx, sy;     /* Fourier standard deviations = half box extents (eq. 8) */
    float weight;     /* mu_p (eq. 10), 1 for the central filter */
} MaafComponent;

typedef struct {
    int pairs;                          /* N */
    float s_min, s_max, omega_y_max;    /* what it was designed for (after clamping) */
    MaafComponent c[MAAF_PAIRS_MAX];    /* p = 0 .. N-1 */
} MaafDesign2D;

/* Slopes are clamped to [MAAF_SLOPE_MIN, MAAF_SLOPE_MAX] and swapped if s_min > s_max; pairs to
 * [1, MAAF_PAIRS_MAX]. False (and a zero design) when omega_y_max is not finite and > 0. */
#define MAAF_SLOPE_MIN 1.0e-4f
#define MAAF_SLOPE_MAX 1.0e4f
bool maaf_design_2d(float s_min, float s_max, float omega_y_max, int pairs, MaafDesign2D *out);
/* Slopes of either sign (defocus: docs/algorithms.md 9.8): a range of negative slopes is the
 * positive design of [-s_max, -s_min] mirrored through the Omega_y axis (every C_x negated; its
 * s_min, s_max are stored as given). False (and a zero design) when the range straddles 0, whose
 * wedge holds the whole Omega_x axis, or omega_y_max is not usable. */
bool maaf_design_2d_signed(float s_min, float s_max, float omega_y_max, int pairs, MaafDesign2D *out);

/* Eq. 9: W(Omega_x, Omega_y), all 2N - 1 components. */
double maaf_fourier_2d(const MaafDesign2D *d, double omega_x, double omega_y);

/* Eq. 12: w(x, y) evaluated directly, sum over p = -(N-1) .. N-1 folded into cosines. */
double maaf_primal_2d_direct(const MaafDesign2D *d, double x, double y);

/* Eq. 13: the same kernel as a sum of 2N - 1 separable products a_t(x) b_t(y): the central
 * filter, and for each pair cos(C_x x) cos(C_y y) minus sin(C_x x) sin(C_y y). Term t of
 * maaf_separable_terms: a = x-factor (weights, normalisation and the 2 of the pair included),
 * b = y-factor. */
int maaf_separable_terms(const MaafDesign2D *d, double x, double y, double *a, double *b);
double maaf_primal_2d_separable(const MaafDesign2D *d, double x, double y);

/* Box coverage (Sec. 5, eqs. 15-18 re-derived): the wedge's area over the summed areas of the
 * 2N - 1 boxes 2 sigma_x x 2 sigma_y,
 *   (2N-1)^2 (1/s_min - 1/s_max) / (4 [N^2/s_min - (N-1)^2/s_max]),
 * which is AAF's (1 - s_min/s_max)/4 at N = 1 and tends to 1 as N grows. */
double maaf_box_coverage(double s_min, double s_max, int pairs);
/* The same ratio from a design's boxes (the oracle for the closed form). */
double maaf_box_area(const MaafDesign2D *d);
double maaf_wedge_area(double s_min, double s_max, double omega_y_max);

#endif
