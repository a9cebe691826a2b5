/* The lens filter's area for the Lagrange allocation (maaf_defocus_area_share; docs/algorithms.md
 * 9.29).
 *
 * 1. For slope ranges from near the focal plane to far from it, the filter maaf_pixel_param_signed
 *    sets (central std s, radius r = param[0]) averages (sum w)^2 / sum w^2 taps per axis, w =
 *    exp(-k^2 / (2 s^2)) for |k| <= r, each weight from its own exp: the share must be the
 *    square of that over 4 pi s^2 (at least 1), to 1e-5. A radius taken as floor instead of
 *    ceil, or a per-axis count not squared, fails here.
 * 2. The share is at most 1 and, cut at 1.5 stds, well below it for wide filters (below 0.8 at
 *    s >= 2 px), and at the radius cap (32 px) it falls as the filter widens.
 * 3. No filter (s <= 0, NaN) keeps the uncut area: share 1. */
#include <math.h>

#include "check.h"
#include "recon/maaf/maaf_defocus.h"

static double brute_share(double s, int radius)
{
    double sum = 0.0, sum2 = 0.0;
    for (int k = -radius; k <= radius; ++k) {
        double w = exp(-(double)k * k / (2.0 * s * s));
        sum += w;
        sum2 += w * w;
    }
    double taps = sum * sum / sum2;
    double uncut = fmax(1.0, 4.0 * M_PI * s * s);
    return fmin(1.0, taps * taps / uncut);
}

int main(void)
{
    MaafLens lens;
    CHECK(maaf_lens_design(MAAF_DEFOCUS_KAPPA_DEFAULT, 3, &lens));
    float omega = lens.omega_u_max;
    maaf_lens_free(&lens);

    /* 1 and 2: slope ranges of one sign, narrow and wide, both sides of the focal plane */
    static const float ranges[][2] = {{0.6f, 0.8f}, {1.0f, 1.4f}, {2.0f, 3.0f}, {3.0f, 8.0f},
                                      {6.0f, 7.0f}, {12.0f, 20.0f}, {-5.0f, -2.5f}, {-0.9f, -0.6f}};
    int wide = 0;
    for (size_t i = 0; i < sizeof ranges / sizeof ranges[0]; ++i) {
        float param[MAAF_PARAM_STRIDE];
        float s = maaf_pixel_param_signed(ranges[i][0], ranges[i][1], omega, 3, param);
        CHECK(s > 0.0f);
        int radius = (int)param[0];
        double want = brute_share(s, radius);
        float got = maaf_defocus_area_share(s);
        CHECK_NEAR(got, want, 1e-5);
        CHECK(got <= 1.0f);
        if (s >= 2.0f) {
            CHECK(got < 0.8f);
            ++wide;
        }
    }
    CHECK(wide >= 2); /* the ranges reach wide filters */

    /* the radius cap: past 32 / 1.5 px the cut moves in, the share falls */
    CHECK_NEAR(maaf_defocus_area_share(40.0f), brute_share(40.0, MAAF_RADIUS_CAP_PX), 1e-5);
    CHECK(maaf_defocus_area_share(40.0f) < maaf_defocus_area_share(20.0f));

    /* 3: no filter */
    CHECK(maaf_defocus_area_share(0.0f) == 1.0f);
    CHECK(maaf_defocus_area_share(-1.0f) == 1.0f);
    CHECK(maaf_defocus_area_share(NAN) == 1.0f);
    return check_failures ? 1 : 0;
}
