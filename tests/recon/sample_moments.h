/* The mean and the unbiased variance of a pixel's samples, the two moments the filter-gain
 * tests compare the estimate's sums with (test_filter_gain.c, test_camera_gain.c). */
#ifndef WEDGE_TESTS_RECON_SAMPLE_MOMENTS_H
#define WEDGE_TESTS_RECON_SAMPLE_MOMENTS_H

static inline double sample_mean(const double *x, int count)
{
    double m = 0.0;
    for (int i = 0; i < count; ++i) m += x[i];
    return m / count;
}

static inline double sample_variance(const double *x, int count)
{
    double m = sample_mean(x, count), v = 0.0;
    for (int i = 0; i < count; ++i) v += (x[i] - m) * (x[i] - m);
    return v / (count - 1);
}

#endif
