/* The filter-gain estimate (src/recon/filter_gain.h) and auto's fallback decision
 * (src/recon/auto_fallback.h) on synthetic pixels with closed forms: all-or-nothing
 * visibility leaves nothing for a light filter (share 0, no gain), a penumbra over an even
 * albedo is all light (share 1, the gain the footprint implies), a texture orthogonal to the
 * penumbra splits the variance as the two parts' variances say, mixed pixels keep theirs (a
 * split one all but its first surface's light), the
 * pixels are weighted as relMSE weighs them, and the convergence exponent comes from the two
 * sets. The decision then keeps a filter exactly when its predicted equal-error speed is the
 * highest, with the speed by the model's formula. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "sample_moments.h"
#include "recon/auto_fallback.h"
#include "recon/filter_gain.h"

enum { N = 4, COUNT = 2 * N };

/* Direct light only: L = texture + albedo * visibility * light, D = albedo * visibility * light. */
static void direct_pixel(FilterGainSample *s, const double *texture, const double *albedo, const double *vis)
{
    for (int i = 0; i < COUNT; ++i) {
        double d = albedo[i] * vis[i];
        s[i] = (FilterGainSample){(float)(texture[i] + d), (float)d, (float)albedo[i], 0.0f, 0.0f};
    }
}

int main(void)
{
    FilterGainSample s[COUNT];
    const double zero[COUNT] = {0}, half[COUNT] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5};

    /* all-or-nothing visibility per pixel under a textured albedo: the light's demodulated value
     * is the same for every sample, an ideal filter changes nothing */
    {
        FilterGainTotals t = {0};
        const double checks[COUNT] = {0.2, 0.8, 0.2, 0.8, 0.8, 0.2, 0.8, 0.2}, lit[COUNT] = {1, 1, 1, 1, 1, 1, 1, 1};
        direct_pixel(s, zero, checks, lit);
        filter_gain_add_pixel(&t, s, N, false);
        direct_pixel(s, zero, checks, zero); /* in full shadow */
        filter_gain_add_pixel(&t, s, N, false);
        CHECK(t.left[FILTER_GAIN_NONE] > 0.0);
        CHECK_NEAR(filter_gain_share(&t, FILTER_GAIN_DIRECT), 0.0, 1e-12);
        CHECK_NEAR(filter_gain_error_ratio(&t, FILTER_GAIN_DIRECT, 16.0), 1.0, 1e-12);
        CHECK_NEAR(filter_gain_share(&t, FILTER_GAIN_INDIRECT), 0.0, 1e-12); /* no indirect light at all */
        CHECK(t.pixels == 2 && t.pixels_filterable == 2);
    }
    /* a penumbra across an even albedo: all the variance is the light's; the filter's error is
     * 1 / footprint of Monte Carlo's */
    {
        FilterGainTotals t = {0};
        const double vis[COUNT] = {0.0, 0.3, 0.9, 0.6, 1.0, 0.1, 0.4, 0.7};
        direct_pixel(s, zero, half, vis);
        filter_gain_add_pixel(&t, s, N, false);
        CHECK_NEAR(filter_gain_share(&t, FILTER_GAIN_DIRECT), 1.0, 1e-9);
        CHECK_NEAR(filter_gain_error_ratio(&t, FILTER_GAIN_DIRECT, 16.0), 1.0 / 16.0, 1e-9);
        CHECK_NEAR(filter_gain_error_ratio(&t, FILTER_GAIN_BOTH, 4.0), 0.25, 1e-9);
        /* the same pixel mixed: the filters pass it through */
        FilterGainTotals m = {0};
        filter_gain_add_pixel(&m, s, N, true);
        CHECK_NEAR(filter_gain_share(&m, FILTER_GAIN_DIRECT), 0.0, 1e-12);
        CHECK(m.pixels_filterable == 0);
    }
    /* a split pixel (docs/algorithms.md 4.6): the filter takes the first surface's samples
     * (their light becomes their albedo times the first surface's demodulated mean), the
     * other surface's samples keep their radiance; a light the frame does not split passes
     * through whole */
    {
        const double vis[COUNT] = {0.0, 0.3, 0.9, 0.6, 1.0, 0.1, 0.4, 0.7};
        const bool off[COUNT] = {false, true, false, true, false, true, false, true};
        double want[COUNT], v_first = 0.0, a_first = 0.0, l[COUNT];
        direct_pixel(s, zero, half, vis);
        for (int i = 0; i < COUNT; ++i)
            if (!off[i]) v_first += s[i].direct_filterable, a_first += s[i].albedo_direct;
        for (int i = 0; i < COUNT; ++i) {
            l[i] = s[i].radiance;
            want[i] = off[i] ? l[i] : half[i] * (v_first / a_first);
        }
        double w = 1.0 / (sample_mean(l, COUNT) * sample_mean(l, COUNT) + 0.01);
        FilterGainSample split[COUNT], whole[COUNT];
        memcpy(split, s, sizeof split), memcpy(whole, s, sizeof whole);
        FilterGainTotals t = {0}, u = {0};
        filter_gain_split_pixel(split, off, COUNT, true, true);
        filter_gain_add_pixel(&t, split, N, false);
        CHECK_NEAR(t.left[FILTER_GAIN_NONE], w * sample_variance(l, COUNT), 1e-6);
        CHECK_NEAR(t.left[FILTER_GAIN_DIRECT], w * sample_variance(want, COUNT), 1e-6);
        CHECK(t.left[FILTER_GAIN_DIRECT] > 0.1 * t.left[FILTER_GAIN_NONE]); /* the others' noise stays */
        filter_gain_split_pixel(whole, off, COUNT, false, true);
        filter_gain_add_pixel(&u, whole, N, false);
        CHECK_NEAR(filter_gain_share(&u, FILTER_GAIN_DIRECT), 0.0, 1e-12);
    }
    /* a texture orthogonal to the penumbra (zero covariance over the samples): the share is the
     * light's variance over the sum, weighted by relMSE's 1 / (mean^2 + 0.01) */
    {
        FilterGainTotals t = {0};
        const double tex[COUNT] = {0.1, -0.1, 0.1, -0.1, 0.1, -0.1, 0.1, -0.1};
        const double vis[COUNT] = {1, 1, 0, 0, 1, 1, 0, 0};
        double l[COUNT], d[COUNT];
        for (int i = 0; i < COUNT; ++i) d[i] = 0.5 * vis[i], l[i] = 0.3 + tex[i] + d[i];
        double base[COUNT];
        for (int i = 0; i < COUNT; ++i) base[i] = 0.3 + tex[i];
        direct_pixel(s, base, half, vis);
        filter_gain_add_pixel(&t, s, N, false);
        double want_share = sample_variance(d, COUNT) / sample_variance(l, COUNT);
        CHECK_NEAR(sample_variance(l, COUNT), sample_variance(d, COUNT) + sample_variance(base, COUNT), 1e-12); /* orthogonal indeed */
        CHECK_NEAR(filter_gain_share(&t, FILTER_GAIN_DIRECT), want_share, 1e-6);
        double w = 1.0 / (sample_mean(l, COUNT) * sample_mean(l, COUNT) + 0.01);
        CHECK_NEAR(t.left[FILTER_GAIN_NONE], w * sample_variance(l, COUNT), 1e-6);
        CHECK_NEAR(t.left[FILTER_GAIN_DIRECT], w * sample_variance(base, COUNT), 1e-6);
        /* a second, brighter pixel of pure texture weighs in by its relMSE weight */
        const double tex2[COUNT] = {2.0, 3.0, 2.0, 3.0, 2.0, 3.0, 2.0, 3.0};
        direct_pixel(s, tex2, half, zero);
        filter_gain_add_pixel(&t, s, N, false);
        double w2 = 1.0 / (2.5 * 2.5 + 0.01);
        double removed = w * sample_variance(d, COUNT), all = w * sample_variance(l, COUNT) + w2 * sample_variance(tex2, COUNT);
        CHECK_NEAR(filter_gain_share(&t, FILTER_GAIN_DIRECT), removed / all, 1e-6);
    }
    /* indirect light alone, demodulated by its own albedo; BOTH removes the two together */
    {
        FilterGainTotals t = {0};
        const double ind[COUNT] = {0.0, 0.4, 0.1, 0.5, 0.2, 0.3, 0.6, 0.7};
        for (int i = 0; i < COUNT; ++i) s[i] = (FilterGainSample){(float)(0.25 + 0.8 * ind[i]), 0.25f, 0.5f, (float)(0.8 * ind[i]), 0.8f};
        filter_gain_add_pixel(&t, s, N, false);
        CHECK_NEAR(filter_gain_share(&t, FILTER_GAIN_DIRECT), 0.0, 1e-9); /* an even direct light */
        CHECK_NEAR(filter_gain_share(&t, FILTER_GAIN_INDIRECT), 1.0, 1e-6);
        CHECK_NEAR(filter_gain_share(&t, FILTER_GAIN_BOTH), 1.0, 1e-6);
    }
    /* the convergence exponent: var(mean of n) = sigma^2 n^-alpha from the two sets */
    {
        FilterGainTotals t = {0};
        const double set_ab[COUNT] = {0.0, 1.0, 0.0, 1.0, 0.25, 1.25, 0.25, 1.25}; /* means 0.5 and 0.75 */
        direct_pixel(s, set_ab, half, zero);
        filter_gain_add_pixel(&t, s, N, false);
        double w = 1.0 / (sample_mean(set_ab, COUNT) * sample_mean(set_ab, COUNT) + 0.01);
        CHECK_NEAR(t.var_mean_n, w * 0.5 * 0.25 * 0.25, 1e-9);
        double alpha = log(sample_variance(set_ab, COUNT) / (0.5 * 0.25 * 0.25)) / log((double)N);
        CHECK(alpha > FILTER_GAIN_ALPHA_MIN && alpha < FILTER_GAIN_ALPHA_MAX);
        CHECK_NEAR(filter_gain_alpha(&t), alpha, 1e-6);
        FilterGainTotals none = {0};
        CHECK_NEAR(filter_gain_alpha(&none), 1.0, 0.0); /* nothing measured: independent samples */
        /* equal set means: no measurable error of the mean, the exponent at its cap */
        const double same[COUNT] = {0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0};
        FilterGainTotals u = {0};
        direct_pixel(s, same, half, zero);
        filter_gain_add_pixel(&u, s, N, false);
        CHECK_NEAR(filter_gain_alpha(&u), FILTER_GAIN_ALPHA_MAX, 0.0);
    }

    /* the decision: no share, Monte Carlo; all of it, the filter, at the model's speed */
    {
        FilterGainTotals t = {0};
        const double checks[COUNT] = {0.2, 0.8, 0.2, 0.8, 0.8, 0.2, 0.8, 0.2}, lit[COUNT] = {1, 1, 1, 1, 1, 1, 1, 1};
        direct_pixel(s, zero, checks, lit);
        filter_gain_add_pixel(&t, s, N, false);
        AutoFallbackFrame f = {true, false, 0, false, 16, 0, false, false, false};
        AutoFallback fb;
        auto_fallback_decide(&t, 2.0, &f, &fb);
        CHECK(fb.asked == FILTER_GAIN_DIRECT && fb.chosen == FILTER_GAIN_NONE);
        CHECK_NEAR(fb.speedup[FILTER_GAIN_NONE], 1.0, 1e-12);
        double t_s = 2.0 * AUTO_RAY_US;
        double t_f = 16 * t_s + 16 * AUTO_SINK_US_PER_SAMPLE + AUTO_FILTER_US_PER_PIXEL;
        CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_DIRECT, &f, t_s), t_f, 1e-9);
        CHECK_NEAR(fb.speedup[FILTER_GAIN_DIRECT], 16 * t_s / t_f, 1e-9); /* no gain, only cost */
        /* beside a camera filter that runs anyway, the shading filter costs its pass alone */
        AutoFallbackFrame g = {true, false, 1, true, 16, 0, false, false, false};
        CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_NONE, &g, t_s), 16 * t_s + 16 * AUTO_SINK_US_PER_SAMPLE + AUTO_FILTER_US_PER_PIXEL, 1e-9);
        auto_fallback_decide(&t, 2.0, &g, &fb);
        /* ... which at 16 spp is less than AUTO_FALLBACK_MIN_ADVANTAGE: auto's choice stands */
        CHECK(fb.speedup[FILTER_GAIN_NONE] > fb.speedup[FILTER_GAIN_DIRECT]);
        CHECK(fb.speedup[FILTER_GAIN_NONE] < AUTO_FALLBACK_MIN_ADVANTAGE * fb.speedup[FILTER_GAIN_DIRECT]);
        CHECK(fb.chosen == FILTER_GAIN_DIRECT);
        /* at 2 spp the pass costs more than the margin: Monte Carlo */
        g.spp = 2;
        auto_fallback_decide(&t, 2.0, &g, &fb);
        CHECK(fb.speedup[FILTER_GAIN_NONE] > AUTO_FALLBACK_MIN_ADVANTAGE * fb.speedup[FILTER_GAIN_DIRECT]);
        CHECK(fb.chosen == FILTER_GAIN_NONE);
    }
    {
        FilterGainTotals t = {0};
        const double vis[COUNT] = {0.0, 0.3, 0.9, 0.6, 1.0, 0.1, 0.4, 0.7};
        direct_pixel(s, zero, half, vis);
        filter_gain_add_pixel(&t, s, N, false);
        AutoFallbackFrame f = {true, false, 0, false, 16, 0, false, false, false};
        AutoFallback fb;
        auto_fallback_decide(&t, 2.0, &f, &fb);
        CHECK(fb.chosen == FILTER_GAIN_DIRECT);
        double alpha = filter_gain_alpha(&t), t_s = 2.0 * AUTO_RAY_US;
        double want = pow(1.0 / AUTO_FILTER_FOOTPRINT, -1.0 / alpha) * 16 * t_s / auto_fallback_time_us(FILTER_GAIN_DIRECT, &f, t_s);
        CHECK_NEAR(fb.speedup[FILTER_GAIN_DIRECT], want, 1e-9);
        CHECK(fb.speedup[FILTER_GAIN_DIRECT] > 1.0);
        /* the same frame with no candidate (nothing auto chose): nothing to decide */
        AutoFallbackFrame none = {false, false, 0, false, 16, 0, false, false, false};
        auto_fallback_decide(&t, 2.0, &none, &fb);
        CHECK(fb.asked == FILTER_GAIN_NONE && fb.chosen == FILTER_GAIN_NONE);
    }
    /* two candidates: a bounce that pays and a shadow that does not, each judged */
    {
        FilterGainTotals t = {0};
        const double ind[COUNT] = {0.0, 0.4, 0.1, 0.5, 0.2, 0.3, 0.6, 0.7};
        for (int i = 0; i < COUNT; ++i) s[i] = (FilterGainSample){(float)(0.25 + 0.8 * ind[i]), 0.25f, 0.5f, (float)(0.8 * ind[i]), 0.8f};
        filter_gain_add_pixel(&t, s, N, false);
        AutoFallbackFrame f = {true, true, 0, false, 2, 0, false, false, false};
        AutoFallback fb;
        auto_fallback_decide(&t, 2.0, &f, &fb);
        CHECK(fb.asked == FILTER_GAIN_BOTH && fb.chosen == FILTER_GAIN_INDIRECT);
        CHECK(fb.speedup[FILTER_GAIN_INDIRECT] > fb.speedup[FILTER_GAIN_BOTH]);
        CHECK(fb.speedup[FILTER_GAIN_INDIRECT] > fb.speedup[FILTER_GAIN_NONE]);
    }
    /* beside a camera filter: the share is the variance in the pixels the shading filters may
     * touch (the lens's variance there is the camera filter's), split as the ideal shares are */
    {
        FilterGainTotals t = {0};
        const double vis[COUNT] = {0.0, 0.3, 0.9, 0.6, 1.0, 0.1, 0.4, 0.7};
        const double lens[COUNT] = {0.1, -0.1, 0.1, -0.1, 0.1, -0.1, 0.1, -0.1};
        double base[COUNT];
        for (int i = 0; i < COUNT; ++i) base[i] = 0.5 + lens[i];
        direct_pixel(s, base, half, vis); /* light and lens */
        filter_gain_add_pixel(&t, s, N, false);
        double l[COUNT];
        for (int i = 0; i < COUNT; ++i) l[i] = base[i] + 0.5 * vis[i];
        double w1 = 1.0 / (sample_mean(l, COUNT) * sample_mean(l, COUNT) + 0.01), filterable = w1 * sample_variance(l, COUNT);
        direct_pixel(s, zero, half, vis); /* a mixed pixel: the shading filters pass it */
        filter_gain_add_pixel(&t, s, N, true);
        double all = t.left[FILTER_GAIN_NONE];
        CHECK_NEAR(filter_gain_filterable_share(&t), filterable / all, 1e-6);
        AutoFallbackFrame f = {true, false, 1, true, 16, 0, false, false, false};
        AutoFallback fb;
        auto_fallback_decide(&t, 2.0, &f, &fb);
        CHECK_NEAR(fb.share[FILTER_GAIN_DIRECT], filterable / all, 1e-6);
        CHECK(fb.share[FILTER_GAIN_DIRECT] > filter_gain_share(&t, FILTER_GAIN_DIRECT)); /* not the ideal share */
        double t_s = 2.0 * AUTO_RAY_US, q = filterable / all;
        double want = pow((1.0 - q) + q / AUTO_FILTER_FOOTPRINT, -1.0 / filter_gain_alpha(&t)) * 16 * t_s /
                      auto_fallback_time_us(FILTER_GAIN_DIRECT, &f, t_s);
        CHECK_NEAR(fb.speedup[FILTER_GAIN_DIRECT], want, 1e-6);
        /* no light variance at all: nothing for the shading filter, whatever the lens does */
        FilterGainTotals u = {0};
        direct_pixel(s, base, half, half);
        filter_gain_add_pixel(&u, s, N, false);
        f.spp = 2; /* where the pass's cost beats the margin */
        auto_fallback_decide(&u, 2.0, &f, &fb);
        CHECK_NEAR(fb.share[FILTER_GAIN_DIRECT], 0.0, 1e-12);
        CHECK(fb.chosen == FILTER_GAIN_NONE);
    }
    return check_failures ? 1 : 0;
}
