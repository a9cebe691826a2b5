/* The still pixels' noise share and the still band's widening (lr_noise_share.h). */
#include "recon/lr/lr_noise_share.h"

#include <math.h>
#include <stddef.h>

/* brightness floor against black pixels, in the units of lr_bright (r + g + b) */
#define BRIGHT_FLOOR2 0.03

double lr_still_noise_share(const LrSamples *img, const unsigned char *moving)
{
    int n = img->spp;
    if (n < 2) return -1.0;
    double noise = 0.0, differ = 0.0;
    long pairs = 0;
    for (int y = 0; y < img->height; ++y) {
        double prev_mean = 0.0;
        bool prev_still = false;
        for (int x = 0; x < img->width; ++x) {
            size_t i = (size_t)y * (size_t)img->width + (size_t)x;
            bool still = !moving[i];
            double sum = 0.0, sum2 = 0.0;
            for (int k = 0; still && k < n; ++k) {
                double b = img->bright[i * (size_t)n + (size_t)k];
                if (!isfinite(b)) still = false;
                sum += b, sum2 += b * b;
            }
            double mean = sum / n;
            if (still && prev_still) {
                double norm = mean * mean + BRIGHT_FLOOR2, var = fmax(0.0, (sum2 - n * mean * mean) / (n - 1));
                noise += var / n / norm;
                differ += 0.5 * (mean - prev_mean) * (mean - prev_mean) / norm;
                ++pairs;
            }
            prev_mean = mean, prev_still = still;
        }
    }
    if (pairs < LR_NOISE_SHARE_MIN_PAIRS || !(differ > 0.0)) return -1.0;
    return noise / differ;
}

float lr_still_band_px(float band_px, double noise_share)
{
    float wide = band_px * lr_still_band_widening(noise_share);
    float cap = band_px > LR_NOISE_BAND_MAX_PX ? band_px : LR_NOISE_BAND_MAX_PX;
    return wide < cap ? wide : cap;
}

float lr_still_band_widening(double noise_share)
{
    if (!(noise_share > LR_NOISE_SHARE_REF)) return 1.0f;
    double w = pow(noise_share / LR_NOISE_SHARE_REF, 0.125);
    return (float)(w < LR_NOISE_WIDEN_MAX ? w : LR_NOISE_WIDEN_MAX);
}
