/* The one function every light's y-factor is made of (docs/algorithms.md 9.6, "The universal
 * band integral"): for band p of the light's y-design (seeds/003 eq. 6),
 *     Phi_p(v) = int_{-inf}^{v} exp(j 2p u) phi(u) du,     phi the standard normal density,
 * v dimensionless (a light coordinate times the design's Fourier width s_y, so in units of the
 * y-Gaussian's primal std 1/s_y). Eq. 6 gives C_y^p = 2p s_y for every light and every N, so
 *     c_p(y) = Phi_p(s_y (hi - y)) - Phi_p(s_y (lo - y))
 * for a light spanning [lo, hi] along the axis: one process-wide table instead of one per light.
 * Phi_0 is the normal CDF; Phi_p(+inf) = exp(-2 p^2) (the Gaussian's characteristic function);
 * Re Phi_p(-v) = exp(-2 p^2) - Re Phi_p(v) and Im Phi_p(-v) = Im Phi_p(v).
 *
 * Tabulated on [-MAAF_BAND_CDF_V_MAX, MAAF_BAND_CDF_V_MAX] every 1 / MAAF_BAND_CDF_PER_UNIT and
 * linearly interpolated; outside it Phi_p is flat to float precision (the normal tail beyond 8
 * is 6e-16) and the end entries are used. Interpolation error at most h^2/8 max|Phi_p''| with
 * |Phi_p''(v)| = sqrt(4 p^2 + v^2) phi(v): h^2/8 x 2p phi(0) = 1.5e-6 p (p >= 1), 4.6e-7 for
 * p = 0 (max |v| phi(v) = phi(1)), per end of the window. */
#ifndef WEDGE_RECON_MAAF_BAND_CDF_H
#define WEDGE_RECON_MAAF_BAND_CDF_H

#include "recon/maaf/maaf_design.h"

#define MAAF_BAND_CDF_V_MAX 8
#define MAAF_BAND_CDF_PER_UNIT 256
#define MAAF_BAND_CDF_ENTRIES (2 * MAAF_BAND_CDF_V_MAX * MAAF_BAND_CDF_PER_UNIT + 1)

/* [p][e] = Phi_p(v_e) (re, im), v_e = -V_MAX + e / PER_UNIT; one band's entries together (the
 * default design reads bands 0 and 1 only). */
typedef float MaafBandCdf[MAAF_PAIRS_MAX][MAAF_BAND_CDF_ENTRIES][2];

/* The table, built on the first call of the process (thread-safe; a double-precision integral,
 * well under a millisecond). */
const MaafBandCdf *maaf_band_cdf(void);

/* Where v falls in the table: entry e and the fraction t in [0, 1] towards e + 1. NaN is -V_MAX. */
typedef struct {
    int e;
    float t;
} MaafBandCdfAt;

static inline MaafBandCdfAt maaf_band_cdf_at(float v)
{
    float u = (v + (float)MAAF_BAND_CDF_V_MAX) * (float)MAAF_BAND_CDF_PER_UNIT;
    if (!(u > 0.0f)) u = 0.0f;
    if (u > (float)(MAAF_BAND_CDF_ENTRIES - 1)) u = (float)(MAAF_BAND_CDF_ENTRIES - 1);
    int e = (int)u;
    if (e > MAAF_BAND_CDF_ENTRIES - 2) e = MAAF_BAND_CDF_ENTRIES - 2;
    return (MaafBandCdfAt){e, u - (float)e};
}

/* Phi_p at a place found by maaf_band_cdf_at. */
static inline void maaf_band_cdf_lerp(const MaafBandCdf *table, int p, MaafBandCdfAt at, float out[2])
{
    const float *a = (*table)[p][at.e], *b = (*table)[p][at.e + 1];
    out[0] = a[0] + at.t * (b[0] - a[0]);
    out[1] = a[1] + at.t * (b[1] - a[1]);
}

/* Re Phi_p alone (the central band's Phi_0 is real). */
static inline float maaf_band_cdf_lerp_re(const MaafBandCdf *table, int p, MaafBandCdfAt at)
{
    float a = (*table)[p][at.e][0], b = (*table)[p][at.e + 1][0];
    return a + at.t * (b - a);
}

#endif
