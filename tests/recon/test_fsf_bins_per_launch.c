/* fsf_cl_bins_per_launch (fsf_cl.h): the y2 bins pass 1a fills per launch, against a brute force
 * over every allowed count. For each frame (bins 1 .. FSF_MAX_Y2_BINS, slices from a few KB to
 * larger than either budget) the count must be allowed (at least 1; at most the larger of the
 * old rule's FSF_CL_BINS_PER_LAUNCH slices within FSF_CL_P_BYTES and FSF_CL_MAX_BINS_PER_LAUNCH
 * within FSF_CL_P_WIDE_BYTES), need no more launches than the best allowed count, and be the
 * smallest count with that many launches. Then the frames measured: the bench grids at 256 x 256
 * (slices of about 1 MB: the shadows' 12 bins as two launches of 6, the lens' 16 as two of 8),
 * the lens at 720 x 720 (slices of 7.8 MB: the old rule's 4), and slices so large that only 3
 * fit in either budget. The kernels at 6 and 8 bins a launch against the C passes: test_fsf_cl
 * (its grids of 13 and 17 nodes). */
#include <stddef.h>

#include "../check.h"
#include "recon/fsf/fsf_cl.h"

static int launches(int bins, int per) { return (bins + per - 1) / per; }

/* slices of `slice` bytes within `bytes`, between 1 and cap */
static int within(size_t slice, size_t bytes, int cap)
{
    size_t fit = bytes / slice;
    return fit < 1 ? 1 : fit > (size_t)cap ? cap : (int)fit;
}

int main(void)
{
    const size_t MB = (size_t)1 << 20;
    for (int bins = 1; bins <= FSF_MAX_Y2_BINS; ++bins) {
        for (size_t slice = 64 << 10; slice <= 80 * MB; slice += slice / 3) {
            int c = fsf_cl_bins_per_launch(bins, slice);
            int most = within(slice, FSF_CL_P_BYTES, FSF_CL_BINS_PER_LAUNCH);
            int wide = within(slice, FSF_CL_P_WIDE_BYTES, FSF_CL_MAX_BINS_PER_LAUNCH);
            most = wide > most ? wide : most;
            CHECK(c >= 1 && c <= most);
            int best = bins; /* the fewest launches of any allowed count */
            for (int k = 1; k <= most; ++k)
                if (launches(bins, k) < best) best = launches(bins, k);
            CHECK(launches(bins, c) == best);
            CHECK(c == 1 || launches(bins, c - 1) > best); /* the smallest count with as few */
        }
    }
    CHECK(fsf_cl_bins_per_launch(12, MB) == 6);
    CHECK(fsf_cl_bins_per_launch(16, MB) == 8);
    CHECK(fsf_cl_bins_per_launch(16, 78 * MB / 10) == 4);
    CHECK(fsf_cl_bins_per_launch(16, 20 * MB) == 3); /* 3 fit in 72 MB, 0 in 16: six launches of 3 */
    CHECK(fsf_cl_bins_per_launch(16, 3 * MB) == 4);  /* 5 fit in 16 MB: four launches of 4 */
    CHECK(fsf_cl_bins_per_launch(1, MB) == 1);
    return check_failures ? 1 : 0;
}
