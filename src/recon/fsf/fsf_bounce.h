/* FSF for one-bounce diffuse indirect light (FSF section 3.1 "Diffuse Indirect Illumination",
 * section 5; docs/algorithms.md, "FSF", "Indirect light"): the bounce direction's v-plane in
 * place of the light.
 *
 * The filter (fsf_filter.h) takes per sample a 2D coordinate and per pixel a shear, widths
 * and gather directions; for indirect light:
 *
 *   frame    per receiver pixel an orthonormal tangent frame (t1, t2, n): t1 the screen-x
 *            Jacobian column dP/dx projected on the tangent plane (neighbouring pixels of one
 *            surface share it to first order), t2 = n x t1
 *   coord    v_a = (d . t_a) / (d . n) for a bounce direction d: the point where the bounce
 *            ray pierces the plane at unit height above the receiver, parallel to it (FSF's
 *            v-plane), clamped into [-3.7, 3.7]^2 inside the truncated plane [-5, 5]^2 (FSF
 *            section 5): every cosine-sampled direction keeps counting (FSF_BOUNCE_V_RIM)
 *   slope    a bounce hit H at height h = t_hit (d . n) over the tangent plane, seen at v' from
 *            the neighbour x' = x + D (D in the tangent plane), is seen from x at
 *            v = v' + D / h: an exact linear shear with k = 1 / h (v units per receiver metre;
 *            FSF's s = z in its own units). A miss (t_hit = inf) has k = 0
 *   shear    eta_a = k_mean (step_world[a] . t_a), v units per pixel step along dir[a]: the
 *            sign convention of fsf_filter.h (the sample's coordinate seen from x is
 *            v'_a + eta_a t for the neighbour t steps away). Kept in px and the AOV; the
 *            method's filter (fsf_flat.h) does not apply it
 *   width    FSF eq. 4 with the transfer's band at the pixel's samples: sigma_v = 2 / Omega_v,
 *            Omega_v where the transfer's spectrum W K1(W) meets e^-2 sqrt(16 / n)
 *            (fsf_bounce_sigma_v: 2.87 at 16 samples, Mehta 2013's Omega_v_max = 2.8 being
 *            its e^-2 point): sigma_x = sigma_v / (k_hi - k_lo) / mu metres, over windows of slopes as
 *            for shadows (fsf_slope_window.h), capped at the 32-pixel diameter; then the
 *            parallax bound (FSF_BOUNCE_PARALLAX_V). The slopes come from the samples within
 *            the band's reach on the v-plane only (fsf_bounce_reach_sq)
 *   profile  the box |v_a| <= 5 with the samples' own cosine density: cosine sampling draws
 *            v with density gamma(v) / pi, gamma(v) = 1 / (1 + |v|^2)^2 the transfer, so a
 *            plain mean of the samples inside the box is the paper's box filter with gamma
 *            weights (section 5) */
#ifndef WEDGE_RECON_FSF_BOUNCE_H
#define WEDGE_RECON_FSF_BOUNCE_H

#include <stdbool.h>

#include "core/vec.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/gbuffer.h"
#include "recon/sample_store.h"

/* The truncated v-plane's half extent (FSF section 5): the box profile and the grid. */
#define FSF_BOUNCE_V_HALF 5.0f
/* Where samples are clamped. The v-plane is infinite (every direction of the hemisphere is
 * part of the irradiance); the box is a truncation, not a boundary like a light's edge, so a
 * sample the shear moves past it is light lost, not a ray that misses. A cosine-sampled
 * direction lies beyond |v_a| = 5 with probability ~3% (1/26 beyond |v| = 5 radially), and
 * the taps shift samples by up to FSF_BOUNCE_PARALLAX_V plus one step's shear: clamped onto the
 * box's edge, samples were dropped by half the taps and fsf_density's correction (made for
 * uniform samples) did not restore them (-0.014 on test_fsf_bounce_factored's disk, whose
 * view factor is 0.96; dropping them outright: +0.018). Clamped 1.3 v inside the edge (into a
 * y2 bin whose centre plus one shift node, 1.25 v, stays in the box) no tap drops any sample
 * (-0.0012 there, within the 4 seeds' noise of 0.0008), which makes the box flat over every
 * sample: docs/algorithms.md, "FSF", "Indirect light". */
#define FSF_BOUNCE_V_RIM 3.7f
/* A receiver's tangent frame. */
typedef struct {
    vec3 t[2], n;
} FsfBounceFrame;

/* The frame from the pixel's screen-x Jacobian column jx and unit normal n; false when jx is
 * (nearly) along n. */
bool fsf_bounce_frame(vec3 jx, vec3 n, FsfBounceFrame *f);

/* v (2 floats) of a bounce direction d in frame f, clamped into the rim's square; (0, 0) for no
 * direction (a sample without a bounce: it still counts, with its value). */
void fsf_bounce_coord(const FsfBounceFrame *f, vec3 d, float v[2]);

/* k = 1 / h, h = t_hit (d . n): v units per receiver metre; 0 for a miss (t_hit = inf); NaN
 * for no bounce or a direction at or below the tangent plane. */
float fsf_bounce_slope(vec3 n, vec3 d, float t_hit_m);

/* The grid: v over [-5, 5]^2, the box profile the same square; 9 shift nodes (8 bins), not the
 * paper's 17: the kernels 0.69x on indirect at 16 spp, its error 0.996-1.003x over seeds 1-3 at
 * 8-32 spp (the bounce's filters are wide and its light smooth; docs/algorithms.md section 10,
 * "Coarser shift grids"). */
#define FSF_BOUNCE_SHIFT_NODES 9
FsfGrid fsf_bounce_grid(void);

/* The store's samples' v-plane coordinates (slots as FsfSamples): y the clamped v of each sample
 * in its pixel's frame (0 where the pixel has none), count the stored samples; usable: samples,
 * a frame, not mixed, and (value4 not NULL) value4 usable. The filter reads no sample's light:
 * its passes take each pixel's stored count times its mean (fsf_flat.h). y NULL: usable and count
 * only (the filter reusing the plan's parameters). false when the store lacks the bounce field. */
bool fsf_bounce_coords(const GBuffer *g, const SampleStore *st, const float *value4, unsigned char *usable, float *y,
                       int *count);

typedef struct {
    const GBuffer *g;
    const SampleStore *store;    /* with SAMPLE_FIELD_BOUNCE */
    const float *y;              /* the samples' v (fsf_bounce_coords): those clamped onto the
                                  * rim have no slope (see fsf_bounce_params) */
    const unsigned char *usable;
    float mu;                    /* width divisor (> 0) */
    float parallax_v;            /* the parallax bound, v units (INFINITY: none) */
    float h_min_frac;            /* heights below this * the scene's size count as it (0: none) */
} FsfBounceIn;

/* A floor under the heights h (slopes at most 1 / (this * scene size)), as AAF-GI's on z_min
 * (its section 5, 2%): near a contact line h -> 0, the spread grows without bound and the
 * widths fall to 0, leaving those pixels plain Monte Carlo. */
#define FSF_BOUNCE_H_MIN_FRAC 0.02f

/* The v distance the taps (2 sigma) may move the nearest reflector's hits: sigma_x <= this /
 * (2 k_hi). The filter weights a reprojected sample by the box, not by gamma at the sheared
 * coordinate, so once the shear is a sizeable part of gamma's scale (~1 v unit) the wide
 * widths of FSF eq. 4 at a small slope spread blur irradiance detail (docs/algorithms.md,
 * "FSF", "Indirect light": measured). */
#define FSF_BOUNCE_PARALLAX_V 1.0f
_Static_assert(FSF_BOUNCE_PARALLAX_V < FSF_BOUNCE_V_HALF - FSF_BOUNCE_V_RIM, "the taps must not push a sample off the box");

/* The reach on the v-plane of the samples whose slopes bound the widths, at n samples:
 * |v|^2 <= 1 / fsf_band_threshold(n) - 1. Cosine sampling puts the share 1 / (1 + V^2) of the
 * irradiance's directions beyond |v| = V, so a reflector that only those directions see gives
 * at most that share of the pixel's light (if no brighter than the rest), and the band's rule
 * (fsf_band.h) lets the filter drop what is weaker than e^-2 sqrt(16 / n) of the mean: 1.9 v at
 * 6 samples, 2.4 at 14, 3.6 at 56, the rim (3.7) at 63, the corners of its square (5.2) at 240
 * (docs/algorithms.md section 10, "The slopes within the band's reach"). */
float fsf_bounce_reach_sq(int samples);

/* px and the AOVs k_lo, k_hi (0 where unknown) per pixel. The slope range holds only the
 * samples inside the rim's square (FSF's v-plane is truncated, section 5), and beyond it the
 * slope has no bound (a floor point sees the foot of a wall at height h -> 0, k -> inf at
 * |v| -> inf; inside the box k <= 5 / D for a wall at distance D), which would make every
 * width 0; and of those, only the samples within the reach of the pixel's count
 * (fsf_bounce_reach_sq). false when out of memory or the store lacks the bounce field. */
bool fsf_bounce_params(const FsfBounceIn *in, FsfPixel *px, float *k_lo, float *k_hi);

#endif
