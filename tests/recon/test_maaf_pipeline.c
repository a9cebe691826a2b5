/* MAAF through the reconstruction pipeline on a small soft-shadow scene (pipeline.c and
 * maaf/maaf_method.c with the real renderer): at equal spp its relMSE against a high-spp
 * reference is well below plain Monte Carlo's, it falls as the count grows (consistency), the
 * image is finite, and the AOV layers say what was filtered. Tiny images: fast under
 * sanitizers. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mc_render.h"
#include "recon_test_util.h"
#include "recon/pipeline.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

/* relMSE of a MAAF render at spp (pairs: --maaf-pairs), -1 on failure. */
static double maaf_error(unsigned seed, int spp, int pairs, const float *ref, size_t n3)
{
    SceneDesc scene;
    Renderer *r;
    if (!recon_test_renderer(SHADOW_SCENE, seed, spp, false, &scene, &r)) return -1.0;
    ReconOptions o = {.filter = "maaf", .spp = spp, .method_options = {pairs}};
    ReconPipeline *p = NULL;
    Diag d = {0};
    double err = -1.0;
    if (recon_pipeline_create(r, &o, &p, &d) && recon_pipeline_render(p, &d)) {
        const ReconResult *res = recon_pipeline_result(p);
        CHECK_STR(recon_choice_name(&res->choice, EFFECT_SOFT_SHADOWS), "maaf");
        CHECK_NEAR(res->spp_avg, spp, 0.0);
        bool finite = true;
        for (size_t i = 0; i < n3; ++i) finite = finite && isfinite(res->rgb[i]);
        CHECK(finite);
        CHECK(res->nonfinite_pixels == 0);
        /* the AOVs: every lit floor pixel near the occluder is filtered with (2N-1)^2 components */
        const float *comps = NULL, *std_px = NULL;
        for (int k = 0; k < res->aov_count; ++k) {
            if (!strcmp(res->aovs[k].name, "maaf.components.soft_shadows")) comps = res->aovs[k].data;
            if (!strcmp(res->aovs[k].name, "maaf.std_px.soft_shadows")) std_px = res->aovs[k].data;
        }
        CHECK(comps && std_px);
        int full = 0;
        for (size_t i = 0; comps && i < n3 / 3; ++i) full += comps[i] == (float)((2 * pairs - 1) * (2 * pairs - 1));
        CHECK(full > (int)(n3 / 3) / 10);
        err = rel_mse(res->rgb, ref, n3);
    } else {
        fprintf(stderr, "%s\n", d.message);
    }
    recon_pipeline_destroy(p);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return err;
}

int main(void)
{
    size_t n3 = 0;
    float *ref = recon_test_mc_image(SHADOW_SCENE, 7, 1024, &n3);
    CHECK(ref != NULL);
    if (!ref) CHECK_DONE();
    float *mc = recon_test_mc_image(SHADOW_SCENE, 1, 9, &n3);
    double err_mc = rel_mse(mc, ref, n3);
    double err9 = maaf_error(1, 9, 3, ref, n3), err36 = maaf_error(1, 36, 3, ref, n3);
    double err9_n1 = maaf_error(1, 9, 1, ref, n3), err144 = maaf_error(1, 144, 3, ref, n3);
    /* N = 2 on the light's axes is the default design of a soft-shadow frame (9.22) */
    double err9_n2 = maaf_error(1, 9, 2, ref, n3);
    printf("relMSE at 9 spp: Monte Carlo %.3g, MAAF %.3g (N = 1: %.3g, N = 2: %.3g); MAAF at 36 spp %.3g, 144 spp %.3g\n",
           err_mc, err9, err9_n1, err9_n2, err36, err144);
    CHECK(err9 > 0.0 && err36 > 0.0 && err144 > 0.0 && err9_n1 > 0.0 && err9_n2 > 0.0);
    /* the filter removes most of the noise: at 9 spp what is left of MAAF's error here is the
     * bias of a filter several pixels wide on a penumbra a few pixels wide (87% of it, two
     * seeds' cross term); with the central component's flat light factor (docs/algorithms.md
     * 9.20) 1.85e-3 against Monte Carlo's 3.43e-3, with c_0(y) as its weight 1.39e-3 (that
     * weight shrinks the light the central component sees, which sharpened this penumbra and
     * biased the bench scenes' smooth light). The margin is asserted for the design a user gets,
     * N = 2 on the light's axes (7.7e-4 here at 6 + 3 or 6.8e-4 at 8 + 1, docs/algorithms.md 9.24);
     * at N = 3 this bias-bound penumbra depends on pass 1's share (1.63e-3 at 8 + 1, 2.45e-3 at
     * 6 + 3), and N = 3 is held to converging below. */
    CHECK(1.5 * err9_n2 <= err_mc);
    /* and converges as the budget grows, at least half Monte Carlo's rate per 4x (a design
     * fixed at the default held both at 1.27e-3: its bias; kappa_for_budget) */
    CHECK(2.0 * err36 <= err9);
    CHECK(2.0 * err144 <= err36);
    free(mc);
    free(ref);
    CHECK_DONE();
}
