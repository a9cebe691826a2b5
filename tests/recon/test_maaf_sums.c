/* MAAF's per-sample sums, cut to the ones a filter reads (maaf_method.c: mark_unread_sums,
 * albedo_add; docs/algorithms.md 9.13): the combined bench scene (soft shadows, indirect light,
 * defocus, every effect maaf's) at 64x64 renders the same image as with every sample in every
 * sum (WEDGE_MAAF_ALL_SUMS), to float rounding (the albedo sums of a one-albedo pixel are made
 * as A sum c_k instead of sum A c_k), at two budgets and two seeds. The frames must hold what
 * the savings act on, or the comparison proves nothing: pixels without a lens filter that got
 * pass 2's samples (their lens sums are skipped), and pixels whose direct light is passed
 * through (no light filter) with more samples than pass 1's. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon_test_util.h"

enum { RES = 64 };

typedef struct {
    int pass1_spp;              /* half the budget in a frame with defocus (maaf_method.c) */
    int unfiltered_lens_extra; /* pixels with no lens filter and more than pass 1's samples */
    int unfiltered_light_extra; /* the same for the light filter */
} SkipCount;

static void count_skips(const ReconPipeline *p, void *ctx)
{
    SkipCount *c = ctx;
    const ReconResult *res = recon_pipeline_result(p);
    const float *lens = recon_test_aov(res, "maaf.std_px.defocus"), *light = recon_test_aov(res, "maaf.std_px.soft_shadows");
    const float *spp = recon_pipeline_gbuffer(p)->frame.spp;
    CHECK(lens && light && spp);
    if (!lens || !light || !spp) return;
    for (int i = 0; i < res->width * res->height; ++i) {
        c->unfiltered_lens_extra += lens[i] == 0.0f && spp[i] > c->pass1_spp;
        c->unfiltered_light_extra += light[i] == 0.0f && spp[i] > c->pass1_spp;
    }
}

int main(void)
{
    char *text = recon_test_bench_scene_at("combined", RES);
    CHECK(text != NULL);
    if (!text) CHECK_DONE();
    size_t n3 = (size_t)RES * RES * 3;
    const int spp[2] = {16, 32};
    for (unsigned seed = 1; seed <= 2; ++seed)
        for (int k = 0; k < 2; ++k) {
            ReconOptions o = {.filter = "maaf", .spp = spp[k]};
            SkipCount c = {spp[k] / 2, 0, 0};
            unsetenv("WEDGE_MAAF_ALL_SUMS");
            float *cut = recon_test_render_pipeline(text, seed, &o, count_skips, &c);
            setenv("WEDGE_MAAF_ALL_SUMS", "1", 1);
            float *all = recon_test_render(text, seed, &o, NULL, NULL);
            unsetenv("WEDGE_MAAF_ALL_SUMS");
            CHECK(cut && all);
            if (cut && all) {
                double e = rel_mse(cut, all, n3);
                printf("seed %u, %d spp: relMSE %.3g between the cut and the full sums; %d lens-unfiltered and %d "
                       "light-unfiltered pixels with extra samples\n",
                       seed, spp[k], e, c.unfiltered_lens_extra, c.unfiltered_light_extra);
                CHECK(e <= 1.0e-10);
            }
            CHECK(c.unfiltered_lens_extra > RES * RES / 50);
            CHECK(c.unfiltered_light_extra > RES * RES / 50);
            free(cut);
            free(all);
        }
    free(text);
    CHECK_DONE();
}
