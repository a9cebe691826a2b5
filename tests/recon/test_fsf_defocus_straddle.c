/* FSF's extra samples where the lens slopes straddle the focal plane (FSF section 5,
 * fsf_lens_plan.h), end to end on the defocus bench scene (its floor crosses the focal plane)
 * at 128x128, three seeds, against a 1024-spp Monte Carlo reference:
 *
 *   plan      without a budget every pixel has 16 samples, 16 + FSF_LENS_STRADDLE_EXTRA_SPP
 *             exactly where the filter found a straddling range (AOV fsf.defocus.straddle),
 *             and some pixels but not most straddle
 *   budget    with --spp N the frame is the fixed-count FSF: N samples everywhere, all in
 *             pass 1 (at 16: the frame before the plan existed; at 24: no extras bought with
 *             the budget, and none left out of the store)
 *   error     at the straddling pixels the relMSE falls against the fixed-count frame
 *   beside    with AAF on the soft shadows of the combined bench scene (64x64), the frame takes
 *             the per-pixel maximum of the two plans: FSF's straddlers have at least 16 + 36
 *   identity  pixels that neither straddle nor lie within two tap radii of a straddler are
 *             bit-identical to the fixed-count frame's (the extra samples reach the image
 *             through the straddlers' own means only) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/fsf/fsf_lens_plan.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"

enum { RES = 128, SEEDS = 3, PASS1 = 16 };
/* a straddler's taps reach FSF_RADIUS_CAP_PX; a neighbour's gather of those taps as far again */
enum { REACH_PX = 2 * FSF_RADIUS_CAP_PX + 1 };

typedef struct {
    int budget;                  /* the --spp given (0: none) */
    unsigned char straddle[RES * RES];
    long straddlers, wrong_counts;
} Run;

static void check_frame(const ReconPipeline *p, void *ctx)
{
    Run *f = ctx;
    const ReconResult *res = recon_pipeline_result(p);
    const GBuffer *g = recon_pipeline_gbuffer(p);
    const float *straddle = recon_test_aov(res, "fsf.defocus.straddle");
    CHECK(straddle != NULL && res->width == RES && res->height == RES && g->width == RES);
    if (!straddle || res->width != RES || g->width != RES) return;
    f->straddlers = f->wrong_counts = 0;
    /* under a budget, one pass: the store (which keeps pass 1's samples) holds them all */
    f->wrong_counts += f->budget && res->pass1_spp != f->budget;
    for (size_t i = 0; i < (size_t)RES * RES; ++i) {
        f->straddle[i] = straddle[i] > 0.5f;
        f->straddlers += f->straddle[i];
        int want = f->budget ? f->budget : PASS1 + (f->straddle[i] ? FSF_LENS_STRADDLE_EXTRA_SPP : 0);
        f->wrong_counts += (int)g->frame.spp[i] != want;
    }
}

static float *render(const char *text, const char *filter, unsigned seed, int spp, Run *f)
{
    ReconOptions o = {.filter = filter, .spp = spp};
    if (f) f->budget = spp;
    return recon_test_render_pipeline(text, seed, &o, f ? check_frame : NULL, f);
}

/* relMSE over the pixels with mask[i] == want */
static double rel_mse_where(const float *img, const float *ref, const unsigned char *mask, int want)
{
    double sum = 0.0;
    long count = 0;
    for (size_t i = 0; i < (size_t)RES * RES; ++i) {
        if (mask[i] != want) continue;
        for (int c = 0; c < 3; ++c) {
            double e = img[3 * i + c] - ref[3 * i + c];
            sum += e * e / ((double)ref[3 * i + c] * ref[3 * i + c] + 0.01);
        }
        ++count;
    }
    return count ? sum / (3.0 * count) : 0.0;
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

/* far[i] = 1 where no straddler lies within REACH_PX (Chebyshev) of pixel i */
static void far_from_straddlers(const unsigned char *straddle, unsigned char *far)
{
    for (int y = 0; y < RES; ++y)
        for (int x = 0; x < RES; ++x) {
            bool near = false;
            for (int v = y - REACH_PX; v <= y + REACH_PX && !near; ++v)
                for (int u = x - REACH_PX; u <= x + REACH_PX && !near; ++u)
                    near = u >= 0 && v >= 0 && u < RES && v < RES && straddle[v * RES + u];
            far[y * RES + x] = !near;
        }
}

int main(void)
{
    char *text = recon_test_bench_scene_at("defocus", RES);
    CHECK(text != NULL);
    if (!text) CHECK_DONE();
    float *ref = render(text, "none", 100, 1024, NULL);
    CHECK(ref != NULL);
    static Run extra, fixed;
    static unsigned char far[RES * RES];
    double e_extra = 0.0, e_fixed = 0.0;
    long far_pixels = 0, far_differ = 0;
    for (unsigned seed = 1; seed <= SEEDS && ref; ++seed) {
        float *a = render(text, "fsf", seed, 0, &extra);
        float *b = render(text, "fsf", seed, PASS1, &fixed);
        CHECK(a && b);
        if (!a || !b) {
            free(a), free(b);
            break;
        }
        CHECK(extra.wrong_counts == 0 && fixed.wrong_counts == 0);
        CHECK(extra.straddlers > 20 && extra.straddlers < RES * RES / 4);
        CHECK(!memcmp(extra.straddle, fixed.straddle, sizeof extra.straddle)); /* from pass 1 alone */
        e_extra += rel_mse_where(a, ref, extra.straddle, 1) / SEEDS;
        e_fixed += rel_mse_where(b, ref, extra.straddle, 1) / SEEDS;
        far_from_straddlers(extra.straddle, far);
        for (size_t i = 0; i < (size_t)RES * RES; ++i) {
            if (!far[i]) continue;
            far_pixels++;
            far_differ += memcmp(a + 3 * i, b + 3 * i, 3 * sizeof(float)) != 0;
        }
        fprintf(stderr, "seed %u: %ld straddling pixels, %ld far from them\n", seed, extra.straddlers, far_pixels);
        free(a), free(b);
    }
    /* a budget above pass 1's count is spread uniformly in pass 1, not spent on straddlers */
    float *c = render(text, "fsf", 1, 24, &fixed);
    CHECK(c != NULL && fixed.wrong_counts == 0);
    free(c);
    char *combined = recon_test_bench_scene_at("combined", 64);
    CHECK(combined != NULL);
    long short_pixels = 0;
    ReconOptions beside = {.filter = "soft_shadows=aaf,defocus=fsf"};
    free(combined ? recon_test_render_pipeline(combined, 1, &beside, check_beside, &short_pixels) : NULL);
    CHECK(short_pixels == 0);
    free(combined);
    fprintf(stderr, "straddling pixels' relMSE (%d seeds): fixed %d spp %.4g, with %d more %.4g; far pixels differing %ld of %ld\n",
            SEEDS, PASS1, e_fixed, FSF_LENS_STRADDLE_EXTRA_SPP, e_extra, far_differ, far_pixels);
    CHECK(e_extra < 0.6 * e_fixed);
    CHECK(far_pixels > 0 && far_differ == 0);
    free(ref);
    free(text);
    CHECK_DONE();
}
