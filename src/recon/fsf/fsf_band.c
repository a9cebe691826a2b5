/* FSF's band per source (fsf_band.h). */
#include "recon/fsf/fsf_band.h"

#include <math.h>

float fsf_band_threshold(int samples)
{
    float n = samples > 1 ? (float)samples : 1.0f;
    return expf(-2.0f) * sqrtf((float)FSF_BAND_REF_SPP / n);
}

float fsf_lens_sigma_u(int samples)
{
    /* the disk's spectrum 2 J1(W) / W has the envelope 2 sqrt(2 / pi) W^-3/2 (J1's asymptote) */
    const float envelope = 2.0f * sqrtf(2.0f / 3.14159265f);
    float omega_u = powf(envelope / fsf_band_threshold(samples), 2.0f / 3.0f);
    return 2.0f / omega_u;
}

/* W K1(W), K1 the modified Bessel function of the second kind, by its integral K1(W) =
 * int_0^inf exp(-W cosh s) cosh s ds (the integrand is below 1e-12 of its peak by s = 6 for W >= 1). */
static double w_k1(double w)
{
    const int steps = 60;
    const double ds = 6.0 / steps;
    double sum = 0.0;
    for (int i = 0; i <= steps; ++i) {
        double c = cosh(ds * i), f = exp(-w * c) * c;
        sum += (i == 0 || i == steps) ? 0.5 * f : f;
    }
    return w * sum * ds;
}

float fsf_bounce_sigma_v(int samples)
{
    /* W K1(W) falls monotonically from 1: bisect for the threshold */
    double t = fsf_band_threshold(samples), lo = 1.0, hi = 20.0;
    for (int i = 0; i < 30; ++i) {
        double mid = 0.5 * (lo + hi);
        if (w_k1(mid) > t) lo = mid;
        else hi = mid;
    }
    return (float)(2.0 / (0.5 * (lo + hi)));
}
