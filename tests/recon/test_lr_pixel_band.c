/* LR's pixel band of still layers at the frame's sample count (lr_still_sigma_pixel_px,
 * docs/algorithms.md 8.36).
 *
 * The law: LR's 1/3 px from LR_PIXEL_BAND_SPP samples per pixel up, (1/3) (16 / spp)^(1/4)
 * below, never narrower as samples fall. It reaches only the filters of layers without motion:
 * a layer's filter with a motion range is the same whatever the still band. The reason for it, on a floor through focus (the
 * bench scenes' in-focus rows): each pixel's error against the box mean of 4096 samples of the
 * exact light field (lr_test_tilted_sample), summed over four seeds, at 4 and 8 spp, is lower
 * with the law's band than with the paper's 1/3 px; at 16 spp the law is the paper's band,
 * so the frame is the same to the bit. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "lr_scene.h"
#include "recon/lr/lr_reconstruct.h"

enum { PW = 48, PH = 48, EDGE = 8, TRUTH_SPP = 4096, SEEDS = 4 };
static const float TEXTURE_FREQ = 0.3f; /* radians per px: a period of 21 px */
static const float C_TOP_PX = -1.0f, C_BOTTOM_PX = 2.0f; /* the floor's slope runs through focus */

static float slope_per_row(void) { return (C_BOTTOM_PX - C_TOP_PX) / (float)PH; }

static void test_law(void)
{
    const float third = 1.0f / 3.0f;
    for (int spp = LR_PIXEL_BAND_SPP; spp <= 4096; spp *= 2) CHECK(lr_still_sigma_pixel_px(spp) == third);
    CHECK(lr_still_sigma_pixel_px(0) == third && lr_still_sigma_pixel_px(-3) == third);
    CHECK(fabsf(lr_still_sigma_pixel_px(8) - third * powf(2.0f, 0.25f)) < 1e-6f);
    CHECK(fabsf(lr_still_sigma_pixel_px(4) - third * sqrtf(2.0f)) < 1e-6f);
    for (int spp = 1; spp < 64; ++spp) CHECK(lr_still_sigma_pixel_px(spp) >= lr_still_sigma_pixel_px(spp + 1));
}

/* The still band widens the filter of a still layer near focus (clip X: its band is the one
 * that clips) and of no layer with motion, near focus or not. */
static void test_only_still_layers(void)
{
    LrFilterConfig paper = lr_filter_config_default(), law = paper;
    law.sigma_pixel_still_px = lr_still_sigma_pixel_px(8);
    const LrSlopes still = {0.0f, 1.0f, 0.0f, 0.0f};
    LrFilter a = lr_filter_make(&still, &paper), b = lr_filter_make(&still, &law);
    CHECK(a.clip_x == LR_CLIP_X && b.inv_sigma_x_px < 0.95f * a.inv_sigma_x_px);
    const LrSlopes moving[] = {{0.0f, 1.0f, 0.5f, 1.5f}, {3.0f, 4.0f, 20.0f, 24.0f}, {0.0f, 0.0f, -2.0f, -1.0f}};
    for (int i = 0; i < 3; ++i) {
        LrFilter m = lr_filter_make(&moving[i], &paper), n = lr_filter_make(&moving[i], &law);
        CHECK(m.clip_x == n.clip_x && m.clip_y == n.clip_y && m.clamped == n.clamped);
        const float mf[] = {m.inv_sigma_x_px, m.eta_px, m.xi_px, m.inv_sigma_u, m.inv_sigma_t, m.inv_sigma_y_px, m.rho_px,
                            m.inv_sigma_v, m.aperture_x_px, m.shutter_x_px, m.aperture_y_px};
        const float nf[] = {n.inv_sigma_x_px, n.eta_px, n.xi_px, n.inv_sigma_u, n.inv_sigma_t, n.inv_sigma_y_px, n.rho_px,
                            n.inv_sigma_v, n.aperture_x_px, n.shutter_x_px, n.aperture_y_px};
        CHECK(memcmp(mf, nf, sizeof mf) == 0);
    }
}

/* The box mean of each pixel over TRUTH_SPP samples (streamed). */
static void truth(double *rgb)
{
    unsigned seed = 4242;
    for (int py = 0; py < PH; ++py)
        for (int px = 0; px < PW; ++px) {
            double sum[3] = {0, 0, 0};
            for (int k = 0; k < TRUTH_SPP; ++k) {
                LrSample s;
                lr_test_tilted_sample(&s, px, py, C_TOP_PX, slope_per_row(), TEXTURE_FREQ, &seed);
                for (int c = 0; c < 3; ++c) sum[c] += s.L[c];
            }
            for (int c = 0; c < 3; ++c) rgb[((size_t)py * PW + px) * 3 + c] = sum[c] / TRUTH_SPP;
        }
}

/* LR's frame (lr_reconstruct_c) of spp samples per pixel of the floor, seed `seed`. */
static float *lr_frame(int spp, unsigned seed, const LrConfig *cfg)
{
    size_t n = (size_t)PW * PH * (size_t)spp;
    LrSample *s = malloc(sizeof(LrSample) * n);
    float *rgb = malloc(sizeof(float) * 3 * PW * PH);
    if (!s || !rgb) {
        free(s), free(rgb);
        return NULL;
    }
    for (int py = 0; py < PH; ++py)
        for (int px = 0; px < PW; ++px)
            for (int k = 0; k < spp; ++k)
                lr_test_tilted_sample(&s[((size_t)py * PW + px) * spp + k], px, py, C_TOP_PX, slope_per_row(), TEXTURE_FREQ,
                                      &seed);
    LrSamples img = lr_samples_split(PW, PH, spp, s);
    LrOutput out = {rgb, NULL, NULL, 0};
    lr_reconstruct_c(&img, cfg, &out);
    lr_samples_free(&img);
    free(s);
    CHECK(out.nonfinite == 0);
    return rgb;
}

/* relMSE (as `wedge compare` weighs it) of LR's frames against the truth, inside EDGE px,
 * summed over SEEDS seeds. */
static double lr_error(int spp, float sigma_pixel_px, const double *ref)
{
    LrConfig cfg = lr_config_default();
    cfg.filter.sigma_pixel_still_px = sigma_pixel_px;
    double err = 0.0;
    for (unsigned seed = 1; seed <= SEEDS; ++seed) {
        float *rgb = lr_frame(spp, 7919u * seed, &cfg);
        if (!rgb) return NAN;
        for (int py = EDGE; py < PH - EDGE; ++py)
            for (int px = EDGE; px < PW - EDGE; ++px)
                for (int c = 0; c < 3; ++c) {
                    size_t i = ((size_t)py * PW + px) * 3 + c;
                    double d = rgb[i] - ref[i];
                    err += d * d / (ref[i] * ref[i] + 0.01);
                }
        free(rgb);
    }
    return err / ((double)(PW - 2 * EDGE) * (PH - 2 * EDGE) * 3 * SEEDS);
}

static void test_floor_through_focus(void)
{
    double *ref = malloc(sizeof(double) * 3 * PW * PH);
    CHECK(ref != NULL);
    if (!ref) return;
    truth(ref);
    const float third = 1.0f / 3.0f;
    for (int spp = 4; spp <= 8; spp *= 2) {
        double paper = lr_error(spp, third, ref), law = lr_error(spp, lr_still_sigma_pixel_px(spp), ref);
        fprintf(stderr, "floor through focus, %d spp: relMSE %.4e with 1/3 px, %.4e with %.3f px (%.3fx)\n", spp, paper, law,
                lr_still_sigma_pixel_px(spp), law / paper);
        CHECK(law < 0.97 * paper);
    }
    /* at 16 spp the law is the paper's band: the same frame, bit for bit */
    LrConfig paper = lr_config_default(), law = paper;
    law.filter.sigma_pixel_still_px = lr_still_sigma_pixel_px(16);
    float *a = lr_frame(16, 5, &paper), *b = lr_frame(16, 5, &law);
    CHECK(a && b && memcmp(a, b, sizeof(float) * 3 * PW * PH) == 0);
    free(a), free(b), free(ref);
}

int main(void)
{
    test_law();
    test_only_still_layers();
    test_floor_through_focus();
    CHECK_DONE();
}
