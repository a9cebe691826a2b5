/* The plan's width of a shading filter without its design (maaf_shadow.h: maaf_pixel_std,
 * maaf_pixel_plain_filters; maaf_design.h: maaf_design_central_sx) against the full design's
 * values, bit for bit, over a sweep of slopes, bands, pixel sizes and knobs that includes the
 * design's clamps, NaN slopes, swapped slopes and filters below a quarter pixel. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "recon/maaf/maaf_shadow.h"

static unsigned rng_state = 12345u;
static float rnd(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (float)(rng_state >> 8) / 16777216.0f;
}

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

int main(void)
{
    /* hand value: s in [1, 2], wy 5, N = 3 (test_maaf_design's): sx_0 = 5 / (5 * 1) = 1; at
     * pixel_world 0.1 and kappa 2 the std is 1 / (2 * 0.1) = 5 pixels */
    CHECK_NEAR(maaf_design_central_sx(1.0f, 2.0f, 5.0f, 3), 1.0, 1e-6);
    CHECK_NEAR(maaf_pixel_std(1.0f, 2.0f, 5.0f, 3, 2.0f, 0.1f), 5.0, 1e-5);
    CHECK(maaf_design_central_sx(1.0f, 2.0f, 0.0f, 3) == 0.0f); /* no design */
    CHECK(maaf_pixel_std(1.0f, 2.0f, 5.0f, 3, 1.0f, 0.0f) == 0.0f);

    int mismatched = 0, filtered = 0, unfiltered = 0, plain_mismatched = 0;
    const float special[] = {NAN, 0.0f, -1.0f, 1.0e-6f, 2.0e4f, INFINITY};
    for (int t = 0; t < 20000; ++t) {
        /* slopes over 8 decades, now and then a special value or the two swapped */
        float s_min = powf(10.0f, 8.0f * rnd() - 5.0f), s_max = s_min * (1.0f + 20.0f * rnd());
        if (t % 13 == 0) s_min = special[(t / 13) % 6];
        if (t % 17 == 0) s_max = special[(t / 17) % 6];
        if (t % 5 == 0) {
            float tmp = s_min;
            s_min = s_max, s_max = tmp;
        }
        float wy = t % 101 == 0 ? 0.0f : powf(10.0f, 4.0f * rnd() - 1.0f);
        float pw = t % 97 == 0 ? 0.0f : powf(10.0f, 4.0f * rnd() - 4.0f);
        float kappa = t % 89 == 0 ? 0.0f : 0.5f + 3.0f * rnd();
        int pairs = 1 + t % 6; /* 6: beyond MAAF_PAIRS_MAX, clamped */
        MaafDesign2D d;
        bool made = maaf_design_2d(s_min, s_max, wy, pairs, &d);
        CHECK(same_bits(maaf_design_central_sx(s_min, s_max, wy, pairs), made ? d.c[0].sx : 0.0f));
        float param[MAAF_PARAM_STRIDE];
        float full = maaf_pixel_param(s_min, s_max, wy, pairs, kappa, pw, param);
        float alone = maaf_pixel_std(s_min, s_max, wy, pairs, kappa, pw);
        mismatched += !same_bits(full, alone);
        filtered += full > 0.0f, unfiltered += full == 0.0f;
        /* the plain far filter: radius > 0 exactly when it filters */
        float std_px = t % 7 == 0 ? special[(t / 7) % 6] : 4.0f * rnd();
        maaf_pixel_param_plain(std_px, pw, pairs, param);
        plain_mismatched += (param[0] > 0.0f) != maaf_pixel_plain_filters(std_px, pw);
    }
    printf("pixel std: %d filtered, %d not, %d differ from the design's; plain: %d differ\n", filtered, unfiltered,
           mismatched, plain_mismatched);
    CHECK(mismatched == 0);
    CHECK(plain_mismatched == 0);
    CHECK(filtered > 1000 && unfiltered > 1000); /* the sweep reaches both sides of the quarter pixel */
    CHECK_DONE();
}
