/* The universal band integral Phi_p (see maaf_band_cdf.h). */
#include "recon/maaf/maaf_band_cdf.h"

#include <math.h>
#include <pthread.h>

/* Simpson panels between two entries: a step of 1 / (2 x 4 x 256) in v, on an integrand whose
 * fourth derivative is at most (2p + ...)^4 phi(0) < 2e3 (p <= 4): the rule's error over the
 * whole range is ~1e-11, far below a float's half ulp. */
enum { PANELS_PER_ENTRY = 4 };

static MaafBandCdf table;
static pthread_once_t built = PTHREAD_ONCE_INIT;

static void build(void)
{
    const double h = 1.0 / (MAAF_BAND_CDF_PER_UNIT * 2.0 * PANELS_PER_ENTRY); /* Simpson's step */
    for (int p = 0; p < MAAF_PAIRS_MAX; ++p) {
        /* the part below -V_MAX (at most the normal tail, 6e-16) is left out */
        double re = 0.0, im = 0.0;
        table[p][0][0] = table[p][0][1] = 0.0f;
        for (int e = 0; e + 1 < MAAF_BAND_CDF_ENTRIES; ++e) {
            double v0 = -MAAF_BAND_CDF_V_MAX + (double)e / MAAF_BAND_CDF_PER_UNIT;
            for (int k = 0; k <= 2 * PANELS_PER_ENTRY; ++k) {
                double u = v0 + k * h, w = (k == 0 || k == 2 * PANELS_PER_ENTRY ? 1.0 : k % 2 ? 4.0 : 2.0) * h / 3.0;
                double g = w * 0.3989422804014327 * exp(-0.5 * u * u);
                re += g * cos(2.0 * p * u);
                im += g * sin(2.0 * p * u);
            }
            table[p][e + 1][0] = (float)re;
            table[p][e + 1][1] = (float)im;
        }
    }
}

const MaafBandCdf *maaf_band_cdf(void)
{
    pthread_once(&built, build);
    return (const MaafBandCdf *)&table;
}
