/* Mixed pixels' first surface filtered, through the pipeline (docs/algorithms.md 4.6): on the
 * foreground_bars bench scene at 64 x 64 a defocused fence covers most of the frame, so most
 * pixels see a bar and the room behind through their lens samples. With maaf and aaf:
 *
 *   - most pixels' direct light is filtered (pixels_filtered; before the split 23% / 18%);
 *   - the composite keeps the expected value: the mean of four seeds' 16-spp images is as close
 *     to a 1024-spp Monte Carlo reference as four seeds of Monte Carlo at 16 spp are (a split
 *     pixel whose first surface's light were mixed with the other samples', or whose others'
 *     light were left out or counted twice, is biased by a share of the bars' light);
 *   - each seed's image has less error than Monte Carlo's at the same count. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mc_render.h"
#include "recon_test_util.h"

enum { RES = 64, SEEDS = 4, SPP = 16 };

static void count_filtered(const ReconResult *res, void *ctx)
{
    *(long long *)ctx = res->pixels_filtered[EFFECT_SOFT_SHADOWS];
}

static void check_method(const char *text, const char *filter, const float *ref, double err_mc_mean, double err_mc_one,
                         size_t n3)
{
    double *sum = calloc(n3, sizeof(double));
    float *mean = malloc(n3 * sizeof(float));
    CHECK(sum && mean);
    if (!sum || !mean) return;
    double err_one = 0.0;
    for (int s = 0; s < SEEDS; ++s) {
        ReconOptions o = {.filter = filter, .spp = SPP};
        long long filtered = -1;
        float *rgb = recon_test_render(text, 11 + (unsigned)s, &o, count_filtered, &filtered);
        CHECK(rgb != NULL);
        if (!rgb) continue;
        CHECK(filtered >= (long long)(0.6 * RES * RES));
        if (s == 0) printf("%s: %lld of %d pixels shadow-filtered\n", filter, filtered, RES * RES);
        err_one += rel_mse(rgb, ref, n3) / SEEDS;
        for (size_t i = 0; i < n3; ++i) sum[i] += rgb[i];
        free(rgb);
    }
    for (size_t i = 0; i < n3; ++i) mean[i] = (float)(sum[i] / SEEDS);
    double err_mean = rel_mse(mean, ref, n3);
    printf("%s %d spp: relMSE per seed %.3g (Monte Carlo %.3g), of the %d seeds' mean %.3g (Monte Carlo %.3g)\n", filter, SPP,
           err_one, err_mc_one, SEEDS, err_mean, err_mc_mean);
    CHECK(err_one < err_mc_one);
    CHECK(err_mean < err_mc_mean);
    free(sum);
    free(mean);
}

int main(void)
{
    char *text = recon_test_bench_scene_at("foreground_bars", RES);
    CHECK(text != NULL);
    if (!text) CHECK_DONE();
    size_t n3 = 0;
    float *ref = recon_test_mc_image(text, 7, 1024, &n3);
    CHECK(ref != NULL);
    if (!ref) CHECK_DONE();
    /* Monte Carlo at the filters' count: each seed, and the seeds' mean */
    double *sum = calloc(n3, sizeof(double)), err_mc_one = 0.0;
    float *mean = malloc(n3 * sizeof(float));
    CHECK(sum && mean);
    for (int s = 0; sum && mean && s < SEEDS; ++s) {
        size_t m3 = 0;
        float *mc = recon_test_mc_image(text, 11 + (unsigned)s, SPP, &m3);
        CHECK(mc && m3 == n3);
        if (!mc) continue;
        err_mc_one += rel_mse(mc, ref, n3) / SEEDS;
        for (size_t i = 0; i < n3; ++i) sum[i] += mc[i];
        free(mc);
    }
    for (size_t i = 0; sum && mean && i < n3; ++i) mean[i] = (float)(sum[i] / SEEDS);
    double err_mc_mean = sum && mean ? rel_mse(mean, ref, n3) : 0.0;
    check_method(text, "maaf", ref, err_mc_mean, err_mc_one, n3);
    check_method(text, "aaf", ref, err_mc_mean, err_mc_one, n3);
    free(sum);
    free(mean);
    free(ref);
    free(text);
    CHECK_DONE();
}
