/* An environment light under a --spp budget (pipeline.c, setup_filtered): the sky's direct
 * light is filtered by nothing, so AAF's plan (which sets counts from the noise its own
 * filters leave) must not decide where the budget goes: every pixel gets exactly the budget,
 * traced in pass 1, while AAF still filters the lens and the bounce. The same scene lit by an
 * area light instead keeps the plan's uneven counts (the rule must not trigger there), and
 * so does AAF's frame of the sky without a budget (its own counts). The same holds for a
 * frame planned by MAAF (auto's choice here: a lens and no motion), and not for one planned
 * by FSF, whose plans were not measured against uniform counts under a sky. Without a budget
 * MAAF's frame of the sky takes the scene file's count (12 here, neither method's pass 1)
 * as its budget, every pixel alike. */
#include <stdlib.h>

#include "check.h"
#include "recon_test_util.h"

/* SHADOW_SCENE's floor and occluder, through a lens focused on the occluder, one bounce, lit
 * by `light` (a LightSource or an AttributeBegin block). */
static void scene_text(char *text, size_t size, const char *light)
{
    snprintf(text, size,
             "LookAt -1.5 2.5 -1.5   0.8 0 0.3   0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 30 ] \"float lensradius\" [ 0.15 ] \"float focaldistance\" [ 2.2 ]\n"
             "Film \"rgb\" \"integer xresolution\" [ 40 ] \"integer yresolution\" [ 40 ] \"string filename\" [ \"t.exr\" ]\n"
             "Sampler \"stratified\" \"integer xsamples\" [ 4 ] \"integer ysamples\" [ 3 ]\n"
             "Integrator \"path\" \"integer maxdepth\" [ 2 ]\n"
             "WorldBegin\n"
             "%s\n"
             "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
             "Shape \"trianglemesh\" \"point3 P\" [ 0.3 1 -0.3  0.9 1 -0.3  0.9 1 0.3  0.3 1 0.3 ] "
             "\"integer indices\" [ 0 1 2 0 2 3 ]\n",
             light);
}

static const char *const SKY = "LightSource \"infinite\" \"rgb L\" [ 0.6 0.7 0.9 ]";
static const char *const AREA = "AttributeBegin\n"
                                "  AreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\n"
                                "  Shape \"trianglemesh\" \"point3 P\" [ -0.8 4 -0.8  0.8 4 -0.8  0.8 4 0.8  -0.8 4 0.8 ]"
                                " \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                                "AttributeEnd";

typedef struct {
    int spp_min, spp_max;
    long long filtered_indirect, filtered_defocus;
    const char *method; /* the method expected for both effects */
} FrameCounts;

static void count_samples(const ReconPipeline *p, void *ctx)
{
    FrameCounts *fc = ctx;
    const ReconResult *res = recon_pipeline_result(p);
    CHECK(res->choice.method[EFFECT_DEFOCUS] && !strcmp(res->choice.method[EFFECT_DEFOCUS]->name, fc->method));
    CHECK(res->choice.method[EFFECT_INDIRECT] && !strcmp(res->choice.method[EFFECT_INDIRECT]->name, fc->method));
    fc->filtered_indirect = res->pixels_filtered[EFFECT_INDIRECT];
    fc->filtered_defocus = res->pixels_filtered[EFFECT_DEFOCUS];
    recon_test_spp_range(p, &fc->spp_min, &fc->spp_max);
}

/* filter: "auto" (MAAF here: a lens, no motion) or a method's name */
static FrameCounts render(const char *light, int spp, const char *filter)
{
    char text[4096];
    scene_text(text, sizeof text, light);
    FrameCounts fc = {-1, -1, 0, 0, strcmp(filter, "auto") ? filter : "maaf"};
    ReconOptions o = {.filter = filter, .spp = spp};
    float *rgb = recon_test_render_pipeline(text, 7, &o, count_samples, &fc);
    CHECK(rgb != NULL);
    free(rgb);
    fprintf(stderr, "%s, %s, --spp %d: samples per pixel %d..%d, filtered %lld (indirect) %lld (defocus) pixels\n",
            light == SKY ? "sky" : "area light", filter, spp, fc.spp_min, fc.spp_max, fc.filtered_indirect, fc.filtered_defocus);
    return fc;
}

int main(void)
{
    /* auto's static choice: this test is about the filters' pipeline on a tiny frame, where
     * auto's fallback (recon/auto_fallback.h) would leave the shading effects to Monte Carlo */
    setenv("WEDGE_AUTO_FALLBACK", "0", 1);
    /* the sky, a budget above the methods' pass 1 (AAF 16, MAAF 9): all of it in pass 1,
     * every pixel alike, under AAF, under MAAF and under auto (MAAF) */
    const char *const uniform[] = {"aaf", "maaf", "auto"};
    for (size_t i = 0; i < sizeof uniform / sizeof uniform[0]; ++i) {
        FrameCounts fc = render(SKY, 40, uniform[i]);
        CHECK(fc.spp_min == 40 && fc.spp_max == 40);
        CHECK(fc.filtered_indirect > 0 && fc.filtered_defocus > 0);
        /* an area light instead: the plan spreads the same budget unevenly */
        fc = render(AREA, 40, uniform[i]);
        CHECK(fc.spp_max > fc.spp_min);
        CHECK(fc.filtered_indirect > 0 && fc.filtered_defocus > 0);
        /* the sky without a budget: AAF's own counts, uneven; MAAF's frame the file's 12 */
        fc = render(SKY, 0, uniform[i]);
        if (!strcmp(uniform[i], "aaf")) CHECK(fc.spp_max > fc.spp_min);
        else CHECK(fc.spp_min == 12 && fc.spp_max == 12);
        /* an area light without a budget: MAAF's own counts too */
        fc = render(AREA, 0, uniform[i]);
        CHECK(fc.spp_max > fc.spp_min);
    }
    /* FSF's plans were not measured under a sky: kept */
    FrameCounts fc = render(SKY, 40, "fsf");
    CHECK(fc.spp_max > fc.spp_min);
    CHECK_DONE();
}
