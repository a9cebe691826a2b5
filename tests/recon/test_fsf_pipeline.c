/* FSF end to end through the reconstruction pipeline (--filter fsf) on the small soft-shadow
 * scene (recon_test_util.h): the image is finite, soft shadows are assigned to fsf at its
 * fixed 16 samples per pixel (and --spp is honoured), the AOVs are there and within their
 * bounds, and at equal samples its error against a high-spp reference is well below plain
 * Monte Carlo's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"
#include "scene/scene_desc.h"

/* What only an FSF frame has: the method chosen, its sample count and its AOVs. */
static void check_fsf(const ReconResult *res, void *ctx)
{
    int spp = *(const int *)ctx;
    size_t n = (size_t)res->width * (size_t)res->height;
    CHECK(!strcmp(recon_choice_name(&res->choice, EFFECT_SOFT_SHADOWS), "fsf"));
    CHECK(res->spp_avg == (spp > 0 ? spp : 16));
    const float *eta = NULL, *sigma = NULL;
    for (int k = 0; k < res->aov_count; ++k) {
        if (!strcmp(res->aovs[k].name, "fsf.eta_m_per_px")) eta = res->aovs[k].data;
        if (!strcmp(res->aovs[k].name, "fsf.sigma_px")) sigma = res->aovs[k].data;
    }
    CHECK(eta && sigma);
    size_t bad = 0, filtered = 0;
    for (size_t i = 0; eta && sigma && i < n; ++i) {
        bad += !(eta[i] >= 0.0f && isfinite(eta[i])) ||
               !(sigma[i] >= 0.0f && sigma[i] <= FSF_RADIUS_CAP_PX / FSF_RADIUS_SIGMAS);
        filtered += sigma[i] > 1.0f;
    }
    CHECK(bad == 0);        /* shear along +u, width within the 32-pixel cap */
    CHECK(filtered > n / 4); /* the floor is filtered, not passed through */
}

/* One render through the pipeline; returns a copy of the image and checks the result. */
static float *render(const char *filter, unsigned seed, int spp, bool fsf_checks)
{
    ReconOptions o = {.filter = filter, .spp = spp};
    return recon_test_render(SHADOW_SCENE, seed, &o, fsf_checks ? check_fsf : NULL, &spp);
}

/* A sphere light has soft shadows but no light plane with axes: a clear refusal. */
static void sphere_light_refused(void)
{
    char text[4096];
    const char *quad = "  Shape \"trianglemesh\" \"point3 P\" [ -0.8 4 -0.8  0.8 4 -0.8  0.8 4 0.8  -0.8 4 0.8 ]"
                       " \"integer indices\" [ 0 1 2 0 2 3 ]\n";
    const char *at = strstr(SHADOW_SCENE, quad);
    CHECK(at != NULL);
    if (!at) return;
    snprintf(text, sizeof text, "%.*s  Translate 0 4 0 Shape \"sphere\" \"float radius\" [ 0.5 ]\n%s",
             (int)(at - SHADOW_SCENE), SHADOW_SCENE, at + strlen(quad));
    SceneDesc scene;
    Renderer *r;
    if (!recon_test_renderer(text, 1, 4, false, &scene, &r)) {
        CHECK(false);
        return;
    }
    ReconOptions o = {.filter = "fsf", .spp = 4};
    ReconPipeline *p = NULL;
    Diag d = {0};
    bool ok = recon_pipeline_create(r, &o, &p, &d) && recon_pipeline_render(p, &d);
    CHECK(!ok);
    CHECK_STR(d.message, "error: --filter fsf filters soft shadows of a planar area light made of triangles; the scene has none");
    recon_pipeline_destroy(p);
    renderer_destroy(r);
    scene_desc_free(&scene);
}

int main(void)
{
    sphere_light_refused();
    const int w = 40, h = 40;
    float *ref = render("none", 100, 1024, false);
    double e_fsf = 0, e_mc = 0;
    for (unsigned seed = 1; seed <= 2 && ref; ++seed) {
        float *f = render("fsf", seed, 0, true), *mc = render("none", seed, 16, false);
        if (f && mc) {
            e_fsf += rel_mse(f, ref, (size_t)w * h * 3);
            e_mc += rel_mse(mc, ref, (size_t)w * h * 3);
        }
        free(f);
        free(mc);
    }
    free(render("fsf", 3, 4, true)); /* --spp 4: the fixed count follows it */
    fprintf(stderr, "relMSE at 16 spp (2 seeds): fsf %.4g, mc %.4g\n", e_fsf / 2, e_mc / 2);
    /* the reference's own noise at 1024 spp is 64x below Monte Carlo's at 16. The bound was
     * 0.5 until a mesh light's triangle came from the light-position sample (stratified over
     * the whole emitter, issue 23): Monte Carlo's relMSE here fell from 0.00218 to 0.00122,
     * FSF's only from 0.00090 to 0.00085, since what is left of FSF's error is bias (contact
     * shadows left unfiltered, docs/benchmarks.md "FSF"). 0.75 keeps a margin of 1.3x on
     * both seeds' mean and still fails for a filter that does not beat the stronger baseline. */
    CHECK(e_fsf < 0.75 * e_mc);
    free(ref);
    CHECK_DONE();
}
