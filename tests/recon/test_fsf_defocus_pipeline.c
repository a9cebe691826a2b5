/* FSF for defocus end to end through the reconstruction pipeline, on the defocus bench scene
 * (scenes/bench/defocus.pbrt: a textured floor through the focal plane, spheres in front of,
 * on and behind it) at 96x96: defocus goes to fsf with --filter fsf and with
 * --filter defocus=fsf, the image is finite, the defocus AOVs are there and within their
 * bounds (no width where a pixel saw only the black sky), and at equal samples the error against a 1024-spp reference is below Monte Carlo's
 * and falls from 8 to 16 samples per pixel; every pixel's taps (to the lens grid's reach) stay
 * inside the image, and the border lets them reach it: some pixel at least 4 px from the
 * border has taps to its edge (with the cap of 2-sigma taps they stopped at 0.75 of it). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/fsf/fsf_lens.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"

enum { RES = 96 };

/* What only an FSF defocus frame has: the method chosen and its AOVs. */
static void check_fsf(const ReconPipeline *p, void *ctx)
{
    (void)ctx;
    const ReconResult *res = recon_pipeline_result(p);
    const GBuffer *g = recon_pipeline_gbuffer(p);
    size_t n = (size_t)res->width * (size_t)res->height;
    CHECK(!strcmp(recon_choice_name(&res->choice, EFFECT_DEFOCUS), "fsf"));
    const float *eta = recon_test_aov(res, "fsf.defocus.eta_lens_per_px"), *sigma = recon_test_aov(res, "fsf.defocus.sigma_px");
    CHECK(eta && sigma);
    size_t bad = 0, filtered = 0, hits = 0, sky_filtered = 0, outside = 0, to_edge = 0;
    FsfGrid lens = fsf_lens_grid();
    for (size_t i = 0; eta && sigma && g && i < n; ++i) {
        bad += !isfinite(eta[i]) || !(sigma[i] >= 0.0f && sigma[i] <= FSF_RADIUS_CAP_PX / FSF_RADIUS_SIGMAS);
        hits += g->hit[i] != 0;
        filtered += g->hit[i] && sigma[i] > 1.0f;
        sky_filtered += !g->hit[i] && sigma[i] > 0.0f;
        int x = (int)(i % (size_t)res->width), y = (int)(i / (size_t)res->width);
        int edge = x < y ? x : y;
        edge = edge < res->width - 1 - x ? edge : res->width - 1 - x;
        edge = edge < res->height - 1 - y ? edge : res->height - 1 - y;
        int r = fsf_tap_radius(&lens, sigma[i]);
        outside += r > edge;
        to_edge += edge >= 4 && r == edge;
    }
    CHECK(bad == 0);          /* a finite shear, a width within the 32-pixel cap */
    CHECK(filtered > hits / 4); /* the defocused floor and spheres are filtered */
    CHECK(sky_filtered == 0);   /* a pixel that saw only the black sky is left out (fsf_lens.c) */
    CHECK(outside == 0);      /* no tap beyond the border */
    CHECK(to_edge > 0);       /* the border cap lets the taps reach it */
}

static float *render(const char *text, const char *filter, unsigned seed, int spp)
{
    ReconOptions o = {.filter = filter, .spp = spp};
    bool fsf = strstr(filter, "fsf") != NULL;
    return recon_test_render_pipeline(text, seed, &o, fsf ? check_fsf : NULL, NULL);
}

int main(void)
{
    char *text = recon_test_bench_scene_at("defocus", RES);
    CHECK(text != NULL);
    if (!text) CHECK_DONE();
    size_t n3 = 3 * (size_t)RES * RES;
    float *ref = render(text, "none", 100, 1024);
    double e_fsf[2] = {0, 0}, e_mc[2] = {0, 0};
    const int spp[2] = {8, 16};
    for (int s = 0; s < 2 && ref; ++s)
        for (unsigned seed = 1; seed <= 2; ++seed) {
            float *f = render(text, seed == 1 ? "fsf" : "defocus=fsf", seed, spp[s]);
            float *mc = render(text, "none", seed, spp[s]);
            if (f && mc) e_fsf[s] += rel_mse(f, ref, n3) / 2, e_mc[s] += rel_mse(mc, ref, n3) / 2;
            free(f);
            free(mc);
        }
    for (int s = 0; s < 2; ++s)
        fprintf(stderr, "relMSE at %d spp (2 seeds): fsf %.4g, mc %.4g\n", spp[s], e_fsf[s], e_mc[s]);
    /* the reference's noise at 1024 spp is 64x below Monte Carlo's at 16 */
    CHECK(e_fsf[0] < 0.7 * e_mc[0]);
    CHECK(e_fsf[1] < 0.7 * e_mc[1]);
    CHECK(e_fsf[1] < 0.8 * e_fsf[0]); /* falls with samples (Monte Carlo: by half) */
    free(ref);
    free(text);
    CHECK_DONE();
}
