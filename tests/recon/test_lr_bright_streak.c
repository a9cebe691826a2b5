/* LR on a short bright streak (docs/algorithms.md 8.49, issue 17): a bright layer's screen
 * filter (8.24's clamp, shrunk with the layer's blur radius) must not put its light past the
 * blur's own support, where the reference is the dark background's; and the clamp's law. */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "lr_scene.h"
#include "recon/lr/lr_reconstruct.h"

enum { W = 48, H = 48, SPP = 16 };
static const float CX = 24.0f, CY = 24.0f, L_E = 300.0f;

/* A disk light (radius 6 px, radiance 300) moving 3 px at -60 degrees over the shutter (as the
 * moving disk light of tools/scene-lottery seed 34), through a pinhole, over misses, 16 spp:
 * its image is the disk swept along a 3-px segment, box-filtered over each pixel, so a pixel
 * whose centre is more than R + sqrt(2)/2 px from the segment gets no light; Algorithm 2's
 * nearest-pixel steps along a diagonal may place a tap up to another sqrt(2)/2 px off, so from
 * R + sqrt(2) = 7.4 px out LR's filter should put nothing but its Gaussian's tails. With the
 * bright clamp at the pixel box's std (8.49: R = 1.5 px) the screen filter has no Gaussian
 * beyond the pixel's binning: under 0.1% of the light lands from 7.5 px out; with 8.24's 1-px clamp,
 * 0.3% (and 4.5% from 7 px out). The time average keeps the disk's energy. */
static double moving_halo(float bright_clamp_min_px, double *energy)
{
    const float R_M = 6.0f, D_M = 3.0f;
    LrSample *s = malloc(sizeof(LrSample) * W * H * SPP);
    float *rgb = malloc(sizeof(float) * 3 * W * H);
    CHECK(s && rgb);
    const float ax = 0.5f, ay = -0.8660254f; /* the motion's direction, -60 degrees */
    LrTestLayer layers[2] = {{10.0f, 0.0f, {D_M * ax, D_M * ay}, CX, CY, R_M, 0.0f}, {20.0f, 0.0f, {0.0f, 0.0f}, 0, 0, 0, 0.0f}};
    lr_test_scene(s, W, H, SPP, layers, 2, 5);
    for (int i = 0; i < W * H * SPP; ++i) {
        bool light = s[i].depth == layers[0].depth;
        if (!light) s[i].depth = INFINITY, s[i].motion_px[0] = s[i].motion_px[1] = 0.0f;
        for (int c = 0; c < 3; ++c) s[i].L[c] = light ? L_E : 0.0f;
    }
    LrConfig cfg = lr_config_default();
    cfg.bright_clamp_min_px = bright_clamp_min_px;
    LrSamples img = lr_samples_split(W, H, SPP, s);
    LrOutput out = {rgb, NULL, NULL, 0};
    lr_reconstruct_c(&img, &cfg, &out);
    CHECK(out.nonfinite == 0);
    double halo = 0.0;
    *energy = 0.0;
    for (int py = 0; py < H; ++py)
        for (int px = 0; px < W; ++px) {
            /* distance from the pixel's centre to the segment the disk's centre sweeps */
            double qx = px + 0.5 - CX, qy = py + 0.5 - CY, v = rgb[((size_t)py * W + px) * 3];
            double along = fabs(qx * ax + qy * ay) - 0.5 * D_M, across = -qx * ay + qy * ax;
            double r = sqrt((along > 0.0 ? along * along : 0.0) + across * across);
            *energy += v;
            if (r >= 7.5) halo = fmax(halo, fabs(v));
        }
    lr_samples_free(&img);
    free(rgb);
    free(s);
    return halo;
}

static void test_moving_light_no_halo(void)
{
    double energy = L_E * M_PI * 36.0, e_on, e_off; /* the time average keeps the disk's energy */
    LrConfig cfg = lr_config_default();
    LrSlopes streak = {0.0f, 0.0f, 3.0f, 3.0f};
    /* R = 1.5 px: the clamp is at its floor, the pixel box's std */
    CHECK(fabsf(lr_bright_clamp_px(&cfg, &streak) - cfg.bright_clamp_min_px) < 1e-6f);
    double on = moving_halo(cfg.bright_clamp_min_px, &e_on), off = moving_halo(1.0f, &e_off);
    fprintf(stderr, "bright light moving 3 px at -60 degrees, 16 spp (energy %.0f): clamp %.3f px: halo %.4g energy %.0f; 1 px: halo %.4g energy %.0f\n",
            energy, lr_bright_clamp_px(&cfg, &streak), on, e_on, off, e_off);
    CHECK(on < 1e-3 * L_E);
    CHECK(fabs(e_on / energy - 1.0) < 0.02);
    CHECK(off > 2e-3 * L_E);
}

/* lr_bright_clamp_px's law: for a moving layer, or a still one whose lens blur is within the
 * still band (|c| / 2 at most the band), sqrt(2 pi) R / (2 bright_contrast) between its two
 * limits, R the smallest blur radius (a circle of confusion, half a streak; 0 across the focal
 * plane or across still); a still layer blurred past the band keeps bright_clamp_px. */
static void test_clamp_law(void)
{
    LrConfig cfg = lr_config_default();
    double k = sqrt(2.0 * M_PI) / (2.0 * cfg.bright_contrast);
    float band = cfg.filter.sigma_pixel_still_px;
    LrSlopes in_band = {0.1f, 2.0f * band, 0.0f, 0.0f}, past_band = {0.1f, 2.0f * band + 0.05f, 0.0f, 0.0f};
    LrSlopes lens = {4.0f, 6.0f, 0.0f, 0.0f}, across_focus = {-0.3f, 0.5f, 0.0f, 0.0f};
    LrSlopes moving = {0.0f, 0.0f, -70.0f, -50.0f}, slow = {0.0f, 0.0f, -7.0f, -5.0f}, across_still = {0.0f, 0.0f, -20.0f, 30.0f};
    LrSlopes both = {-25.0f, -24.0f, 2.0f, 12.0f}, both_slow = {-5.0f, -4.0f, 2.0f, 12.0f};
    LrSlopes moving_across_focus = {-20.0f, 30.0f, 5.0f, 6.0f};
    CHECK(lr_bright_clamp_px(&cfg, &in_band) == cfg.bright_clamp_min_px);
    CHECK(lr_bright_clamp_px(&cfg, &across_focus) == cfg.bright_clamp_min_px);
    CHECK(lr_bright_clamp_px(&cfg, &past_band) == cfg.bright_clamp_px);
    CHECK(lr_bright_clamp_px(&cfg, &lens) == cfg.bright_clamp_px);
    CHECK(lr_bright_clamp_px(&cfg, &moving) == cfg.bright_clamp_px); /* R = 25 px: past the cap */
    CHECK(fabs(lr_bright_clamp_px(&cfg, &slow) - k * 2.5) < 1e-5);
    CHECK(lr_bright_clamp_px(&cfg, &across_still) == cfg.bright_clamp_min_px);
    CHECK(lr_bright_clamp_px(&cfg, &both) == cfg.bright_clamp_px);
    CHECK(fabs(lr_bright_clamp_px(&cfg, &both_slow) - k * 4.0) < 1e-5);
    CHECK(fabs(lr_bright_clamp_px(&cfg, &moving_across_focus) - k * 2.5) < 1e-5);
}

int main(void)
{
    test_clamp_law();
    test_moving_light_no_halo();
    CHECK_DONE();
}
