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
 * geometry, so pass 1a carries it with no new channel. */
#ifndef WEDGE_RECON_FSF_GEO_TERM_H
#define WEDGE_RECON_FSF_GEO_TERM_H

#include <stddef.h>

typedef struct {
    float centre[3], axis[2][3], normal[3]; /* the light's frame (world; axes and normal unit) */
    const float *mean_g;                    /* per pixel: the mean of G over the light (1/m^2);
                                             * 0 where form 4 does not apply (below) */
} FsfGeoTerm;

/* G (1/m^2) at a receiver point pos (world, metres) with unit normal nrm towards the light
 * point at light coordinates (z1, z2) (metres along the light's axes); 0 below the receiver's
 * horizon. */
float fsf_geo_G(const FsfGeoTerm *t, const float *pos, const float *nrm, float z1, float z2);

/* Per pixel (pos4, nrm4 as FsfGuides'), mean_g: G's mean over the light of half extents
 * half_m, on an 8 x 8 midpoint grid; 0 for a pixel that is not usable or whose light
 * straddles its tangent plane (a light corner with G = 0: the curved receiver's terminator,
 * where a sample's 0 is the receiver's own horizon, not an occluder the shear can move). */
void fsf_geo_mean(const FsfGeoTerm *t, const float *pos4, const float *nrm4, const unsigned char *usable,
                  const float half_m[2], size_t n, float *mean_g);

/* Form 4's factors for a sample of pixel i at light point (y1, y2) read at z1 along the first
 * axis: *f_rgb multiplies its value, *f_w its weight. Both 1 where the pixel has no mean term
 * (t NULL, or mean_g 0) or the sample's own term is 0. */
void fsf_geo_factors(const FsfGeoTerm *t, const float *pos4, const float *nrm4, size_t i, float y1, float y2,
                     float z1, float *f_rgb, float *f_w);

#endif
