/* Fast 4D sheared filtering (FSF, seeds/000) of soft shadows: the filter itself, on the host.
 *
 * Coordinates (docs/algorithms.md, section "FSF"):
 *   y = (y1, y2)   a sample's point on the light along the light's axes u, v, in metres,
 *                  centred on the light: |y1| <= L1, |y2| <= L2 (half extents)
 *   x              the pixel grid; gather a steps along the screen direction dir[a] (the
 *                  screen image of light axis a on the receiver), t pixel steps at a time
 *
 * The shear. A sample at receiver x' with light point y' sees the same occluder point as
 * receiver x with light point y' + k (x' - x), k = (d_light - d_occ) / d_occ (light metres
 * per receiver metre; d_light, d_occ measured from the receiver along the shadow ray). With
 * x' = x + t steps along axis a and eta_a = k * (receiver metres per step along u or v), the
 * sample's light coordinate seen from x is y'_a + eta_a t, and the light's profile I (a box:
 * our area lights are uniform) weights it by I(y'_a + eta_a t), i.e. w_y(y'_a - c) with
 * centre c = -eta_a t = eta_a (x - x') (FSF eq. 5, primal form).
 *
 * The 4D filter at pixel x (FSF eq. 9, normalised by the same sum with every value 1):
 *
 *   h(x) = sum_{t1,t2} w(t1; s1) w(t2; s2) sum_k v_k I1(z1) I2(z2) / (rho1(z1) rho2(z2)),
 *          z_a = y_a,k + eta_a t_a (the light coordinate the sample has seen from x)
 *
 * rho (fsf_density) corrects for the samples covering the light unevenly once reprojected.
 * over the samples k of the pixel at x + t1 dir1 + t2 dir2. fsf_filter_brute evaluates that
 * sum directly (the oracle, O(n^2 l^2) per pixel); fsf_filter_factored in four 1D passes:
 *
 *   1a  per pixel and y2 bin: P(Y1) = sum_k v_k I1(z) / rho1(z), z = y1_k - Y1, on a grid of shifts Y1   eq. 12
 *   1b  per pixel and y2 bin: G = sum_t1 w(t1) P(x + t1 dir1, Y1 = -eta1 t1)            eq. 13
 *   2a  per pixel: the bins G_b (over their form-4 marginals) and the marginals
 *   2b  per pixel: H = sum_t2 w(t2) Q(x + t2 dir2, Y2 = -eta2 t2),                       eqs. 14-15
 *       Q(Y2) = sum_b G_b I2(z) / rho2(z), z = c_b - Y2, c_b the centre of y2 bin b, rho2 of the
 *       gathering pixel x's filter (as the oracle's): each tap weights its bins itself
 *
 * Values are 4 floats: demodulated light (rgb) and the weight (1 per sample), so that the
 * result is H.rgb / H.w. Reading P and Q between grid nodes interpolates linearly. */
#ifndef WEDGE_RECON_FSF_FILTER_H
#define WEDGE_RECON_FSF_FILTER_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "recon/fsf/fsf_geo_term.h"

/* The paper's 32-pixel diameter cap (FSF section 5): taps up to 16 steps each side. */
enum { FSF_RADIUS_CAP_PX = 16 };
/* Taps reach 2 sigma (95% of a Gaussian's mass) on the default grid and the bounce's: the
 * widths' caps are set so that a filter of this reach stays inside its slope window
 * (fsf_slope_window.h). The budget plan counts each filter's taps to its own grid's reach
 * (FsfGrid.reach_sigmas). */
#define FSF_RADIUS_SIGMAS 2.0f
/* The shadows' and the lens' taps stop at 1.5 sigma (87% of the mass, the last tap at 0.32 of
 * the centre's weight): a quarter fewer taps in the taps kernel and passes 1b and 2b, and
 * over seeds 1-3 at 8-32 spp relMSE 0.97-1.0x on soft_shadows, defocus and tilted_stack,
 * 1.01-1.02x on thin_occluders; the bounce's (a box of v over the rim's square) keep 2 sigma:
 * 1.5 cost indirect 1.09-1.14x (docs/algorithms.md section 10, "Coarser shift grids, shorter
 * taps"). */
#define FSF_REACH_SIGMAS_NARROW 1.5f

/* One frame's samples as the filter sees them. Slot k of pixel i is index i * capacity + k. */
typedef struct {
    int width, height, capacity;
    const int *count;          /* samples per pixel (<= capacity) */
    const float *y_m;          /* 2 per slot: light coordinates (metres) along u and v */
    const float *value;        /* 3 per slot: the sample's demodulated light */
} FsfSamples;

/* The light and the discretisation shared by all pixels. */
typedef struct {
    float half_m[2];           /* L1, L2: the light's half extents along u and v (metres): where
                                * samples lie (bins, shift grid, density) */
    float profile_half[2];     /* the box profile I keeps |z| <= these: half_m for the light; for
                                * the lens (a disk inside the hull half_m) the square with the
                                * disk's variance (fsf_lens.h) */
    int shift_nodes;           /* nodes of the shift grids Y1, Y2 over [-2 L, 2 L] (odd: one
                                * node at 0); FSF section 5: 16 bins, so 17 nodes */
    int y2_bins;               /* bins of y2 over [-L2, L2] carried through pass 1 (FSF footnote 8);
                                * must be shift_nodes - 1 (<= FSF_MAX_Y2_BINS): pass 2a relies on
                                * the node spacing being twice the bin width */
    float reach_sigmas;        /* the taps reach this many standard deviations each side (capped
                                * at FSF_RADIUS_CAP_PX): fsf_tap_radius */
    float ramp_m[2];           /* a light that moves: the ramps (metres) of its samples' density
                                * along u and v (fsf_swept_profile); 0: a uniform light, the box */
} FsfGrid;
enum { FSF_MAX_Y2_BINS = 64 };

/* Per pixel. sigma_px[a] == 0 leaves the pixel out (its input passes through). */
typedef struct {
    float dir[2][2];           /* unit screen directions of the gathers along axes 1, 2 */
    float eta_m[2];            /* light metres per pixel step along dir[a] (the shear) */
    float sigma_px[2];         /* standard deviation of w along dir[a], pixel steps */
} FsfPixel;

/* A pixel left out: screen axes, no shear, width 0. */
static inline FsfPixel fsf_pixel_left_out(void)
{
    FsfPixel p = {{{1.0f, 0.0f}, {0.0f, 1.0f}}, {0.0f, 0.0f}, {0.0f, 0.0f}};
    return p;
}

/* Which neighbours a pixel may take light from: same surface orientation and plane. */
typedef struct {
    const float *pos4;         /* mean position (world) and camera depth per pixel; NULL (with
                                * nrm4): no geometric test, every usable neighbour */
    const float *nrm4;         /* unit normal per pixel (or NULL, with pos4) */
    const unsigned char *usable; /* 0: no surface, mixed, or not demodulated: never a source,
                                  * and its own result is 0 (the host keeps its input): no pass
                                  * reads its samples */
    float cos_normal_min;      /* neighbours whose normal is further are rejected */
    float plane_tol_rel;       /* ... or off the centre's tangent plane by more than this * depth */
    const FsfGeoTerm *geo;     /* the light's geometric term (fsf_geo_term.h, form 4): passes 1a,
                                * 2a and the oracle weight each sample by its pixel's term at the
                                * reprojected light point; needs pos4 and nrm4. NULL: none (the
                                * lens, indirect light; fsf_guides_default) */
} FsfGuides;

/* The guides' neighbour angle (fsf_guides_default): cos 15 deg, as the AAF filters' (papers:
 * 10-20 deg). */
#define FSF_NEIGHBOUR_COS_MIN 0.96592583f

/* May centre pixel p take light from pixel q (usable, and unless the guides are NULL, its
 * normal within the guides' angle and its mean position within the tolerance of p's tangent
 * plane)? The filter's taps, the oracle's and the footprint's slope range (fsf_params.c). */
static inline bool fsf_accept(const FsfGuides *gd, int p, int q)
{
    if (!gd->usable[q]) return false;
    if (q == p || !gd->nrm4) return true; /* no guides: every usable neighbour */
    const float *np = gd->nrm4 + 4 * (size_t)p, *nq = gd->nrm4 + 4 * (size_t)q;
    if (np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2] < gd->cos_normal_min) return false;
    const float *pp = gd->pos4 + 4 * (size_t)p, *pq = gd->pos4 + 4 * (size_t)q;
    float off = np[0] * (pq[0] - pp[0]) + np[1] * (pq[1] - pp[1]) + np[2] * (pq[2] - pp[2]);
    return fabsf(off) <= gd->plane_tol_rel * pp[3];
}

/* The pixel t steps from (x, y) along dir, rounded to the nearest; -1 outside the image. */
static inline int fsf_step_pixel(int w, int h, int x, int y, const float dir[2], float t)
{
    int qx = x + (int)floorf(t * dir[0] + 0.5f), qy = y + (int)floorf(t * dir[1] + 0.5f);
    return (qx < 0 || qy < 0 || qx >= w || qy >= h) ? -1 : qy * w + qx;
}

/* The paper's grid (17 shift nodes, 16 y2 bins) over half extents u, v; fsf_grid_nodes with
 * another odd count of nodes (3 .. FSF_MAX_Y2_BINS + 1). */
FsfGrid fsf_grid_default(float half_u_m, float half_v_m);
FsfGrid fsf_grid_nodes(float half_u_m, float half_v_m, int shift_nodes);
FsfGuides fsf_guides_default(const float *pos4, const float *nrm4, const unsigned char *usable);
/* Guides that accept every usable neighbour (defocus: docs/algorithms.md section 10,
 * "Defocus"): nothing per pixel to read or compare. */
FsfGuides fsf_guides_unguided(const unsigned char *usable);

/* Taps each side along one axis for a standard deviation (capped): to reach_sigmas, to the
 * grid's reach (the filter's own taps). */
int fsf_radius_reach(float sigma_px, float reach_sigmas);
int fsf_tap_radius(const FsfGrid *g, float sigma_px);

/* The 4D sum, directly (the oracle). out4: 4 floats per pixel (rgb, weight); pixels left
 * out (both widths 0) get their own samples' plain sum, pixels that are not usable 0. */
void fsf_filter_brute(const FsfSamples *s, const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd, float *out4);

/* The same in four 1D passes. false when out of memory (or a grid without y2_bins = shift_nodes - 1). */
bool fsf_filter_factored(const FsfSamples *s, const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd,
                         float *out4);

/* One tap of a gather: the node (q * shift_nodes + j0) of the neighbour q's grid below the
 * tap's shift, and the weights of nodes j0 and j0 + 1 (Gaussian times linear
 * interpolation); node -1: no tap (outside the radius or the image, rejected). */
typedef struct {
    int node;
    float a0, a1;
} FsfTap;
enum { FSF_TAPS = 2 * FSF_RADIUS_CAP_PX + 1 };

/* The pieces, for the OpenCL version's tests: each pixel's taps along one axis (FSF_TAPS
 * per pixel); one y2-bin slice of pass 1a (P: shift_nodes * 4 per pixel) and pass 1b of that
 * slice into G (y2_bins * 4 per pixel; cum1: fsf_tap_prefix of each pixel's first axis, FSF_CUM
 * floats per pixel); pass 2a (Q: FSF_Q2_FLOATS per pixel, each bin's 4 sums over its form-4
 * marginal, then the B marginals) and 2b (out4; the density of the second axis from the
 * gathering pixel's filter, so 2b reads a tap's bins rather than two nodes). */
#define FSF_Q2_FLOATS(bins) (5 * (bins))
/* The OpenCL pass 2a's Q per pixel, fsf.cl's FSF_Q_FLOATS(B, geo) (keep the two equal): with
 * form 4 (geo) the C layout's 5 B plus the marginals clamped for pass 2b's contiguous reads */
#define FSF_Q2_CL_FLOATS(bins, geo) ((geo) ? 7 * (bins) + 8 : FSF_Q2_FLOATS(bins))
void fsf_taps(const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd, int width, int height, int axis,
              FsfTap *taps, size_t begin, size_t end);
void fsf_pass1a(const FsfSamples *s, const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd,
                const float *cum1, int bin, float *P, size_t begin, size_t end);
void fsf_pass1b(const FsfGrid *g, const FsfTap *taps1, int bin, const float *P, float *G, size_t begin, size_t end);
void fsf_pass2a(const FsfGrid *g, const FsfGuides *gd, const float *G, float *Q, size_t begin, size_t end);
void fsf_pass2b(const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd, const FsfTap *taps2, const float *Q,
                float *out4, size_t begin, size_t end);

/* The density of reprojected samples. Samples lie uniformly on the light, so those of the
 * neighbour t steps away land, seen from the centre, uniformly on [-L + eta t, L + eta t]:
 * at a light coordinate z the taps' weights overlap as rho(z) = sum_t w(t) [|z - eta t| <= L],
 * highest mid-light and lowest at its ends. Each sample is weighted by 1 / rho so that the
 * sum estimates the light's uniform mean rather than a profile tapered by the filter.
 * fsf_tap_prefix fills cum (2 r + 2 floats, r the filter's radius, fsf_tap_radius) with the
 * running sums of w over the taps -r .. r. */
enum { FSF_CUM = 2 * FSF_RADIUS_CAP_PX + 2 };
void fsf_tap_prefix(float sigma_px, int r, float *cum);
float fsf_density(float z_m, float eta_m, float half_m, int r, const float *cum);

/* Pass 1a divides a pixel's samples by the density of its own filter, as the gathering pixel's
 * is not known there (FSF section 4.2); where the neighbours' widths differ, a narrow one's
 * density (near 1) is a wide one's (near its taps' sum) several times over, and its samples
 * outweigh the gatherer's. So the factored passes divide by the density over its mean over
 * the profile box, and each tap along the first axis by the gathering pixel's mean: exact
 * where the filters agree, the means' ratio corrected where they do not (docs/algorithms.md
 * section 10, "Pass 1a's density over its mean"). fsf_density_mean is that mean (>= 1 for
 * sigma >= 0: the centre tap covers the box), fsf_tap_prefix_mean the running sums of the
 * pixel's first axis over it (pass 1a's cum1). */
float fsf_density_mean(const FsfGrid *g, int axis, float eta_m, float sigma_px);

/* A light that moves during the shutter (docs/algorithms.md 10, "The swept light's density"):
 * its samples' light points lie over the area it sweeps with a density proportional to the
 * time it covers each point, along axis a the trapezoid T(z) = clamp((L - |z|) / ramp, 0, 1)
 * (the pose's extent convolved with the motion's; L = half_m[a], ramp = ramp_m[a] > 0): the
 * light's profile I (FSF eq. 9) in place of the box. Its samples seen from a pixel t steps away lie with
 * density T(z - eta t), so the density of reprojected samples is
 * rho(z) = sum_t w(t) T(z - eta t) (fsf_density_swept; cum as fsf_density's), and a sample
 * weighs T(z) / rho(z): fsf_swept_weight, 0 where either is 0. With ramp 0 the filter keeps
 * the box and fsf_density (a static light, bit for bit). */
float fsf_swept_profile(float z_m, float half_m, float ramp_m);
float fsf_density_swept(float z_m, float eta_m, float half_m, float ramp_m, int r, const float *cum);
float fsf_swept_weight(float z_m, float eta_m, float half_m, float ramp_m, int r, const float *cum);
void fsf_tap_prefix_mean(const FsfGrid *g, const FsfPixel *p, float *cum);

/* The factors that make a pixel's samples (count of them, 3 floats each from sample_rgb)
 * average to its value value4 (rgb): value / mean per channel, 0 where the mean is not
 * positive or the factor not finite. The pipeline's value may differ from the samples' raw
 * mean (demodulation, a shading filter's result); the filter then blurs samples on the
 * pixel's own scale. */
void fsf_match_pixel(const float *value4, const float *sample_rgb, int count, float scale[3]);
/* The same over the samples whose light point is on the filter's light (fsf_sample_on_light:
 * light coordinates y_m, 2 per sample, within the half extents); every sample when none is.
 * The shadow filter's box profile gives a sample aimed at another emitter no weight, so the
 * filter averages the others alone: their mean is the pixel's light over the probability of
 * choosing this light, and it is that mean the pixel's value must scale. */
void fsf_match_pixel_on_light(const float *value4, const float *sample_rgb, const float *y_m, const float half_m[2],
                              int count, float scale[3]);
/* y_m within the half extents, to the rounding of a light point's projection on the axes */
#define FSF_ON_LIGHT_SLACK 1e-4f
bool fsf_sample_on_light(const float y_m[2], const float half_m[2]);
/* out (3 floats per sample) = each of count samples' rgb times scale (fsf_match_pixel's); a
 * product that is not finite is written as 0 and counted: the return value, which the method
 * reports (a value cleaned up is never hidden). */
long long fsf_scale_samples(const float *sample_rgb, int count, const float scale[3], float *out);

/* After fsf_scale_samples: where one channel of a pixel's stored samples sums to 0 (or less)
 * while its value4 is positive, the pixel's light is in samples the store did not keep (under
 * a --spp budget pass 2 adds samples the store has no room for), fsf_match_pixel's scale is 0
 * and the filter would drop that light. Each stored sample (out, count of them) then takes the
 * value itself in that channel, so that a pixel's samples always sum to count times its value.
 * Where light is rare (a wall lit by a small bright patch, most stored samples 0) the drop was a
 * bias: 16% dark on hotspot_bounce's left wall at 16 spp (docs/algorithms.md 10, "FSF's
 * biases on held-out scenes"). */
void fsf_fill_dark_channels(const float *value4, const float *sample_rgb, int count, float *out);

/* The y2 bin of a light coordinate (clamped into [0, y2_bins)). */
int fsf_y2_bin(const FsfGrid *g, float y2_m);

#endif
