/* auto's judgement of its camera filters against closed forms: the blur's area (the Minkowski
 * sum of pixel, circle of confusion and motion segment, src/recon/camera_gain.h), the real
 * filter's footprint, a pixel's (the harmonic mean of its samples'), the totals' camera sums (each pixel's variance over its footprint, mixed
 * pixels included), the camera error ratio, the decision on both sides of the margin with its
 * speed by the model's formula, the shading judged alone once the camera filters fall back,
 * non-finite samples, and the reason the choice carries (exact text). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "sample_moments.h"
#include "recon/auto_fallback.h"
#include "recon/camera_gain.h"
#include "recon/filter_gain.h"
#include "recon/gain_probe.h"
#include "recon/select.h"

enum { N = 4, COUNT = 2 * N };

/* A pixel of texture alone (no light a shading filter takes): L = x. */
static void texture_pixel(FilterGainSample *s, const double *x)
{
    for (int i = 0; i < COUNT; ++i) s[i] = (FilterGainSample){(float)x[i], 0.0f, 0.0f, 0.0f, 0.0f};
}

int main(void)
{
    /* the blur's area: a sharp, static sample covers its pixel; a disk of diameter c adds its
     * area and its sweep round the pixel's perimeter; a segment of length m the pixel's sweep
     * and the disk's */
    CHECK_NEAR(camera_blur_area_px(0.0, 0.0), 1.0, 0.0);
    CHECK_NEAR(camera_blur_area_px(4.0, 0.0), 1.0 + M_PI * 4.0 + 8.0, 1e-12);
    CHECK_NEAR(camera_blur_area_px(0.0, 10.0), 11.0, 1e-12);
    CHECK_NEAR(camera_blur_area_px(2.0, 10.0), 1.0 + M_PI + 4.0 + 10.0 + 20.0, 1e-12);
    CHECK_NEAR(camera_blur_area_px(NAN, -3.0), 1.0, 0.0); /* nothing to trust: the pixel alone */
    /* the real filter's footprint: 1 + efficiency (A - 1), between 1 and the cap */
    CHECK_NEAR(camera_footprint(11.0, 0.2, 50.0), 3.0, 1e-12);
    CHECK_NEAR(camera_footprint(1000.0, 0.2, 50.0), 50.0, 0.0);
    CHECK_NEAR(camera_footprint(0.5, 0.2, 50.0), 1.0, 0.0);
    /* a pixel's: the harmonic mean of its samples' (half sharp, half blurred by 50: ~2) */
    const float half_sharp[4] = {1.0f, 50.0f, 1.0f, 50.0f}, even[3] = {4.0f, 4.0f, 4.0f};
    CHECK_NEAR(camera_pixel_footprint(half_sharp, 4), 4.0 / (2.0 + 2.0 / 50.0), 1e-9);
    CHECK_NEAR(camera_pixel_footprint(even, 3), 4.0, 1e-12);
    CHECK_NEAR(camera_pixel_footprint(even, 0), 1.0, 0.0);

    /* the totals' camera sums: each pixel's weighted variance over its footprint; a mixed
     * pixel too (the camera filters take it); footprint 1 leaves them equal to the others */
    const double tex[COUNT] = {0.2, 0.8, 0.3, 0.7, 0.25, 0.75, 0.35, 0.65};
    const double edge[COUNT] = {0.1, 0.9, 0.1, 0.9, 0.9, 0.1, 0.9, 0.1};
    FilterGainSample s[COUNT];
    double w1 = 1.0 / (sample_mean(tex, COUNT) * sample_mean(tex, COUNT) + 0.01), w2 = 1.0 / (sample_mean(edge, COUNT) * sample_mean(edge, COUNT) + 0.01);
    double v1 = w1 * sample_variance(tex, COUNT), v2 = w2 * sample_variance(edge, COUNT);
    {
        FilterGainTotals t = {0};
        texture_pixel(s, tex);
        filter_gain_add_pixel_sets(&t, s, N, N, false, 10.0); /* blurred over ten pixels' worth */
        texture_pixel(s, edge);
        filter_gain_add_pixel_sets(&t, s, N, N, true, 1.0); /* a sharp, mixed pixel */
        CHECK_NEAR(t.left[FILTER_GAIN_NONE], v1 + v2, 1e-6); /* the samples are floats */
        CHECK_NEAR(t.camera_left[FILTER_GAIN_NONE], v1 / 10.0 + v2, 1e-6);
        CHECK_NEAR(t.camera_footprint_sum, 11.0, 1e-12);
        CHECK_NEAR(filter_gain_camera_error_ratio(&t, FILTER_GAIN_NONE, AUTO_FILTER_FOOTPRINT), (v1 / 10.0 + v2) / (v1 + v2), 1e-6);
        /* the old entry point is the footprint-1 case */
        FilterGainTotals u = {0}, v = {0};
        texture_pixel(s, tex);
        filter_gain_add_pixel(&u, s, N, false);
        filter_gain_add_pixel_sets(&v, s, N, N, false, 1.0);
        CHECK(memcmp(&u, &v, sizeof u) == 0);
        CHECK_NEAR(u.camera_left[FILTER_GAIN_NONE], u.left[FILTER_GAIN_NONE], 0.0);
        FilterGainTotals none = {0};
        CHECK_NEAR(filter_gain_camera_error_ratio(&none, FILTER_GAIN_NONE, AUTO_FILTER_FOOTPRINT), 1.0, 0.0);
    }
    /* a shading filter beside the camera filter: what it removes falls by its own footprint,
     * what it leaves by the camera's (a penumbra over an even albedo: all light) */
    {
        const double vis[COUNT] = {0.0, 0.3, 0.9, 0.6, 1.0, 0.1, 0.4, 0.7};
        for (int i = 0; i < COUNT; ++i) s[i] = (FilterGainSample){(float)(0.5 * vis[i]), (float)(0.5 * vis[i]), 0.5f, 0.0f, 0.0f};
        FilterGainTotals t = {0};
        filter_gain_add_pixel_sets(&t, s, N, N, false, 4.0);
        double all = t.left[FILTER_GAIN_NONE];
        CHECK_NEAR(t.left[FILTER_GAIN_DIRECT], 0.0, 1e-9 * all);
        CHECK_NEAR(filter_gain_camera_error_ratio(&t, FILTER_GAIN_DIRECT, 50.0), 1.0 / 4.0 / 50.0, 1e-6);
        CHECK_NEAR(filter_gain_camera_error_ratio(&t, FILTER_GAIN_NONE, 50.0), 1.0 / 4.0, 1e-9);
    }
    /* non-finite samples: recognised; a pixel with fewer samples in a set is read as it is */
    {
        FilterGainSample bad = {NAN, 0.0f, 0.0f, 0.0f, 0.0f}, inf = {1.0f, 0.0f, INFINITY, 0.0f, 0.0f}, ok = {1.0f, 0.5f, 0.5f, 0.0f, 0.0f};
        CHECK(!filter_gain_sample_finite(&bad) && !filter_gain_sample_finite(&inf) && filter_gain_sample_finite(&ok));
        FilterGainTotals t = {0};
        texture_pixel(s, tex);
        filter_gain_add_pixel_sets(&t, s + 1, N - 1, N, false, 1.0); /* set A lost its first sample */
        double x[COUNT - 1];
        for (int i = 0; i < COUNT - 1; ++i) x[i] = tex[i + 1];
        double m = 0.0, q = 0.0;
        for (int i = 0; i < COUNT - 1; ++i) m += x[i];
        m /= COUNT - 1;
        for (int i = 0; i < COUNT - 1; ++i) q += (x[i] - m) * (x[i] - m);
        CHECK_NEAR(t.left[FILTER_GAIN_NONE], q / (COUNT - 2) / (m * m + 0.01), 1e-6);
        CHECK(t.pixels == 1 && t.set_spp == N - 1);
        FilterGainTotals u = {0};
        filter_gain_add_pixel_sets(&u, s, 1, N, false, 1.0); /* one sample left in a set: dropped */
        CHECK(u.pixels == 0);
    }

    /* the decision, motion alone: a frame whose variance the camera footprint divides by 40
     * keeps the filter at the formula's speed; footprint 1 leaves it to Monte Carlo */
    {
        FilterGainTotals t = {0};
        texture_pixel(s, tex);
        filter_gain_add_pixel_sets(&t, s, N, N, false, 40.0);
        AutoFallbackFrame f = {false, false, 0, false, 16, 1, false, false, false};
        AutoFallback fb;
        auto_fallback_decide(&t, 2.0, &f, &fb);
        double alpha = filter_gain_alpha(&t), t_s = 2.0 * AUTO_RAY_US;
        double t_kept = 16 * t_s + 16 * AUTO_SINK_US_PER_SAMPLE + AUTO_FILTER_US_PER_PIXEL;
        CHECK_NEAR(auto_fallback_time_us(FILTER_GAIN_NONE, &f, t_s), t_kept, 1e-9);
        CHECK(fb.camera_asked && !fb.camera_fell_back);
        CHECK_NEAR(fb.camera_error, 1.0 / 40.0, 1e-9);
        CHECK_NEAR(fb.camera_footprint, 40.0, 1e-12);
        CHECK_NEAR(fb.camera_speedup, pow(1.0 / 40.0, -1.0 / alpha) * 16 * t_s / t_kept, 1e-9);
        CHECK_NEAR(fb.camera_speedup_without, 1.0, 1e-12);
        FilterGainTotals u = {0};
        filter_gain_add_pixel_sets(&u, s, N, N, false, 1.0);
        auto_fallback_decide(&u, 2.0, &f, &fb);
        CHECK(fb.camera_asked && fb.camera_fell_back);
        CHECK_NEAR(fb.camera_error, 1.0, 1e-12);
        CHECK_NEAR(fb.camera_speedup, 16 * t_s / t_kept, 1e-9); /* no gain, only cost */
        /* the margin: a footprint whose predicted speed is just above 1 / margin of Monte
         * Carlo's stays, just below falls back */
        double kept_speed[2];
        double footprints[2] = {1.0, 1.0};
        for (int side = 0; side < 2; ++side) {
            /* solve E^(-1/alpha) T0 / T = 1 / margin (+-1%) for E = 1 / F */
            double target = (side ? 1.01 : 0.99) / AUTO_CAMERA_MIN_ADVANTAGE;
            FilterGainTotals v = {0};
            filter_gain_add_pixel_sets(&v, s, N, N, false, 1.0);
            double a = filter_gain_alpha(&v);
            footprints[side] = pow(target * t_kept / (16 * t_s), a);
            FilterGainTotals x = {0};
            filter_gain_add_pixel_sets(&x, s, N, N, false, footprints[side]);
            auto_fallback_decide(&x, 2.0, &f, &fb);
            kept_speed[side] = fb.camera_speedup;
            CHECK(fb.camera_fell_back == (side == 0));
        }
        CHECK_NEAR(kept_speed[0], 0.99 / AUTO_CAMERA_MIN_ADVANTAGE, 1e-6);
        /* within the model's error a camera filter predicted 0.8x Monte Carlo's speed stays */
        {
            FilterGainTotals v = {0};
            filter_gain_add_pixel_sets(&v, s, N, N, false, 1.0);
            FilterGainTotals x = {0};
            filter_gain_add_pixel_sets(&x, s, N, N, false, pow(0.8 * t_kept / (16 * t_s), filter_gain_alpha(&v)));
            auto_fallback_decide(&x, 2.0, &f, &fb);
            CHECK_NEAR(fb.camera_speedup, 0.8, 1e-6);
            CHECK(!fb.camera_fell_back);
        }
        CHECK_NEAR(kept_speed[1], 1.01 / AUTO_CAMERA_MIN_ADVANTAGE, 1e-6);
        /* no camera candidate: nothing judged on the camera side */
        AutoFallbackFrame g = {false, false, 1, true, 16, 0, false, false, false};
        auto_fallback_decide(&t, 2.0, &g, &fb);
        CHECK(!fb.camera_asked && !fb.camera_fell_back);
    }
    /* with a shading candidate: the camera filters kept, the shading is decided as before this
     * judgement (beside a camera filter); fallen back, it is decided as in a frame without one.
     * At 2 spp, where a camera filter with nothing to average costs more than the margin beside
     * the shading filter (at 16 spp the shared sink makes it 1.24x: kept) */
    {
        const double vis[COUNT] = {0.0, 0.3, 0.9, 0.6, 1.0, 0.1, 0.4, 0.7};
        FilterGainTotals t = {0};
        for (int i = 0; i < COUNT; ++i) s[i] = (FilterGainSample){(float)(0.5 * vis[i]), (float)(0.5 * vis[i]), 0.5f, 0.0f, 0.0f};
        filter_gain_add_pixel_sets(&t, s, N, N, false, 1.0); /* a penumbra, nothing blurred */
        AutoFallbackFrame f = {true, false, 0, false, 2, 1, false, false, false}, beside = {true, false, 1, true, 2, 0, false, false, false},
                          alone = {true, false, 0, false, 2, 0, false, false, false};
        AutoFallback fb, want_beside, want_alone;
        auto_fallback_decide(&t, 2.0, &f, &fb);
        auto_fallback_decide(&t, 2.0, &alone, &want_alone);
        auto_fallback_decide(&t, 2.0, &beside, &want_beside);
        CHECK(fb.camera_fell_back);
        CHECK(fb.chosen == want_alone.chosen && fb.chosen == FILTER_GAIN_DIRECT);
        CHECK_NEAR(fb.speedup[FILTER_GAIN_DIRECT], want_alone.speedup[FILTER_GAIN_DIRECT], 1e-12);
        CHECK_NEAR(fb.camera_speedup_without, want_alone.speedup[FILTER_GAIN_DIRECT], 1e-12);
        /* the same frame blurred over 40 pixels' worth: the camera filters stay, and each
         * shading configuration beside them is judged by the error they leave with it (E_cam)
         * in its time (branch auto6; test_auto_fallback_beside.c for the decision) */
        FilterGainTotals u = {0};
        filter_gain_add_pixel_sets(&u, s, N, N, false, 40.0);
        auto_fallback_decide(&u, 2.0, &f, &fb);
        CHECK(!fb.camera_fell_back);
        double t_s = 2.0 * AUTO_RAY_US, a = filter_gain_alpha(&u);
        for (int c = FILTER_GAIN_NONE; c <= FILTER_GAIN_DIRECT; ++c) {
            double e = filter_gain_camera_error_ratio_at(&u, (FilterGainConfig)c, AUTO_FILTER_FOOTPRINT, 1.0);
            CHECK_NEAR(fb.speedup[c], pow(e, -1.0 / a) * 2 * t_s / auto_fallback_time_us((FilterGainConfig)c, &beside, t_s), 1e-9);
        }
        CHECK_NEAR(fb.camera_speedup, fb.speedup[fb.chosen], 1e-12);
        /* named explicitly, the camera filter's footprint is not measured: the old rule */
        auto_fallback_decide(&u, 2.0, &beside, &want_beside);
        CHECK(fb.speedup[FILTER_GAIN_DIRECT] != want_beside.speedup[FILTER_GAIN_DIRECT]);
    }
    /* the choice: auto's lr for motion (a blur above its threshold), judged unable to pay,
     * becomes none with the reason */
    {
        ReconChoice c;
        recon_select_budget(EFFECT_BIT(EFFECT_MOTION), "auto", 4.0f, 8, &c);
        CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "lr");
        CHECK(recon_select_wants_fallback(&c));
        AutoFallbackFrame f = recon_select_fallback_frame(&c, 8);
        CHECK(f.cameras == 1 && f.others == 0 && !f.camera && !f.direct && !f.indirect);
        CameraBlurKinds k = recon_select_fallback_blur(&c);
        CHECK(k.motion && !k.defocus);
        AutoFallback fb = {0};
        fb.camera_asked = fb.camera_fell_back = true;
        fb.camera_speedup = 0.53, fb.camera_speedup_without = 1.0, fb.camera_error = 0.66, fb.camera_footprint = 1.9, fb.alpha = 1.94;
        recon_select_fallback(&c, &fb);
        CHECK_STR(recon_choice_name(&c, EFFECT_MOTION), "none");
        CHECK(c.fell_back == EFFECT_BIT(EFFECT_MOTION));
        CHECK_STR(c.reason[EFFECT_MOTION], "none, auto fell back to Monte Carlo: lr predicted 0.53x its equal-error speed, 1.00x "
                                           "without (error 0.66x at equal spp, footprint 1.9 pixels, alpha 1.94, gain probe)");
        /* an explicit camera filter: no camera candidate (the probe could not tell its gain) */
        ReconChoice d;
        recon_select_budget(EFFECT_BIT(EFFECT_MOTION) | EFFECT_BIT(EFFECT_DEFOCUS), "motion=lr", 1.0f, 8, &d);
        CHECK(recon_select_fallback_frame(&d, 8).cameras == 0);
        CHECK(!recon_select_wants_fallback(&d));
    }
    {
        /* MAAF's lens filter: its width from the pixel's sharpest slope. A defocused fence (slope
         * 20 px) over a background nearly in focus (0.5): every sample blurred by the background's
         * circle (diameter 1), not the fence's; a miss is skipped; both signs (the focal plane
         * inside the pixel): no blur; no hit: none */
        const float fence[4] = {20.0f, 0.5f, NAN, 0.75f}, behind[2] = {-4.0f, -2.0f}, straddle[2] = {3.0f, -0.25f};
        const float misses[2] = {NAN, NAN};
        CHECK_NEAR(camera_lens_sharpest_diameter_px(fence, 4), 1.0, 0.0);
        CHECK_NEAR(camera_lens_sharpest_diameter_px(behind, 2), 4.0, 0.0);
        CHECK_NEAR(camera_lens_sharpest_diameter_px(straddle, 2), 0.0, 0.0);
        CHECK_NEAR(camera_lens_sharpest_diameter_px(misses, 2), 0.0, 0.0);
        /* the pixel's footprint: every sample (the miss too) at A(1, 0), against the per-sample
         * rule's harmonic mean, which the fence's 50 would lift */
        const float still[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        double sharp = (float)camera_footprint(camera_blur_area_px(1.0, 0.0), 0.2, 50.0);
        CHECK_NEAR(camera_pixel_footprint_sharpest_lens(fence, still, 4, 0.2, 50.0), sharp, 1e-12);
        CHECK_NEAR(sharp, 1.0 + 0.2 * (M_PI / 4.0 + 2.0), 1e-6);
        /* with motion each sample keeps its own segment: harmonic mean of F(A(4, 0)), F(A(4, 10)) */
        const float moving[2] = {0.0f, 10.0f};
        double f0 = (float)camera_footprint(camera_blur_area_px(4.0, 0.0), 0.2, 50.0);
        double f1 = (float)camera_footprint(camera_blur_area_px(4.0, 10.0), 0.2, 50.0);
        CHECK_NEAR(camera_pixel_footprint_sharpest_lens(behind, moving, 2, 0.2, 50.0), 2.0 / (1.0 / f0 + 1.0 / f1), 1e-12);
        CHECK_NEAR(camera_pixel_footprint_sharpest_lens(straddle, still, 2, 0.2, 50.0), 1.0, 0.0);
        CHECK_NEAR(camera_pixel_footprint_sharpest_lens(fence, still, 0, 0.2, 50.0), 1.0, 0.0);
        /* the probe reads it for auto's maaf lens filter only (the others, per sample) */
        ReconChoice c;
        recon_select_budget(EFFECT_BIT(EFFECT_DEFOCUS), "auto", 1.0f, 8, &c);
        CHECK_STR(recon_choice_name(&c, EFFECT_DEFOCUS), "maaf");
        CameraBlurKinds k = recon_gain_probe_blur(&c);
        CHECK(k.defocus && !k.motion && k.sharpest_lens);
        recon_select_budget(EFFECT_BIT(EFFECT_DEFOCUS) | EFFECT_BIT(EFFECT_MOTION), "auto", 1.0f, 8, &c);
        CHECK(strcmp(recon_choice_name(&c, EFFECT_DEFOCUS), "maaf") != 0); /* aaf beside motion */
        k = recon_gain_probe_blur(&c); /* the motion, under lr's blur threshold, is Monte Carlo's: no candidate */
        CHECK(k.defocus && !k.motion && !k.sharpest_lens);
    }
    return check_failures ? 1 : 0;
}
