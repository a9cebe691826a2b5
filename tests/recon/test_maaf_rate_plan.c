/* MAAF's plan in frames with defocus (docs/algorithms.md 9.14), through the pipeline: under a
 * budget pass 1 takes half of it and the frame's average is the budget; the Lagrange
 * allocation gives the pixels that every filter passes through (A = 1) several times the
 * samples of those all three filters cover (A >= 4 pi s^2, tens of pixels). combined.pbrt at
 * 64x64, 16 spp, seeds 1 and 2: 38.3 and 38.7 against 11.2 and 11.1 spp (at 256x256 78.8
 * against 10.7; uniform counts would give 1). A frame with soft shadows alone
 * (soft_shadows.pbrt, 9.20) has the same plan, pass 1 half the budget but at least 9 (here
 * 9), and the pixels whose
 * shadow filter is narrow (central std 0.5-2 px: contact shadows) get more than 1.3 times the
 * samples of those whose filter is wide (8 px or more); the class plan before gave every
 * filtered pixel the same count (ratio 1). */
#include <stdlib.h>

#include "check.h"
#include "recon_test_util.h"

enum { RES = 64, BUDGET = 16 };

typedef struct {
    double spp_open, spp_covered; /* sample sums: pixels all filters pass through / all cover */
    int open, covered;
    long budget_wrong;
} PlanCount;

static void count_plan(const ReconPipeline *p, void *ctx)
{
    PlanCount *c = ctx;
    const float *lens = recon_test_frame_aov(p, "maaf.std_px.defocus", RES);
    const float *light = recon_test_frame_aov(p, "maaf.std_px.soft_shadows", RES);
    const float *bounce = recon_test_frame_aov(p, "maaf.std_px.indirect", RES);
    const float *spp = recon_pipeline_gbuffer(p)->frame.spp;
    c->budget_wrong = recon_test_budget_wrong(p, 0.5f, BUDGET);
    if (!lens || !light || !bounce) return;
    for (int i = 0; i < RES * RES; ++i) {
        if (lens[i] == 0.0f && light[i] == 0.0f && bounce[i] == 0.0f) c->spp_open += spp[i], ++c->open;
        if (lens[i] > 0.0f && light[i] > 0.0f && bounce[i] > 0.0f) c->spp_covered += spp[i], ++c->covered;
    }
}

typedef struct {
    double spp_narrow, spp_wide; /* sample sums: shadow filter std in [0.5, 2) px / >= 8 px */
    int narrow, wide;
    long budget_wrong;
} ShadowCount;

static void count_shadows(const ReconPipeline *p, void *ctx)
{
    ShadowCount *c = ctx;
    const float *light = recon_test_frame_aov(p, "maaf.std_px.soft_shadows", RES);
    const float *comps = recon_test_frame_aov(p, "maaf.components.soft_shadows", RES);
    const float *spp = recon_pipeline_gbuffer(p)->frame.spp;
    c->budget_wrong = recon_test_budget_wrong(p, 9.0f / BUDGET, BUDGET);
    if (!light || !comps) return;
    for (int i = 0; i < RES * RES; ++i) {
        if (comps[i] < 2.0f) continue; /* the full design only (a wedge measured) */
        if (light[i] >= 0.5f && light[i] < 2.0f) c->spp_narrow += spp[i], ++c->narrow;
        if (light[i] >= 8.0f) c->spp_wide += spp[i], ++c->wide;
    }
}

int main(void)
{
    char *text = recon_test_bench_scene_at("combined", RES);
    CHECK(text != NULL);
    if (!text) CHECK_DONE();
    for (unsigned seed = 1; seed <= 2; ++seed) {
        ReconOptions o = {.filter = "maaf", .spp = BUDGET};
        PlanCount c = {0};
        free(recon_test_render_pipeline(text, seed, &o, count_plan, &c));
        double open = c.open ? c.spp_open / c.open : 0.0, covered = c.covered ? c.spp_covered / c.covered : 0.0;
        printf("seed %u: %d pixels no filter covers, %.1f spp; %d all filters cover, %.1f spp\n", seed, c.open, open,
               c.covered, covered);
        CHECK(c.budget_wrong == 0);
        CHECK(c.open > RES * RES / 100 && c.covered > RES * RES / 16);
        CHECK(open > 3.0 * covered);
    }
    free(text);
    text = recon_test_bench_scene_at("soft_shadows", RES);
    CHECK(text != NULL);
    if (text) {
        ReconOptions o = {.filter = "maaf", .spp = BUDGET};
        ShadowCount c = {.budget_wrong = -1};
        free(recon_test_render_pipeline(text, 1, &o, count_shadows, &c));
        double narrow = c.narrow ? c.spp_narrow / c.narrow : 0.0, wide = c.wide ? c.spp_wide / c.wide : 0.0;
        printf("soft_shadows: %d pixels with a narrow shadow filter, %.1f spp; %d with a wide one, %.1f spp\n", c.narrow,
               narrow, c.wide, wide);
        CHECK(c.budget_wrong == 0);
        CHECK(c.narrow > 10 && c.wide > 10);
        CHECK(narrow > 1.3 * wide);
    }
    free(text);
    CHECK_DONE();
}
