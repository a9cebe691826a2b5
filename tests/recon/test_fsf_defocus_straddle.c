/* FSF's extra samples where the lens slopes straddle the focal plane (FSF section 5,
 * fsf_lens_plan.h), end to end on the defocus bench scene (its floor crosses the focal plane)
 * at 128x128, three seeds, against a 1024-spp Monte Carlo reference:
 *
 *   plan      without a budget every pixel has 16 samples, 16 + FSF_LENS_STRADDLE_EXTRA_SPP
 *             exactly where the filter found a straddling range (AOV fsf.defocus.straddle),
 *             and some pixels but not most straddle
 *   budget    with --spp N pass 1 has FSF_BUDGET_PASS1_SHARE_LENS of N, the average is N, and the
 *             straddlers (A = 1 in the allocation, fsf_budget_plan.h) have on average several
 *             times the other pixels' extra samples
 *   error     at the straddling pixels the relMSE falls against Monte Carlo at pass 1's 16
 *             samples (what a straddler was in the fixed-count FSF: 95% of them are left out)
 *   beside    with AAF on the soft shadows of the combined bench scene (64x64), the frame takes
 *             the per-pixel maximum of the two plans: FSF's straddlers have at least 16 + 36
 *
 * (Until the budget plan, a --spp 16 frame was the fixed-count FSF, and the pixels far from
 * every straddler were checked bit-identical between it and the frame with the extras; no
 * option gives that frame any more.) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/fsf/fsf_budget_plan.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/fsf/fsf_lens_plan.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"

enum { RES = 128, SEEDS = 3, PASS1 = 16 };

typedef struct {
    int budget;                  /* the --spp given (0: none) */
    unsigned char straddle[RES * RES];
    long straddlers, wrong_counts;
    double straddle_extra, other_extra; /* under a budget: mean samples above pass 1's */
} Run;

static void check_frame(const ReconPipeline *p, void *ctx)
{
    Run *f = ctx;
    const GBuffer *g = recon_pipeline_gbuffer(p);
    const float *straddle = recon_test_frame_aov(p, "fsf.defocus.straddle", RES);
    if (!straddle) return;
    f->straddlers = f->wrong_counts = 0;
    f->straddle_extra = f->other_extra = 0.0;
    if (f->budget) {
        /* pass 1 takes its share of the budget, the plan the rest: the average is the budget */
        int pass1 = (int)lroundf(FSF_BUDGET_PASS1_SHARE_LENS * (float)f->budget);
        f->wrong_counts = recon_test_budget_wrong(p, FSF_BUDGET_PASS1_SHARE_LENS, f->budget);
        for (size_t i = 0; i < (size_t)RES * RES; ++i) {
            f->straddle[i] = straddle[i] > 0.5f;
            f->straddlers += f->straddle[i];
            *(f->straddle[i] ? &f->straddle_extra : &f->other_extra) += g->frame.spp[i] - (float)pass1;
        }
        f->straddle_extra /= (double)(f->straddlers ? f->straddlers : 1);
        f->other_extra /= (double)(RES * RES - f->straddlers);
        return;
    }
    for (size_t i = 0; i < (size_t)RES * RES; ++i) {
        f->straddle[i] = straddle[i] > 0.5f;
        f->straddlers += f->straddle[i];
        int want = PASS1 + (f->straddle[i] ? FSF_LENS_STRADDLE_EXTRA_SPP : 0);
        f->wrong_counts += (int)g->frame.spp[i] != want;
    }
}

static float *render(const char *text, const char *filter, unsigned seed, int spp, Run *f)
{
    if (f) f->budget = spp;
    return recon_test_render_spp(text, filter, seed, spp, f ? check_frame : NULL, f);
}

/* The combined scene's soft shadows to AAF, its defocus to FSF: every straddler has FSF's count
 * (or more, from AAF's plan), every pixel at least pass 1's. */
static void check_beside(const ReconPipeline *p, void *ctx)
{
    long *short_pixels = ctx;
    const ReconResult *res = recon_pipeline_result(p);
    const GBuffer *g = recon_pipeline_gbuffer(p);
    const float *straddle = recon_test_aov(res, "fsf.defocus.straddle");
    CHECK(straddle != NULL && g->width == res->width && g->height == res->height);
    CHECK(!strcmp(recon_choice_name(&res->choice, EFFECT_SOFT_SHADOWS), "aaf"));
    long straddlers = 0;
    for (size_t i = 0; straddle && i < (size_t)res->width * (size_t)res->height; ++i) {
        int want = PASS1 + (straddle[i] > 0.5f ? FSF_LENS_STRADDLE_EXTRA_SPP : 0);
        straddlers += straddle[i] > 0.5f;
        *short_pixels += g->frame.spp[i] < (float)want;
    }
    CHECK(straddlers > 0);
}

int main(void)
{
    char *text = recon_test_bench_scene_at("defocus", RES);
    CHECK(text != NULL);
    if (!text) CHECK_DONE();
    float *ref = render(text, "none", 100, 1024, NULL);
    CHECK(ref != NULL);
    static Run extra, budget;
    double e_extra = 0.0, e_mc = 0.0;
    for (unsigned seed = 1; seed <= SEEDS && ref; ++seed) {
        float *a = render(text, "fsf", seed, 0, &extra);
        float *b = render(text, "none", seed, PASS1, NULL);
        CHECK(a && b);
        if (!a || !b) {
            free(a), free(b);
            break;
        }
        CHECK(extra.wrong_counts == 0);
        CHECK(extra.straddlers > 20 && extra.straddlers < RES * RES / 4);
        e_extra += rel_mse_where(a, ref, extra.straddle, 1, (size_t)RES * RES) / SEEDS;
        e_mc += rel_mse_where(b, ref, extra.straddle, 1, (size_t)RES * RES) / SEEDS;
        fprintf(stderr, "seed %u: %ld straddling pixels\n", seed, extra.straddlers);
        free(a), free(b);
    }
    /* under a budget the straddlers take a larger share of the rest than the others */
    for (int spp = 16; spp <= 24; spp += 8) {
        float *c = render(text, "fsf", 1, spp, &budget);
        fprintf(stderr, "--spp %d: %ld straddlers at %.2f extra spp, the others %.2f\n", spp, budget.straddlers,
                budget.straddle_extra, budget.other_extra);
        CHECK(c != NULL && budget.wrong_counts == 0);
        CHECK(budget.straddlers > 20 && budget.straddle_extra > 3.0 * budget.other_extra);
        free(c);
    }
    char *combined = recon_test_bench_scene_at("combined", 64);
    CHECK(combined != NULL);
    long short_pixels = 0;
    ReconOptions beside = {.filter = "soft_shadows=aaf,defocus=fsf"};
    free(combined ? recon_test_render_pipeline(combined, 1, &beside, check_beside, &short_pixels) : NULL);
    CHECK(short_pixels == 0);
    free(combined);
    fprintf(stderr, "straddling pixels' relMSE (%d seeds): Monte Carlo %d spp %.4g, fsf with %d more %.4g\n", SEEDS,
            PASS1, e_mc, FSF_LENS_STRADDLE_EXTRA_SPP, e_extra);
    CHECK(e_extra < 0.6 * e_mc);
    free(ref);
    free(text);
    CHECK_DONE();
}
