/* A shading filter beside camera candidates (branch auto6; docs/algorithms.md, "a shading filter
 * beside a kept camera filter"): each configuration judged by the error the camera filters leave
 * with it (E_cam) in its time, a filter of another method than the camera filters' charged its
 * own per-sample sink, and decided against a brute-force evaluation of the model: each pixel's
 * variances from its samples, E_cam(c) as the sum over the pixels, T(c) and S(c) by their
 * formulas, the highest S kept (margin AUTO_OWN_SINK_MIN_ADVANTAGE for a filter with its own
 * sink, 4/3 for one sharing the camera filters' method). A family of frames whose light share
 * grows crosses the first threshold. */
#include <math.h>
#include <stdio.h>

#include "check.h"
#include "sample_moments.h"
#include "recon/auto_fallback.h"
#include "recon/filter_gain.h"

enum { N = 4, COUNT = 2 * N };

static const double LENS[COUNT] = {0.1, -0.1, 0.05, -0.05, 0.1, -0.1, 0.05, -0.05};
static const double VIS[COUNT] = {0.0, 0.3, 0.9, 0.6, 1.0, 0.1, 0.4, 0.7};
static const double TEX[COUNT] = {0.496, 0.504, 0.497, 0.503, 0.498, 0.502, 0.495, 0.505};
static const double ALBEDO = 0.5, BLURRED_FOOTPRINT = 20.0;
static const double RAYS = 4.0; /* rays per sample */

/* relMSE's weight of a pixel whose mean is m (core/image_metrics.c) */
static double weight(double m) { return 1.0 / (m * m + 0.01); }

/* The frame: a blurred pixel (footprint 20) whose samples see the lens (0.5 + lens) and a
 * penumbra of depth k (albedo 0.5 times visibility k VIS), and a sharp textured pixel no
 * shading filter reaches. Its totals into *t; the brute force's E_cam(none) and E_cam(direct)
 * into e[], with the neighbours' error grown by g (1 up to 16 spp). */
static void frame(double k, double g, FilterGainTotals *t, double e[2])
{
    FilterGainSample s[COUNT];
    double l[COUNT], kept[COUNT], tex[COUNT];
    for (int i = 0; i < COUNT; ++i) {
        float base = (float)(0.5 + LENS[i]), d = (float)(ALBEDO * k * VIS[i]);
        s[i] = (FilterGainSample){base + d, d, (float)ALBEDO, 0.0f, 0.0f};
        l[i] = (double)(base + d);
    }
    *t = (FilterGainTotals){0};
    filter_gain_add_pixel_sets(t, s, N, N, false, BLURRED_FOOTPRINT);
    /* the ideal shading filter gives every sample the pixel's demodulated light back */
    double sum_d = 0.0;
    for (int i = 0; i < COUNT; ++i) sum_d += (double)s[i].direct_filterable;
    double v = sum_d / (COUNT * ALBEDO);
    for (int i = 0; i < COUNT; ++i) kept[i] = l[i] - (double)s[i].direct_filterable + ALBEDO * v;
    for (int i = 0; i < COUNT; ++i) {
        tex[i] = (double)(float)TEX[i];
        s[i] = (FilterGainSample){(float)TEX[i], 0.0f, 0.0f, 0.0f, 0.0f};
    }
    filter_gain_add_pixel_sets(t, s, N, N, false, 1.0);
    double w1 = weight(sample_mean(l, COUNT)), w2 = weight(sample_mean(tex, COUNT));
    double sigma1 = sample_variance(l, COUNT), left1 = fmin(sample_variance(kept, COUNT), sigma1);
    double sigma2 = sample_variance(tex, COUNT), all = w1 * sigma1 + w2 * sigma2;
    /* of the blurred pixel's variance over F, its own samples' part (1 / F^2) stays and the
     * neighbours' part grows by g, as what the shading filter removes does (auto5) */
    double f = BLURRED_FOOTPRINT, own = (1.0 + (f - 1.0) * g) / (f * f);
    e[0] = (w1 * sigma1 * own + w2 * sigma2) / all;
    e[1] = (w1 * (left1 * own + g * (sigma1 - left1) / (AUTO_FILTER_FOOTPRINT * f)) + w2 * sigma2) / all;
}

int main(void)
{
    const int spp = 16;
    double t_s = RAYS * AUTO_RAY_US, n = spp;
    /* the time: the camera filter's sink and pass; a shading filter of its method adds its
     * pass, one of another method its own sink as well */
    AutoFallbackFrame shared = {.direct = true, .spp = spp, .cameras = 1};
    AutoFallbackFrame own = shared;
    own.direct_own_sink = true;
    double t_none = n * t_s + n * AUTO_SINK_US_PER_SAMPLE + AUTO_FILTER_US_PER_PIXEL;
    double t_shared = t_none + AUTO_FILTER_US_PER_PIXEL, t_own = t_shared + n * AUTO_SINK_US_PER_SAMPLE;
    AutoFallbackFrame kept = own;
    kept.cameras = 0, kept.others = 1, kept.camera = true; /* the camera filter as it runs */
    CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_DIRECT, &kept, t_s), t_own, 1e-12);
    CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_NONE, &kept, t_s), t_none, 1e-12);
    kept.direct_own_sink = false;
    CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_DIRECT, &kept, t_s), t_shared, 1e-12);
    /* two shading filters of one method beside the camera filter: one sink between them */
    AutoFallbackFrame two = {.direct = true, .indirect = true, .others = 1, .camera = true, .spp = spp,
                             .direct_own_sink = true, .indirect_own_sink = true};
    double t_two = t_none + 2 * AUTO_FILTER_US_PER_PIXEL + n * AUTO_SINK_US_PER_SAMPLE;
    CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_BOTH, &two, t_s), t_two + n * AUTO_SINK_US_PER_SAMPLE, 1e-12);
    two.shading_one_method = true;
    CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_BOTH, &two, t_s), t_two, 1e-12);
    CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_INDIRECT, &two, t_s), t_own, 1e-12);
    /* no camera filter running: the shading filter's sink is the frame's first */
    AutoFallbackFrame alone = {.direct = true, .spp = spp, .direct_own_sink = true};
    CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_DIRECT, &alone, t_s), n * t_s + n * AUTO_SINK_US_PER_SAMPLE + AUTO_FILTER_US_PER_PIXEL,
               1e-12);

    /* the decision over a family of frames, against the brute force */
    int dropped_own = 0, kept_own = 0, dropped_shared = 0, kept_shared = 0, differ = 0;
    for (int step = 0; step <= 40; ++step) {
        double k = 0.05 * step;
        FilterGainTotals t;
        double e[2];
        frame(k, 1.0, &t, e);
        double alpha = filter_gain_alpha(&t);
        CHECK_NEAR(filter_gain_camera_error_ratio_at(&t, FILTER_GAIN_NONE, AUTO_FILTER_FOOTPRINT, 1.0), e[0], 1e-6);
        CHECK_NEAR(filter_gain_camera_error_ratio_at(&t, FILTER_GAIN_DIRECT, AUTO_FILTER_FOOTPRINT, 1.0), e[1], 1e-6);
        double s_none = pow(e[0], -1.0 / alpha) * n * t_s / t_none;
        for (int which = 0; which < 2; ++which) {
            const AutoFallbackFrame *f = which ? &own : &shared;
            double s_direct = pow(e[1], -1.0 / alpha) * n * t_s / (which ? t_own : t_shared);
            double margin = which ? AUTO_OWN_SINK_MIN_ADVANTAGE : AUTO_FALLBACK_MIN_ADVANTAGE;
            FilterGainConfig want = s_none >= margin * s_direct && s_none > s_direct ? FILTER_GAIN_NONE : FILTER_GAIN_DIRECT;
            AutoFallback fb;
            auto_fallback_decide(&t, RAYS, f, &fb);
            CHECK(fb.camera_asked);
            CHECK_NEAR(fb.speedup[FILTER_GAIN_NONE], s_none, 1e-6 * s_none);
            CHECK_NEAR(fb.speedup[FILTER_GAIN_DIRECT], s_direct, 1e-6 * s_direct);
            CHECK_NEAR(fb.share[FILTER_GAIN_DIRECT], 1.0 - e[1] / e[0], 1e-6);
            /* the camera side sees the chosen configuration's own numbers (both speeds here
             * beat the shading alone, which has no camera gain: kept) */
            CHECK(!fb.camera_fell_back);
            CHECK(fb.chosen == want);
            CHECK_NEAR(fb.camera_error, e[want == FILTER_GAIN_DIRECT], 1e-6);
            CHECK_NEAR(fb.camera_speedup, want == FILTER_GAIN_DIRECT ? s_direct : s_none, 1e-6 * s_none);
            if (which) fb.chosen == FILTER_GAIN_NONE ? ++dropped_own : ++kept_own;
            else fb.chosen == FILTER_GAIN_NONE ? ++dropped_shared : ++kept_shared;
        }
        AutoFallback a, b;
        auto_fallback_decide(&t, RAYS, &own, &a);
        auto_fallback_decide(&t, RAYS, &shared, &b);
        differ += a.chosen != b.chosen;
    }
    /* past 16 spp the neighbours' part of E_cam grows by g (auto_fallback_neighbour_error) */
    {
        FilterGainTotals t;
        double e[2];
        frame(1.0, 1.0, &t, e);
        double alpha = filter_gain_alpha(&t), g = auto_fallback_neighbour_error(64, alpha);
        CHECK(g > 1.5);
        frame(1.0, g, &t, e);
        AutoFallbackFrame f64 = own;
        f64.spp = 64;
        AutoFallback fb;
        auto_fallback_decide(&t, RAYS, &f64, &fb);
        double t64_none = 64 * t_s + 64 * AUTO_SINK_US_PER_SAMPLE + AUTO_FILTER_US_PER_PIXEL;
        double t64_own = t64_none + 64 * AUTO_SINK_US_PER_SAMPLE + AUTO_FILTER_US_PER_PIXEL;
        CHECK_NEAR(fb.speedup[FILTER_GAIN_NONE], pow(e[0], -1.0 / alpha) * 64 * t_s / t64_none, 1e-6);
        CHECK_NEAR(fb.speedup[FILTER_GAIN_DIRECT], pow(e[1], -1.0 / alpha) * 64 * t_s / t64_own, 1e-6);
    }
    /* the family crosses the own sink's threshold, below which a filter sharing the camera
     * filters' method (cheaper, and with the wider margin) is still kept */
    CHECK(dropped_own > 0 && kept_own > 0 && kept_shared > 0 && differ == dropped_own - dropped_shared);
    printf("own sink: %d dropped, %d kept; shared: %d dropped, %d kept; %d differ\n", dropped_own, kept_own, dropped_shared,
           kept_shared, differ);
    return check_failures ? 1 : 0;
}
