/* The lens filter's slope range from the pooled pass-1 ranges (maaf_coc_pool, maaf_defocus_pixel;
 * docs/algorithms.md 9.21).
 *
 * 1. A 9 x 9 frame of background pixels, each with the circle-of-confusion range [4, 4] px, and
 *    one pixel beside the centre whose samples also hit a small emitter nearer the focal plane,
 *    coc 1.5. Pooled over each pixel and its 4 neighbours, that pixel and its 4 neighbours hold
 *    [1.5, 4], all inside the centre's 5 x 5 window, so the centre's design must be the one of
 *    the averaged range [(5 x 1.5 + 20 x 4) / 25, 4] (slopes its negation): checked parameter for parameter against
 *    maaf_pixel_param_signed. Averaging the raw ranges (the old behaviour) gives
 *    [(1.5 + 24 x 4) / 25, 4], a wider filter: its central std is checked to differ by more than
 *    5%, so the test can fail.
 * 2. A pixel without a range (aaf_stats' empty range: min +inf, max -inf) stays without one and
 *    gives its neighbours nothing; a corner pixel pools only what lies inside the frame; the
 *    diagonal neighbours are not pooled. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/maaf/maaf_defocus.h"

enum { W = 9, H = 9, N = W * H };

static float centre_std(const float *lo, const float *hi, const float *plo, const float *phi, float omega, float *param)
{
    float side = 0.0f;
    return maaf_defocus_pixel(lo, hi, plo, phi, W, H, 4, 4, omega, 3, param, &side);
}

int main(void)
{
    MaafLens lens;
    CHECK(maaf_lens_design(4.0f, 3, &lens));
    float omega = lens.omega_u_max;
    maaf_lens_free(&lens);

    float lo[N], hi[N], plo[N], phi[N];
    for (int i = 0; i < N; ++i) lo[i] = hi[i] = 4.0f;
    lo[4 * W + 5] = 1.5f; /* (5, 4): beside the centre (4, 4) */
    maaf_coc_pool(lo, hi, W, H, plo, phi);
    int widened = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int near = abs(x - 5) + abs(y - 4) <= 1;
            widened += plo[y * W + x] == 1.5f;
            CHECK(plo[y * W + x] == (near ? 1.5f : 4.0f));
            CHECK(phi[y * W + x] == 4.0f);
        }
    CHECK(widened == 5);

    float param[MAAF_PARAM_STRIDE], want[MAAF_PARAM_STRIDE], old[MAAF_PARAM_STRIDE];
    float std_new = centre_std(lo, hi, plo, phi, omega, param);
    float lo_avg = (5.0f * 1.5f + 20.0f * 4.0f) / 25.0f;
    float std_want = maaf_pixel_param_signed(-4.0f, -lo_avg, omega, 3, want);
    CHECK(std_new > 0.0f && std_new == std_want);
    CHECK(memcmp(param, want, sizeof param) == 0);
    /* the old rule: the raw ranges averaged (the pool is the raw ranges themselves) */
    float std_old = centre_std(lo, hi, lo, hi, omega, old);
    printf("centre std: pooled %.4f px, raw ranges averaged %.4f px\n", std_new, std_old);
    CHECK(fabsf(std_old - std_new) > 0.05f * std_new);

    /* 2: the empty range (0, 0) stays empty, its neighbours keep their own; the corner (8, 8)
     * sees only (7..8, 7..8) */
    lo[0] = INFINITY, hi[0] = -INFINITY;
    lo[4 * W + 5] = 4.0f;
    lo[8 * W + 7] = 2.0f;
    maaf_coc_pool(lo, hi, W, H, plo, phi);
    CHECK(plo[0] == INFINITY && phi[0] == -INFINITY);
    CHECK(plo[1] == 4.0f && phi[1] == 4.0f && plo[W] == 4.0f && plo[W + 1] == 4.0f);
    CHECK(plo[8 * W + 8] == 2.0f && phi[8 * W + 8] == 4.0f);
    /* (7, 8)'s 4 neighbours pool its 2, its diagonal ones (6, 7) and (8, 7) do not */
    CHECK(plo[7 * W + 7] == 2.0f && plo[8 * W + 6] == 2.0f);
    CHECK(plo[7 * W + 6] == 4.0f && plo[7 * W + 8] == 4.0f);
    CHECK_DONE();
}
