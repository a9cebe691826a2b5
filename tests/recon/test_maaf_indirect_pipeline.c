/* MAAF on indirect light through the reconstruction pipeline (docs/algorithms.md 9.12): the
 * indirect bench scene (scenes/bench/indirect.pbrt: a spot-lit room, its picture mostly one
 * bounce) at 64x64, `--filter maaf` and `--filter indirect=maaf`: the indirect light is
 * assigned to maaf, its relMSE against a 1024-spp reference is well below Monte Carlo's at
 * equal spp and falls as the budget grows, the image is finite, and the AOVs show most
 * receivers filtered with the pass's full design (without directions the bands |p|, |q| <= 1
 * of the N = 3 design: 3 x 3 filters, maaf_method.c's indirect_pass_pairs). Then the combined bench scene (soft
 * shadows, indirect light, defocus) with every effect maaf's: the defocus sums take over the
 * filtered indirect light (9.8's substitution) and the image stays finite. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon_test_util.h"

enum { RES = 64 };

typedef struct {
    int full, pixels;
} AovCount;

static void check_indirect(const ReconResult *res, void *ctx)
{
    AovCount *c = ctx;
    CHECK_STR(recon_choice_name(&res->choice, EFFECT_INDIRECT), "maaf");
    const float *comps = recon_test_aov(res, "maaf.components.indirect"), *std_px = recon_test_aov(res, "maaf.std_px.indirect");
    CHECK(comps && std_px);
    c->pixels = res->width * res->height;
    c->full = 0;
    for (int i = 0; comps && std_px && i < c->pixels; ++i) c->full += comps[i] == 9.0f && std_px[i] > 0.0f;
}

static void check_combined(const ReconResult *res, void *ctx)
{
    (void)ctx;
    CHECK_STR(recon_choice_name(&res->choice, EFFECT_INDIRECT), "maaf");
    CHECK_STR(recon_choice_name(&res->choice, EFFECT_SOFT_SHADOWS), "maaf");
    CHECK_STR(recon_choice_name(&res->choice, EFFECT_DEFOCUS), "maaf");
    CHECK(recon_test_aov(res, "maaf.std_px.indirect") != NULL);
    CHECK(recon_test_aov(res, "maaf.std_px.defocus") != NULL);
}

static bool finite_image(const float *rgb, size_t n3)
{
    bool ok = true;
    for (size_t i = 0; i < n3; ++i) ok = ok && isfinite(rgb[i]);
    return ok;
}

int main(void)
{
    char *text = recon_test_bench_scene_at("indirect", RES);
    CHECK(text != NULL);
    if (!text) CHECK_DONE();
    size_t n3 = (size_t)RES * RES * 3;
    ReconOptions plain = {.filter = "none", .spp = 1024};
    float *ref = recon_test_render(text, 99, &plain, NULL, NULL);
    CHECK(ref != NULL);
    const int spp[3] = {8, 32, 128};
    double err[3] = {0, 0, 0}, mc8 = 0.0;
    for (unsigned seed = 1; seed <= 2 && ref; ++seed) {
        ReconOptions mo = {.filter = "none", .spp = 8};
        float *mc = recon_test_render(text, seed, &mo, NULL, NULL);
        CHECK(mc != NULL);
        if (mc) mc8 += rel_mse(mc, ref, n3) / 2;
        free(mc);
        for (int k = 0; k < 3; ++k) {
            /* the per-effect form on one seed, the whole method on the other */
            ReconOptions o = {.filter = seed == 1 ? "maaf" : "indirect=maaf", .spp = spp[k]};
            AovCount c = {0, 0};
            float *rgb = recon_test_render(text, seed, &o, check_indirect, &c);
            CHECK(rgb != NULL);
            if (!rgb) continue;
            CHECK(finite_image(rgb, n3));
            err[k] += rel_mse(rgb, ref, n3) / 2;
            CHECK(c.full > c.pixels / 2);
            if (k == 0) printf("seed %u: %d of %d pixels filtered with 9 components\n", seed, c.full, c.pixels);
            free(rgb);
        }
    }
    printf("indirect %dx%d relMSE (2 seeds): Monte Carlo 8 spp %.3g; MAAF 8 spp %.3g, 32 spp %.3g, 128 spp %.3g\n", RES, RES,
           mc8, err[0], err[1], err[2]);
    CHECK(err[0] > 0.0 && err[0] < 0.25 * mc8); /* the filter removes most of the bounce noise */
    CHECK(err[1] < 0.7 * err[0]);                /* and converges as the budget grows */
    CHECK(err[2] < 0.7 * err[1]);
    free(ref);
    free(text);

    text = recon_test_bench_scene_at("combined", RES);
    CHECK(text != NULL);
    if (text) {
        ReconOptions o = {.filter = "maaf", .spp = 16};
        float *rgb = recon_test_render(text, 1, &o, check_combined, NULL);
        CHECK(rgb != NULL);
        if (rgb) CHECK(finite_image(rgb, n3));
        free(rgb);
    }
    free(text);
    CHECK_DONE();
}
