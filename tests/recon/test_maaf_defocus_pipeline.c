/* MAAF for defocus through the reconstruction pipeline on the defocus bench scene
 * (scenes/bench/defocus.pbrt: a floor from in front of the focal plane to far behind it, spheres
 * on both sides of it) at its own 128x128: at equal spp its relMSE against a high-spp reference is below
 * Monte Carlo's, it falls as the count grows, the image is finite, and the AOVs show both
 * filtered pixels (the full (2N-1)^2 components) and unfiltered ones (near the focal plane). */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mc_render.h"
#include "recon_test_util.h"

typedef struct {
    int full, none, pixels;
} AovCount;

static void check_result(const ReconResult *res, void *ctx)
{
    AovCount *c = ctx;
    CHECK_STR(recon_choice_name(&res->choice, EFFECT_DEFOCUS), "maaf");
    const float *comps = NULL, *std_px = NULL;
    for (int k = 0; k < res->aov_count; ++k) {
        if (!strcmp(res->aovs[k].name, "maaf.components.defocus")) comps = res->aovs[k].data;
        if (!strcmp(res->aovs[k].name, "maaf.std_px.defocus")) std_px = res->aovs[k].data;
    }
    CHECK(comps && std_px);
    c->pixels = res->width * res->height;
    for (int i = 0; comps && std_px && i < c->pixels; ++i) {
        c->full += comps[i] == 25.0f && std_px[i] > 0.0f;
        c->none += comps[i] == 0.0f && std_px[i] == 0.0f;
    }
}

int main(void)
{
    char *text = recon_test_bench_scene("defocus", 0);
    CHECK(text != NULL);
    if (!text) CHECK_DONE();
    size_t n3 = 0;
    float *ref = recon_test_mc_image(text, 7, 1024, &n3), *mc = recon_test_mc_image(text, 1, 8, &n3);
    CHECK(ref && mc);
    double err_mc = rel_mse(mc, ref, n3), err[3] = {-1.0, -1.0, -1.0};
    const int spp[3] = {8, 32, 128};
    for (int k = 0; k < 3; ++k) {
        ReconOptions o = {.filter = "maaf", .spp = spp[k]};
        AovCount c = {0, 0, 0};
        float *rgb = recon_test_render(text, 1, &o, check_result, &c);
        CHECK(rgb != NULL);
        if (!rgb) continue;
        bool finite = true;
        for (size_t i = 0; i < n3; ++i) finite = finite && isfinite(rgb[i]);
        CHECK(finite);
        err[k] = rel_mse(rgb, ref, n3);
        printf("%d spp: %d of %d pixels filtered with 25 components, %d not filtered\n", spp[k], c.full, c.pixels, c.none);
        CHECK(c.full > c.pixels / 4);
        CHECK(c.none > 0);
        free(rgb);
    }
    printf("relMSE: Monte Carlo 8 spp %.3g, MAAF 8 spp %.3g, 32 spp %.3g, 128 spp %.3g\n", err_mc, err[0], err[1], err[2]);
    CHECK(err[0] > 0.0 && err[1] > 0.0 && err[2] > 0.0);
    CHECK(err[0] < err_mc); /* the filter removes lens noise */
    CHECK(err[1] < err[0]); /* and converges with more samples, past the default frame's too */
    CHECK(err[2] < err[1]);
    free(ref);
    free(mc);
    free(text);
    CHECK_DONE();
}
