/* A fixed-count method beside an adaptive one under a --spp budget (pipeline.c,
 * budget_in_pass1): the soft shadows of a moving occluder go to AAF (adaptive) and, seen
 * through a wide lens, its defocus and motion to LR (fixed count, reads as many samples per
 * pixel as the pixel with the fewest has). The whole budget must be traced uniformly in pass
 * 1, so every pixel has exactly the budget and LR reads all of it, while AAF still filters.
 * Without a budget (the methods' own counts), and through a pinhole (LR asked for the motion
 * alone: auto leaves a blur that short to Monte Carlo), AAF's plan adds samples where it wants them. */
#include <stdlib.h>

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

/* What a frame left: the smallest and largest samples per pixel, the pixels AAF filtered. */
typedef struct {
    int spp_min, spp_max;
    long long aaf_pixels;
    const char *defocus_method; /* expected method for defocus, NULL: no defocus */
} FrameCounts;

static void count_samples(const ReconPipeline *p, void *ctx)
{
    FrameCounts *fc = ctx;
    const ReconResult *res = recon_pipeline_result(p);
    CHECK(res->choice.method[EFFECT_SOFT_SHADOWS] && !strcmp(res->choice.method[EFFECT_SOFT_SHADOWS]->name, "aaf"));
    CHECK(res->choice.method[EFFECT_MOTION] && !strcmp(res->choice.method[EFFECT_MOTION]->name, "lr"));
    const ReconMethodClass *dof = res->choice.method[EFFECT_DEFOCUS];
    CHECK(fc->defocus_method ? dof && !strcmp(dof->name, fc->defocus_method) : !dof);
    fc->aaf_pixels = res->pixels_filtered[EFFECT_SOFT_SHADOWS];
    recon_test_spp_range(p, &fc->spp_min, &fc->spp_max);
}

/* Renders with `spp` (0: the methods' own counts) and `filter`, through a lens of radius 0.3
 * focused at 1 unit (the floor ~3.4 units away blurs ~16 px) or a pinhole. */
static FrameCounts render(int spp, bool lens, const char *filter, const char *defocus_method)
{
    const char *camera = "Camera \"perspective\" \"float fov\" [ 30 ]\n";
    const char *at = strstr(SHADOW_SCENE, camera);
    CHECK(at != NULL);
    char text[8192];
    int head = at ? (int)(at - SHADOW_SCENE) : 0;
    snprintf(text, sizeof text, "%.*s%s%s%s", head, SHADOW_SCENE,
             lens ? "Camera \"perspective\" \"float fov\" [ 30 ] \"float lensradius\" [ 0.3 ] \"float focaldistance\" [ 1 ]\n"
                  : camera,
             at ? at + strlen(camera) : "", MOVING_OCCLUDER); /* shutter: pbrt's [0, 1] */
    FrameCounts fc = {-1, -1, 0, defocus_method};
    ReconOptions o = {.filter = filter, .spp = spp};
    free(recon_test_render_pipeline(text, 5, &o, count_samples, &fc));
    return fc;
}

int main(void)
{
    /* auto's static choice: this test is about the filters' pipeline on a tiny frame, where
     * auto's fallback (recon/auto_fallback.h) would leave the shading effects to Monte Carlo */
    setenv("WEDGE_AUTO_FALLBACK", "0", 1);
    FrameCounts fc = render(24, true, "auto", "lr");
    fprintf(stderr, "lens, --spp 24: samples per pixel %d..%d, AAF filtered %lld pixels\n", fc.spp_min, fc.spp_max,
            fc.aaf_pixels);
    CHECK(fc.spp_min == 24 && fc.spp_max == 24);
    CHECK(fc.aaf_pixels > 0);
    /* no budget: the plan decides, unevenly (the penumbrae want more than the open floor) */
    fc = render(0, true, "auto", "lr");
    fprintf(stderr, "lens, own counts: samples per pixel %d..%d, AAF filtered %lld pixels\n", fc.spp_min, fc.spp_max,
            fc.aaf_pixels);
    CHECK(fc.spp_max > fc.spp_min);
    CHECK(fc.aaf_pixels > 0);
    /* a pinhole: LR takes the motion alone, and the plan keeps the budget */
    fc = render(24, false, "motion=lr", NULL);
    fprintf(stderr, "pinhole, --spp 24: samples per pixel %d..%d, AAF filtered %lld pixels\n", fc.spp_min, fc.spp_max,
            fc.aaf_pixels);
    CHECK(fc.spp_max > fc.spp_min);
    CHECK(fc.aaf_pixels > 0);
    CHECK_DONE();
}
