/* auto's model past the sample counts its footprints were measured at (branch auto5;
 * docs/algorithms.md, "the error ratio's growth with N"): g(N), the growth of a borrowed
 * sample's error relative to Monte Carlo's, against its closed form; the shading and camera
 * error ratios with it against a brute-force sum over the pixels (own samples' part kept,
 * neighbours' part times g); the camera filters' margin (4/3 up to N_fit, 1 past it); the
 * decision on a frame whose camera filter is kept at 16 spp and left to Monte Carlo at 64, with
 * its speed by the formula. */
#include <math.h>
#include <stdio.h>

#include "check.h"
#include "sample_moments.h"
#include "recon/auto_fallback.h"
#include "recon/filter_gain.h"

enum { N = 4, COUNT = 2 * N, PIXELS = 3 };

int main(void)
{
    /* g(N): 1 up to N_fit, (N / N_fit)^(alpha - 1) past it; 1 for independent samples */
    CHECK_NEAR(auto_fallback_neighbour_error(8, 1.5), 1.0, 0.0);
    CHECK_NEAR(auto_fallback_neighbour_error(16, 1.5), 1.0, 0.0);
    CHECK_NEAR(auto_fallback_neighbour_error(64, 1.5), 2.0, 1e-12); /* 4^0.5 */
    CHECK_NEAR(auto_fallback_neighbour_error(256, 1.25), 2.0, 1e-12); /* 16^0.25 */
    CHECK_NEAR(auto_fallback_neighbour_error(1024, 1.0), 1.0, 0.0);
    CHECK_NEAR(auto_fallback_neighbour_error(0, 2.0), 1.0, 0.0);
    /* the camera filters' margin: as measured up to N_fit, none past it */
    CHECK_NEAR(auto_fallback_camera_margin(16), AUTO_CAMERA_MIN_ADVANTAGE, 0.0);
    CHECK_NEAR(auto_fallback_camera_margin(17), 1.0, 0.0);

    /* three pixels, each a penumbra over a texture (radiance = albedo x visibility + a texture
     * term no filter takes), blurred by footprints 1, 4 and 20 */
    const double vis[PIXELS][COUNT] = {{0.0, 0.3, 0.9, 0.6, 1.0, 0.1, 0.4, 0.7},
                                       {0.2, 0.8, 0.5, 0.5, 0.9, 0.1, 0.6, 0.4},
                                       {1.0, 0.0, 1.0, 0.0, 0.5, 0.5, 0.7, 0.3}};
    const double tex[COUNT] = {0.05, 0.0, 0.1, 0.02, 0.0, 0.08, 0.03, 0.01};
    const double footprint[PIXELS] = {1.0, 4.0, 20.0};
    FilterGainTotals t = {0};
    double all = 0.0, want_cam[2] = {0.0, 0.0}, want_one = 0.0;
    const double g = 2.5, fs = AUTO_FILTER_FOOTPRINT;
    for (int p = 0; p < PIXELS; ++p) {
        FilterGainSample s[COUNT];
        double l[COUNT], left[COUNT];
        for (int i = 0; i < COUNT; ++i) {
            double d = 0.5 * vis[p][i];
            s[i] = (FilterGainSample){(float)(d + tex[i]), (float)d, 0.5f, 0.0f, 0.0f};
            l[i] = (float)(d + tex[i]);
        }
        /* the ideal soft-shadow filter leaves the texture: albedo x the pixel's mean light */
        double sum_d = 0.0, sum_a = 0.0;
        for (int i = 0; i < COUNT; ++i) sum_d += s[i].direct_filterable, sum_a += s[i].albedo_direct;
        for (int i = 0; i < COUNT; ++i) left[i] = l[i] - s[i].direct_filterable + s[i].albedo_direct * sum_d / sum_a;
        double m = sample_mean(l, COUNT), w = 1.0 / (m * m + 0.01);
        double var = sample_variance(l, COUNT), kept = fmin(sample_variance(left, COUNT), var), f = footprint[p];
        all += w * var;
        /* brute force: own samples' part of what the shading filter leaves, neighbours' part
         * times g; what it removes is all neighbours', times g, over both footprints */
        want_cam[0] += w * (kept * (1.0 + (f - 1.0) * g) / (f * f) + g * (var - kept) / (fs * f));
        want_cam[1] += w * var * (1.0 + (f - 1.0) * g) / (f * f); /* no shading filter */
        want_one += w * (kept + (var - kept) / fs) / f;
        filter_gain_add_pixel_sets(&t, s, N, N, false, f);
    }
    CHECK_NEAR(t.left[FILTER_GAIN_NONE], all, 1e-6 * all); /* the samples are floats */
    CHECK_NEAR(filter_gain_camera_error_ratio_at(&t, FILTER_GAIN_DIRECT, fs, g), want_cam[0] / all, 1e-6);
    CHECK_NEAR(filter_gain_camera_error_ratio_at(&t, FILTER_GAIN_NONE, fs, g), want_cam[1] / all, 1e-6);
    /* g = 1: the error ratio as measured (and as before this model) */
    CHECK_NEAR(filter_gain_camera_error_ratio_at(&t, FILTER_GAIN_DIRECT, fs, 1.0), want_one / all, 1e-6);
    CHECK_NEAR(filter_gain_camera_error_ratio_at(&t, FILTER_GAIN_DIRECT, fs, 1.0),
               filter_gain_camera_error_ratio(&t, FILTER_GAIN_DIRECT, fs), 1e-12);
    /* the shading ratio: (1 - s) + s g / F */
    double share = filter_gain_share(&t, FILTER_GAIN_DIRECT);
    CHECK(share > 0.2 && share < 1.0);
    CHECK_NEAR(filter_gain_error_ratio_at(&t, FILTER_GAIN_DIRECT, fs, g), (1.0 - share) + share * g / fs, 1e-12);
    CHECK_NEAR(filter_gain_error_ratio_at(&t, FILTER_GAIN_DIRECT, fs, 1.0), filter_gain_error_ratio(&t, FILTER_GAIN_DIRECT, fs), 1e-12);

    /* the decision: motion alone, one texture pixel blurred so that the camera filter's
     * predicted speed at 16 spp is 0.9x Monte Carlo's: kept there (within the 4/3 margin);
     * at 64 spp its error grows by g and the margin is 1: left to Monte Carlo */
    {
        const double x[COUNT] = {0.2, 0.8, 0.3, 0.7, 0.25, 0.75, 0.35, 0.65};
        FilterGainSample s[COUNT];
        for (int i = 0; i < COUNT; ++i) s[i] = (FilterGainSample){(float)x[i], 0.0f, 0.0f, 0.0f, 0.0f};
        FilterGainTotals probe = {0};
        filter_gain_add_pixel_sets(&probe, s, N, N, false, 1.0);
        double alpha = filter_gain_alpha(&probe), t_s = 2.0 * AUTO_RAY_US;
        CHECK(alpha > 1.05); /* g grows */
        AutoFallbackFrame f16 = {false, false, 0, false, 16, 1, false, false, false};
        double t16 = auto_fallback_time_us(FILTER_GAIN_NONE, &f16, t_s);
        double f = pow(0.9 * t16 / (16 * t_s), alpha); /* E = 1 / f gives 0.9x at 16 spp */
        FilterGainTotals u = {0};
        filter_gain_add_pixel_sets(&u, s, N, N, false, f);
        AutoFallback fb;
        auto_fallback_decide(&u, 2.0, &f16, &fb);
        CHECK_NEAR(fb.neighbour_error, 1.0, 0.0);
        CHECK_NEAR(fb.camera_speedup, 0.9, 1e-6);
        CHECK(!fb.camera_fell_back);
        AutoFallbackFrame f64 = f16;
        f64.spp = 64;
        auto_fallback_decide(&u, 2.0, &f64, &fb);
        double g64 = pow(4.0, alpha - 1.0), e64 = (1.0 + (f - 1.0) * g64) / (f * f);
        CHECK_NEAR(fb.neighbour_error, g64, 1e-12);
        CHECK_NEAR(fb.camera_error, e64, 1e-6);
        double t64 = auto_fallback_time_us(FILTER_GAIN_NONE, &f64, t_s);
        CHECK_NEAR(fb.camera_speedup, pow(e64, -1.0 / alpha) * 64 * t_s / t64, 1e-6);
        CHECK(fb.camera_speedup < 1.0);
        CHECK(fb.camera_fell_back);
        /* a blur 40 times wider still pays at 64 spp */
        FilterGainTotals v = {0};
        filter_gain_add_pixel_sets(&v, s, N, N, false, 40.0 * f);
        auto_fallback_decide(&v, 2.0, &f64, &fb);
        CHECK(fb.camera_speedup > 1.0 && !fb.camera_fell_back);
    }
    return check_failures ? 1 : 0;
}
