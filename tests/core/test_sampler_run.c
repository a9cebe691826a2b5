/* sampler_run_*: every value of a run is bit for bit what the per-sample requests
 * (sampler_start_sample, sampler_1d_at / sampler_2d) give that sample, for both samplers,
 * table and untabled sample counts, continued sets whose runs straddle the prefix and the
 * continuation, indices past the set (further blocks), dimensions past the padded ones, and
 * runs interleaved with per-sample requests of other samples; and, over enough pixels that
 * some jitter falls within rounding of a stratum edge (where the vectorised run loops hand
 * their values back to the scalar path), every value of whole pixels. */
#include <stdlib.h>

#include "check.h"
#include "core/sampler.h"

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* The per-sample reference: a fresh sampler per value, so no cache state is shared with the
 * run under test. */
static float ref_1d(SamplerKind kind, int px, int before, int spp, int sample, int dim)
{
    static PixelSampler s;
    sampler_continue_pixel(&s, kind, 7, px, 3, 1, before, spp);
    sampler_start_sample(&s, sample);
    return sampler_1d_at(&s, dim);
}

static vec2 ref_2d(SamplerKind kind, int px, int before, int spp, int sample, int dim)
{
    static PixelSampler s;
    sampler_continue_pixel(&s, kind, 7, px, 3, 1, before, spp);
    sampler_start_sample(&s, sample);
    s.dim = dim;
    return sampler_2d(&s);
}

/* Runs of `count` samples from `first` over dimensions 0 .. 8 and two past the padding;
 * with `interleave`, a per-sample request of another sample between the run's dimensions
 * (as the wave's lobe draws do). Returns the number of values that differ. */
static int compare_runs(SamplerKind kind, int px, int before, int spp, int first, int count, bool interleave)
{
    static PixelSampler s;
    static SamplerRun run;
    float v1[SAMPLER_RUN_MAX];
    vec2 v2s[SAMPLER_RUN_MAX];
    int dims[] = {0, 1, 2, 3, 5, 8, SAMPLER_PADDED_DIMS - 2, SAMPLER_PADDED_DIMS - 1, SAMPLER_PADDED_DIMS + 3};
    int bad = 0;
    sampler_continue_pixel(&s, kind, 7, px, 3, 1, before, spp);
    sampler_run_begin(&s, &run, first, count);
    for (size_t d = 0; d < sizeof dims / sizeof dims[0]; ++d) {
        int dim = dims[d];
        if (interleave) {
            sampler_start_sample(&s, first + count + 5); /* perhaps another part */
            (void)sampler_1d_at(&s, dim);
        }
        sampler_run_1d(&s, &run, dim, v1);
        if (interleave) {
            sampler_start_sample(&s, 0);
            (void)sampler_2d(&s);
        }
        sampler_run_2d(&s, &run, dim, v2s);
        for (int k = 0; k < run.count; ++k) {
            float r1 = ref_1d(kind, px, before, spp, first + k, dim);
            vec2 r2 = ref_2d(kind, px, before, spp, first + k, dim);
            bad += !same_bits(v1[k], r1);
            bad += !same_bits(v2s[k].x, r2.x) || !same_bits(v2s[k].y, r2.y);
        }
    }
    return bad;
}

/* Every pixel of a strip, runs of run_len samples, against per-sample requests on a second
 * sampler: about spp 2^-22 of the values have a jitter within rounding of a stratum edge, so
 * 4096 pixels at 256 spp meet some hundreds of them. */
static int compare_pixels_runs(int spp, int pixels, int run_len)
{
    static PixelSampler a, b;
    static SamplerRun run;
    static vec2 out2[SAMPLER_RUN_MAX];
    static float out1[SAMPLER_RUN_MAX];
    int bad = 0;
    for (int px = 0; px < pixels; ++px) {
        sampler_start_pixel(&a, SAMPLER_STRATIFIED, 3, px, 11, 0, spp);
        sampler_start_pixel(&b, SAMPLER_STRATIFIED, 3, px, 11, 0, spp);
        for (int first = 0; first < spp; first += run_len) {
            sampler_run_begin(&a, &run, first, spp - first < run_len ? spp - first : run_len);
            for (int dim = 0; dim < 8; dim += 3) {
                sampler_run_2d(&a, &run, dim, out2);
                sampler_run_1d(&a, &run, dim + 2, out1);
                for (int k = 0; k < run.count; ++k) {
                    sampler_start_sample(&b, first + k);
                    b.dim = dim;
                    vec2 r2 = sampler_2d(&b);
                    float r1 = sampler_1d_at(&b, dim + 2);
                    bad += !same_bits(out2[k].x, r2.x) || !same_bits(out2[k].y, r2.y) || !same_bits(out1[k], r1);
                }
            }
        }
    }
    return bad;
}

static int compare_pixels(int spp, int pixels) { return compare_pixels_runs(spp, pixels, SAMPLER_RUN_MAX); }

int main(void)
{
    CHECK(compare_pixels(256, 4096) == 0);
    CHECK(compare_pixels(100, 4096) == 0);
    CHECK(compare_pixels(418, 1024) == 0);
    /* rounds of 64-127 samples (renderer.c): the cycle walk in 16-bit lanes at its longest
     * (65: half the domain outside), and grids past 16 x 16 whose runs fill the whole table
     * (83 = 1 x 83, 158 = 2 x 79: run_tabled_values) */
    CHECK(compare_pixels(65, 1024) == 0);
    CHECK(compare_pixels(83, 1024) == 0);
    CHECK(compare_pixels(158, 1024) == 0);
    /* the renderer's rounds of 64 on grids that a run fills at once or entry by entry
     * (GRID_FILL_ALL_RATIO): 8192 = 64 x 128, 32768 = 128 x 256, 211 = 1 x 211, 509 = 1 x 509;
     * every run of a few pixels */
    CHECK(compare_pixels_runs(8192, 16, 64) == 0);
    CHECK(compare_pixels_runs(32768, 4, 64) == 0);
    CHECK(compare_pixels_runs(211, 256, 64) == 0);
    CHECK(compare_pixels_runs(509, 128, 64) == 0);
    /* grids with both sides at most 32 and one past 16, whose table look-ups are
     * in-register permutes (run_tabled_values_small): 512 = 16 x 32 in the renderer's rounds
     * of 64 and 128 and in runs that end inside a 16-lane chunk (50); 1024 = 32 x 32 and
     * 992 = 31 x 32 at the limit, 1056 = 32 x 33 just past it (run_tabled_values), 34 = 2 x 17
     * and 17 = 1 x 17 (a side of one) */
    CHECK(compare_pixels_runs(512, 512, 64) == 0);
    CHECK(compare_pixels_runs(512, 256, 128) == 0);
    CHECK(compare_pixels_runs(512, 256, 50) == 0);
    CHECK(compare_pixels_runs(1024, 128, 127) == 0);
    CHECK(compare_pixels_runs(992, 128, 64) == 0);
    CHECK(compare_pixels_runs(1056, 128, 64) == 0);
    CHECK(compare_pixels_runs(34, 2048, 34) == 0);
    CHECK(compare_pixels_runs(17, 2048, 17) == 0);
    /* grids with a side past 32, whose runs compute each sample's grid entries for it alone
     * (run_grid_values_direct; the 8192, 32768, 211, 509 and 1056 above too): rows by
     * lattice nibbles (5 x 37), by exact shuffles (3 x 67; 6 x 37 in runs ending inside a
     * vector), a side of one with the longest lattice side tabled (1 x 1021), 31 x 33 (both
     * sides by the lattice's reciprocal), 32 x 64 in runs of 127 and 64 x 64 in runs of one;
     * and the largest grid tabled, 512 x 512 (rows + cols = SAMPLER_GRID_ENTRIES), in a few
     * runs below */
    CHECK(compare_pixels_runs(185, 512, 64) == 0);
    CHECK(compare_pixels_runs(201, 512, 64) == 0);
    CHECK(compare_pixels_runs(222, 512, 50) == 0);
    CHECK(compare_pixels_runs(1021, 64, 64) == 0);
    CHECK(compare_pixels_runs(1023, 64, 64) == 0);
    CHECK(compare_pixels_runs(2048, 32, 127) == 0);
    CHECK(compare_pixels_runs(4096, 4, 1) == 0);
    for (int px = 0; px < 8; ++px) {
        CHECK(compare_runs(SAMPLER_STRATIFIED, px, 0, 262144, 64 * 1000 * px, 64, false) == 0);
        CHECK(compare_runs(SAMPLER_STRATIFIED, px, 0, 262144, 262144 - 127 + px, 127 - px, px & 1) == 0);
    }
    /* per-pixel tables (spp <= 16: run_table_values_2d, run_table_strata), whole pixels in
     * one run as the renderer's rounds take them. Few near-edge jitters change a value (the
     * rounding must cross the edge): 131072 pixels at 16 spp (19 million values) meet some;
     * with the correction of the run's 2D values skipped this check fails, with 16384 it
     * did not */
    CHECK(compare_pixels_runs(16, 131072, 16) == 0);
    CHECK(compare_pixels_runs(13, 8192, 13) == 0);
    CHECK(compare_pixels_runs(8, 8192, 8) == 0);

    static const SamplerKind kinds[] = {SAMPLER_STRATIFIED, SAMPLER_SOBOL};
    for (int kk = 0; kk < 2; ++kk) {
        SamplerKind kind = kinds[kk];
        /* one set: tables (4, 9, 16), untabled grids packed (64, 100, 256), grids with a side
         * past 16 in the lazily filled grid tables (17, 37, 289, 300, 1000) and past them
         * (2062 = 2 x 1031); 70001: a padding domain past 2^16 (the walk in 32-bit lanes) */
        static const int spps[] = {1, 4, 9, 16, 17, 37, 64, 65, 83, 100, 256, 289, 300, 1000, 2062, 70001};
        for (size_t i = 0; i < sizeof spps / sizeof spps[0]; ++i) {
            int spp = spps[i];
            int first = spp > 8 ? spp / 3 : 0, count = spp - first < SAMPLER_RUN_MAX ? spp - first : SAMPLER_RUN_MAX;
            CHECK(compare_runs(kind, 5, 0, spp, first, count, false) == 0);
            CHECK(compare_runs(kind, 6, 0, spp, first, count, true) == 0);
            /* past the set: the next block, and a run straddling blocks */
            CHECK(compare_runs(kind, 7, 0, spp, spp + 1, 3, false) == 0);
            CHECK(compare_runs(kind, 8, 0, spp, spp > 2 ? spp - 2 : 0, 5, true) == 0);
        }
        /* continued sets (sampler_continue_pixel): runs inside the prefix, inside the
         * continuation, and across the two */
        CHECK(compare_runs(kind, 9, 16, 64, 0, 16, false) == 0);
        CHECK(compare_runs(kind, 9, 16, 64, 16, 48, true) == 0);
        CHECK(compare_runs(kind, 9, 16, 64, 10, 20, false) == 0);
        CHECK(compare_runs(kind, 10, 40, 300, 30, 64, true) == 0);
    }
    /* count above the maximum is clipped, 0 gives an empty run */
    static PixelSampler s;
    static SamplerRun run;
    sampler_start_pixel(&s, SAMPLER_STRATIFIED, 1, 0, 0, 0, 256);
    sampler_run_begin(&s, &run, 0, 1000);
    CHECK(run.count == SAMPLER_RUN_MAX);
    sampler_run_begin(&s, &run, 3, 0);
    CHECK(run.count == 0);
    return check_failures ? 1 : 0;
}
