/* The still pixels' noise share and the still band's widening (src/recon/lr/lr_noise_share.c,
 * docs/algorithms.md 8.37): 1 for pixels that differ by their noise alone, 0 for noise-free
 * texture, moving pixels left out, unknown with too few pairs; the widening's law and its caps. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/lr/lr_noise_share.h"

enum { NW = 64, NH = 32, NSPP = 8 };

static unsigned next(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}
static double unit(unsigned *s) { return (double)next(s) / 16777216.0; }

/* bright[] of NW x NH pixels x NSPP samples: base(x, y) plus uniform noise of half-width amp. */
static float *image(double (*base)(int, int), double amp, unsigned seed)
{
    float *b = malloc(sizeof(float) * NW * NH * NSPP);
    for (int i = 0; b && i < NW * NH; ++i)
        for (int k = 0; k < NSPP; ++k) b[i * NSPP + k] = (float)(base(i % NW, i / NW) + amp * (2.0 * unit(&seed) - 1.0));
    return b;
}

static double flat(int x, int y) { return (void)x, (void)y, 1.5; }
static double stripes(int x, int y) { return (void)y, (x / 2) % 2 ? 2.4 : 0.6; }

static double share(const float *bright, const unsigned char *moving, int spp)
{
    LrSamples img = {NW, NH, spp, NULL, NULL, bright};
    return lr_still_noise_share(&img, moving);
}

static void test_share(void)
{
    unsigned char *still = calloc(NW * NH, 1), *half = malloc(NW * NH);
    float *noise = image(flat, 0.5, 3), *texture = image(stripes, 0.0, 5), *both = image(stripes, 0.5, 7);
    CHECK(still && half && noise && texture && both);
    if (!still || !half || !noise || !texture || !both) return;
    /* iid noise on a flat field: a pixel mean's variance is its neighbour difference's half */
    double r_noise = share(noise, still, NSPP), r_texture = share(texture, still, NSPP), r_both = share(both, still, NSPP);
    fprintf(stderr, "noise share: noise alone %.3f, texture alone %.3f, both %.3f\n", r_noise, r_texture, r_both);
    CHECK(r_noise > 0.85 && r_noise < 1.15);
    CHECK(r_texture == 0.0);
    CHECK(r_both > 0.0 && r_both < 0.2);
    /* moving pixels are left out: wild values in every other row change nothing */
    for (int i = 0; i < NW * NH; ++i) half[i] = (i / NW) % 2;
    float *wild = malloc(sizeof(float) * NW * NH * NSPP);
    CHECK(wild != NULL);
    if (wild) {
        memcpy(wild, noise, sizeof(float) * NW * NH * NSPP);
        for (int i = 0; i < NW * NH; ++i)
            if (half[i])
                for (int k = 0; k < NSPP; ++k) wild[i * NSPP + k] = (float)(k % 2 ? 50.0 : -20.0);
        double a = share(noise, half, NSPP), b = share(wild, half, NSPP);
        CHECK(a == b && a > 0.8 && a < 1.25);
    }
    /* unknown: one sample per pixel, or too few still pairs (only the first row's 63) */
    CHECK(share(noise, still, 1) == -1.0);
    for (int i = 0; i < NW * NH; ++i) half[i] = i >= NW;
    CHECK(share(noise, half, NSPP) == -1.0);
    free(still), free(half), free(noise), free(texture), free(both), free(wild);
}

static void test_widening(void)
{
    CHECK(lr_still_band_widening(-1.0) == 1.0f && lr_still_band_widening(NAN) == 1.0f);
    CHECK(lr_still_band_widening(0.0) == 1.0f && lr_still_band_widening(LR_NOISE_SHARE_REF) == 1.0f);
    CHECK(fabsf(lr_still_band_widening(2.0 * LR_NOISE_SHARE_REF) - powf(2.0f, 0.125f)) < 1e-6f);
    CHECK(lr_still_band_widening(100.0) == (float)LR_NOISE_WIDEN_MAX);
    for (double r = 0.1; r < 10.0; r *= 1.1) CHECK(lr_still_band_widening(r) <= lr_still_band_widening(r * 1.1));
    /* the widened band: never narrower, at most LR_NOISE_BAND_MAX_PX unless already wider */
    CHECK(lr_still_band_px(0.396f, -1.0) == 0.396f);
    CHECK(fabsf(lr_still_band_px(0.396f, 2.0 * LR_NOISE_SHARE_REF) - 0.396f * powf(2.0f, 0.125f)) < 1e-6f);
    CHECK(lr_still_band_px(0.471f, 100.0) == LR_NOISE_BAND_MAX_PX);
    CHECK(lr_still_band_px(0.6f, 100.0) == 0.6f);
}

int main(void)
{
    test_share();
    test_widening();
    CHECK_DONE();
}
