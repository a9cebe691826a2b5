/* The light's geometric term under FSF's shear (docs/algorithms.md section 10, "The light's
 * geometric term under the shear", form 4).
 *
 * A demodulated soft-shadow sample of pixel x' at light point y carries V(x', y) g_x'(y), with
 * g_x(y) = G(x, y) / mean_y G(x, .) and G(x, y) = max(0, n_x . w) |n_L . w| / d^2 (1/m^2; w the
 * unit direction from the pixel's mean position P_x to the light point, d its distance). The
 * shear reprojects the sample to z = y + eta t at the gathering pixel, but the sample still
 * weights its visibility by its own term at y. Form 4 reads the source pixel's term at the
 * reprojected point instead: in pass 1a (first axis, z = (z1, y2)) the sample's rgb is
 * multiplied by g_x'(z) / g_x'(y) and its weight by g_x'(z). It needs only the source pixel's
 * geometry, so pass 1a carries it with no new channel.
 *
 * Along the second axis (pass 2a, z2 = y2 + eta2 t2) both rgb and weight already carry the term
 * at (z1, y2), and pass 1b has summed z1 away: pass 2a multiplies both by the ratio of the
 * source pixel's z1-marginals Gm(z2) / Gm(y2), Gm(y2) = mean over z1 of G(z1, y2) (exact where
 * G separates as a(z1) b(z2)); y2 is the bin's centre there. */
#ifndef WEDGE_RECON_FSF_GEO_TERM_H
#define WEDGE_RECON_FSF_GEO_TERM_H

#include <stddef.h>

typedef struct {
    float centre[3], axis[2][3], normal[3]; /* the light's frame (world; axes and normal unit) */
    const float *mean_g;                    /* per pixel: the mean of G over the light (1/m^2);
                                             * 0 where form 4 does not apply (below) */
    float ramp_m[2];                        /* a moving light: its samples' density ramps along
                                             * the axes (FsfGrid.ramp_m); 0: uniform */
    float pose_m[2], motion_m[2];           /* a translating light: its pose's extent and its
                                             * motion over the shutter along the axes (metres;
                                             * FsfLight's), for fsf_geo_mean's joint density;
                                             * pose 0: the product of the ramps' trapezoids */
} FsfGeoTerm;

/* G (1/m^2) at a receiver point pos (world, metres) with unit normal nrm towards the light
 * point at light coordinates (z1, z2) (metres along the light's axes); 0 below the receiver's
 * horizon. */
float fsf_geo_G(const FsfGeoTerm *t, const float *pos, const float *nrm, float z1, float z2);

/* Per pixel (pos4, nrm4 as FsfGuides'), mean_g: G's mean over the light of half extents
 * half_m, on an 8 x 8 midpoint grid (a moving light's: weighted by its samples' density, the
 * mean a sample's G has, which form 4's weight g(z) / mean_g must average to 1 over the pixel's
 * own samples: with t->pose_m set the joint density of a translating pose, fsf_swept_joint,
 * which a diagonal motion does not make a product; else, where t->ramp_m is set, the product of
 * the axes' trapezoids, fsf_swept_profile); 0 for a pixel that is not usable or whose light
 * straddles its tangent plane (a light corner with G = 0: the curved receiver's terminator,
 * where a sample's 0 is the receiver's own horizon, not an occluder the shear can move). */
void fsf_geo_mean(const FsfGeoTerm *t, const float *pos4, const float *nrm4, const unsigned char *usable,
                  const float half_m[2], size_t n, float *mean_g);

/* A moving light's samples' density along one axis (half extent half_m, ramp ramp_m > 0,
 * fsf_swept_profile) averaged over each of the 8 equal cells of [-half_m, half_m] that the
 * means' midpoints (fsf_geo_mean, fsf_geo_marginal) stand for: the weights of those midpoints.
 * The cell's mean rather than the profile at its midpoint: the trapezoid's corners fall inside
 * cells in general, where the midpoint's value is off the cell's mean. */
enum { FSF_GEO_CELLS = 8 };

/* The share of the shutter during which a pose of extent pose_m (along the two axes, centred
 * at c_mean + (s - 1/2) motion_m at shutter time s) covers the light point (z1, z2): the
 * samples' density there over its largest value's (docs/algorithms.md 10, "The swept light's
 * density"). */
float fsf_swept_joint(float z1, float z2, const float pose_m[2], const float motion_m[2]);
void fsf_geo_swept_weights(float half_m, float ramp_m, float w[FSF_GEO_CELLS]);

/* Form 4's factors for a sample of pixel i at light point (y1, y2) read at z1 along the first
 * axis: *f_rgb multiplies its value, *f_w its weight. Both 1 where the pixel has no mean term
 * (t NULL, or mean_g 0) or the sample's own term is 0. */
void fsf_geo_factors(const FsfGeoTerm *t, const float *pos4, const float *nrm4, size_t i, float y1, float y2,
                     float z1, float *f_rgb, float *f_w);

/* Gm (1/m^2): G's mean over z1 in [-half1_m, half1_m] (8 midpoints; a moving light's weighted
 * by its samples' density along z1, t->ramp_m[0]) at the second light coordinate z2, from the
 * receiver point pos with normal nrm. */
float fsf_geo_marginal(const FsfGeoTerm *t, const float *pos, const float *nrm, float half1_m, float z2);

/* Form 4 along the second axis for a sample of pixel i at y2 reprojected to z2: the factor
 * Gm(z2) / Gm(y2) on both its rgb and its weight; 1 where the pixel has no mean term (t NULL,
 * or mean_g 0) or Gm(y2) is 0. A pixel with a mean term has G > 0 over the whole light (its
 * four corners are above the receiver's tangent plane and the light is convex), so Gm > 0. */
float fsf_geo_factor2(const FsfGeoTerm *t, const float *pos4, const float *nrm4, size_t i, float half1_m, float y2,
                      float z2);

#endif
