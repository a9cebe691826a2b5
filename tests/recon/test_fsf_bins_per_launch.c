/* fsf_cl_bins_per_launch (fsf_cl.h): the y2 bins pass 1a fills per launch, against a brute force
 * over every allowed count. For each frame (bins 1 .. FSF_MAX_Y2_BINS, slices that fit from none
 * to more than FSF_CL_MAX_BINS_PER_LAUNCH) the count must be allowed (at least 1; at most the
 * cap and, where one slice fits, at most the slices that fit), need no more launches than the
 * best allowed count, and be the smallest count with that many launches (no launch takes more
 * slices than the split needs). Then the bench grids' values:
 * the shadows' 12 bins as two launches of 6, the lens' 16 as two of 8. The kernels at these
 * counts against the C passes: test_fsf_cl (its grids of 13 and 17 nodes run C = 6 and 8). */
#include <stddef.h>

#include "../check.h"
#include "recon/fsf/fsf_cl.h"

static int launches(int bins, int per) { return (bins + per - 1) / per; }

int main(void)
{
    const size_t slice = 1000;
    for (int bins = 1; bins <= FSF_MAX_Y2_BINS; ++bins) {
        for (size_t fit = 0; fit <= 2 * FSF_CL_MAX_BINS_PER_LAUNCH; ++fit) {
            size_t p_bytes = fit * slice + slice / 2; /* fit slices and a half: the half fits none */
            int c = fsf_cl_bins_per_launch(bins, slice, p_bytes);
            int most = fit < 1 ? 1 : fit > FSF_CL_MAX_BINS_PER_LAUNCH ? FSF_CL_MAX_BINS_PER_LAUNCH : (int)fit;
            CHECK(c >= 1 && c <= most);
            int best = bins; /* the fewest launches of any allowed count */
            for (int k = 1; k <= most; ++k)
                if (launches(bins, k) < best) best = launches(bins, k);
            CHECK(launches(bins, c) == best);
            /* the smallest count with as few launches */
            CHECK(c == 1 || launches(bins, c - 1) > best);
        }
    }
    /* the bench grids at 256 x 256 (P's rings take a few MB of the 72 MB budget) */
    CHECK(fsf_cl_bins_per_launch(12, (size_t)1 << 20, (size_t)72 << 20) == 6);
    CHECK(fsf_cl_bins_per_launch(16, (size_t)1 << 20, (size_t)72 << 20) == 8);
    CHECK(fsf_cl_bins_per_launch(8, (size_t)1 << 20, (size_t)72 << 20) == 8);
    /* three slices fit: 16 bins in six launches of 3 (the last 1), not of 2 */
    CHECK(fsf_cl_bins_per_launch(16, (size_t)1 << 20, (size_t)3 << 20) == 3);
    /* an empty frame's slices (0 bytes) and a single bin */
    CHECK(fsf_cl_bins_per_launch(16, 0, (size_t)72 << 20) == 1);
    CHECK(fsf_cl_bins_per_launch(1, (size_t)1 << 20, (size_t)72 << 20) == 1);
    return check_failures ? 1 : 0;
}
