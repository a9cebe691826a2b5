/* A fixed-count method beside an adaptive one under a --spp budget (pipeline.c,
 * budget_in_pass1): the soft shadows of a moving occluder go to AAF (adaptive) and its motion
 * to LR (fixed count, reads as many samples per pixel as the pixel with the fewest has). The
 * whole budget must be traced uniformly in pass 1, so every pixel has exactly the budget and
 * LR reads all of it, while AAF still filters. Without a budget (the methods' own counts),
 * AAF's plan still adds samples where it wants them. */
#include "check.h"
#include "recon_test_util.h"

static const char *const MOVING_OCCLUDER =
    "AttributeBegin\n"
    "  ActiveTransform StartTime\n"
    "  Translate 0 0 0\n"
    "  ActiveTransform EndTime\n"
    "  Translate 0.6 0 0\n"
    "  ActiveTransform All\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.6 1.5 -0.2  -0.2 1.5 -0.2  -0.2 1.5 0.2  -0.6 1.5 0.2 ]"
    " \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n";

/* Renders with `spp` (0: the methods' own counts); stores the smallest and largest samples
 * per pixel and the pixels AAF filtered. */
static void render(int spp, int *spp_min, int *spp_max, long long *aaf_pixels)
{
    char text[8192];
    snprintf(text, sizeof text, "%s%s", SHADOW_SCENE, MOVING_OCCLUDER);
    /* the shutter: pbrt's default [0, 1] */
    SceneDesc scene;
    Renderer *r;
    *spp_min = *spp_max = -1;
    *aaf_pixels = 0;
    if (!recon_test_renderer(text, 5, spp, false, &scene, &r)) {
        CHECK(false);
        return;
    }
    ReconOptions o = {.filter = "auto", .spp = spp};
    ReconPipeline *p = NULL;
    Diag d = {0};
    if (recon_pipeline_create(r, &o, &p, &d) && recon_pipeline_render(p, &d)) {
        const ReconResult *res = recon_pipeline_result(p);
        CHECK(res->choice.method[EFFECT_SOFT_SHADOWS] && !strcmp(res->choice.method[EFFECT_SOFT_SHADOWS]->name, "aaf"));
        CHECK(res->choice.method[EFFECT_MOTION] && !strcmp(res->choice.method[EFFECT_MOTION]->name, "lr"));
        *aaf_pixels = res->pixels_filtered[EFFECT_SOFT_SHADOWS];
        const GBuffer *g = recon_pipeline_gbuffer(p);
        size_t n = (size_t)g->frame.width * (size_t)g->frame.height;
        for (size_t i = 0; i < n; ++i) {
            int k = (int)g->frame.spp[i];
            if (*spp_min < 0 || k < *spp_min) *spp_min = k;
            if (k > *spp_max) *spp_max = k;
        }
    } else {
        fprintf(stderr, "%s\n", d.message);
        CHECK(false);
    }
    recon_pipeline_destroy(p);
    renderer_destroy(r);
    scene_desc_free(&scene);
}

int main(void)
{
    int lo, hi;
    long long aaf;
    render(24, &lo, &hi, &aaf);
    fprintf(stderr, "--spp 24: samples per pixel %d..%d, AAF filtered %lld pixels\n", lo, hi, aaf);
    CHECK(lo == 24 && hi == 24);
    CHECK(aaf > 0);
    /* no budget: the plan decides, unevenly (the penumbrae want more than the open floor) */
    render(0, &lo, &hi, &aaf);
    fprintf(stderr, "own counts: samples per pixel %d..%d, AAF filtered %lld pixels\n", lo, hi, aaf);
    CHECK(hi > lo);
    CHECK(aaf > 0);
    CHECK_DONE();
}
