/* The pipeline's step function (progressive rendering): every step adds samples to every
 * pixel and reconstructs with mu doubled, so the image converges to the Monte Carlo answer:
 * on a soft-shadow scene the error against a 1024-spp reference falls at every step, every
 * pixel's count grows, and the image stays finite. A step with a cap stops at it. --filter
 * none steps double the samples. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon_test_util.h"
#include "recon/pipeline.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

typedef struct {
    SceneDesc scene;
    Renderer *r;
    ReconPipeline *p;
} Setup;

static bool setup(Setup *s, const char *filter, unsigned seed)
{
    memset(s, 0, sizeof *s);
    Diag d = {0};
    RenderOptions ro = {0};
    ro.seed = seed, ro.threads = 2;
    ReconOptions o = {.filter = filter};
    bool ok = scene_parse_string(SHADOW_SCENE, strlen(SHADOW_SCENE), "<step>", NULL, &s->scene, &d) &&
              renderer_create(&s->scene, &ro, &s->r, &d) && recon_pipeline_create(s->r, &o, &s->p, &d);
    if (!ok) fprintf(stderr, "%s\n", d.message);
    return ok;
}

static void teardown(Setup *s)
{
    recon_pipeline_destroy(s->p);
    renderer_destroy(s->r);
    scene_desc_free(&s->scene);
}

int main(void)
{
    enum { N = 40 * 40 }; /* SHADOW_SCENE's film */
    /* the reference: 1024 Monte Carlo samples per pixel, another seed */
    Setup ref;
    CHECK(setup(&ref, "none", 99));
    float *ref_rgb = NULL;
    {
        Frame f;
        frame_init(&f, 40, 40);
        CHECK(render_pass(ref.r, 0, NULL, 1024, &f, NULL));
        ref_rgb = malloc(3 * N * sizeof(float));
        frame_resolve3(&f, f.color, ref_rgb);
        frame_free(&f);
    }
    teardown(&ref);

    Setup s;
    CHECK(setup(&s, "aaf", 1));
    Diag d = {0};
    double prev_err = 1e30, prev_avg = 0.0;
    float *prev_spp = calloc(N, sizeof(float));
    for (int step = 0; step < 4; ++step) {
        CHECK(recon_pipeline_step(s.p, 0.0, &d));
        const ReconResult *res = recon_pipeline_result(s.p);
        const float *spp = recon_pipeline_gbuffer(s.p)->frame.spp;
        double err = rel_mse(res->rgb, ref_rgb, 3 * N);
        fprintf(stderr, "step %d: mu %g, spp_avg %.1f, relMSE %.3g\n", step, (double)res->mu, res->spp_avg, err);
        CHECK(res->steps == step + 1);
        CHECK(err < prev_err);            /* converging */
        CHECK(res->spp_avg > prev_avg);
        /* an uncapped step at most doubles the frame (a preview's steps do not lengthen
         * 8-fold when mu doubles and a plan grows as mu^3) */
        if (step > 0) CHECK(res->spp_avg <= 2.0 * prev_avg + 1e-9);
        for (int i = 0; i < N; ++i) CHECK(spp[i] > prev_spp[i]); /* every pixel gets more */
        for (int i = 0; i < 3 * N; ++i) CHECK(isfinite(res->rgb[i]));
        memcpy(prev_spp, spp, N * sizeof(float));
        prev_err = err;
        prev_avg = res->spp_avg;
    }
    teardown(&s);

    /* A capped step stops at the cap: a --time or --spp target is met, not overshot. The
     * plan is scaled down by error diffusion, so the frame's total is the cap to within one
     * sample; at the cap a step adds nothing. */
    CHECK(setup(&s, "aaf", 2));
    CHECK(recon_pipeline_step(s.p, 0.0, &d));
    double first = recon_pipeline_result(s.p)->spp_avg, cap = 1.5 * first;
    CHECK(recon_pipeline_step(s.p, cap, &d));
    CHECK_NEAR(recon_pipeline_result(s.p)->spp_avg, cap, 1.0 / N);
    CHECK(recon_pipeline_result(s.p)->steps == 2);
    CHECK(recon_pipeline_step(s.p, cap, &d));
    CHECK(recon_pipeline_result(s.p)->steps == 2);
    CHECK_NEAR(recon_pipeline_result(s.p)->spp_avg, cap, 1.0 / N);
    teardown(&s);

    /* Monte Carlo steps: 16, then +16, +32, +64 samples (doubling the total) */
    CHECK(setup(&s, "none", 1));
    const double expect[4] = {16, 32, 64, 128};
    for (int step = 0; step < 4; ++step) {
        CHECK(recon_pipeline_step(s.p, 0.0, &d));
        CHECK_NEAR(recon_pipeline_result(s.p)->spp_avg, expect[step], 0.0);
    }
    teardown(&s);
    free(prev_spp);
    free(ref_rgb);
    CHECK_DONE();
}
