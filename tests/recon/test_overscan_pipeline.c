/* Overscan through the pipeline (--filter lr): LR reprojects samples from up to its window
 * margin (8 px) away, so at the image border, without a traced band, it integrates only the
 * part of the lens domain whose sources lie inside the frame: bias. The scene puts a bright,
 * strongly defocused strip just above the top of the frame (its circle of confusion reaches
 * about 6 px into the image) in front of an in-focus textured wall. Against a high-spp Monte
 * Carlo reference, over four seeds at 8 spp:
 *  - the error of the 8-pixel border band falls with overscan (ReconOptions.no_overscan
 *    false) against without it (true);
 *  - the interior's error does not change beyond its seed-to-seed noise (4 standard errors
 *    of the difference of the two means);
 *  - the result is the visible 64x48 image: size, overscan_px, spp_avg = samples traced per
 *    visible pixel (closed form), AOV layers and guides of the visible size, every visible
 *    pixel with its 8 samples, pixels_filtered = the visible pixels.
 * Checked to fail: with LR's overscan_px returning 0 the two runs are the same images and the
 * border assertion and the overscan_px checks fail. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"
#include "scene/scene_desc.h"

enum { W = 64, H = 48, BAND = 8, SPP = 8, SEEDS = 4 };

static const char *const SCENE =
    "LookAt 0 1 -5   0 1 0   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ] \"float lensradius\" [ 0.4 ] \"float focaldistance\" [ 9 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 48 ] \"string filename\" [ \"t.exr\" ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 8 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "LightSource \"distant\" \"rgb L\" [ 2 2 2 ] \"point3 from\" [ 0 0 -1 ] \"point3 to\" [ 0 0 0 ]\n"
    "AttributeBegin\n"
    "  Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 10 ] \"float vscale\" [ 10 ]\n"
    "          \"rgb tex1\" [ 0.8 0.8 0.8 ] \"rgb tex2\" [ 0.1 0.1 0.1 ]\n"
    "  Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -8 -5 4  8 -5 4  8 8 4  -8 8 4 ] \"integer indices\" [ 0 1 2 0 2 3 ]"
    " \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n"
    "AttributeEnd\n"
    /* 3 units from the camera the frame's top edge is at y = 1 + 3 tan(20 deg) = 2.09: the
     * strip starts 0.06 above it */
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 6 6 6 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -4 2.15 -2  4 2.15 -2  4 3 -2  -4 3 -2 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
    "AttributeEnd\n";

/* The result is the visible image, with what the outputs read of the visible size. */
static void check_visible(const ReconResult *res, const GBuffer *g, bool overscan)
{
    size_t n = (size_t)W * H;
    CHECK(res->width == W && res->height == H);
    CHECK(res->overscan_px == (overscan ? BAND : 0));
    int m = res->overscan_px;
    double traced = (double)(W + 2 * m) * (double)(H + 2 * m);
    CHECK_NEAR(res->spp_avg, SPP * traced / (double)n, 1e-9);
    CHECK(res->pixels_filtered[EFFECT_DEFOCUS] == (long long)n);
    CHECK(res->aov_count > 0);
    for (int k = 0; k < res->aov_count; ++k) { /* all n values readable (ASan) and finite */
        double s = 0.0;
        for (size_t i = 0; i < n; ++i) s += res->aovs[k].data[i];
        CHECK(isfinite(s));
    }
    CHECK(g->width == W && g->height == H && g->frame.width == W && g->frame.height == H);
    int wrong = 0;
    for (size_t i = 0; i < n; ++i) wrong += g->frame.spp[i] != (float)SPP || !(g->frame.hits[i] >= 0.0f);
    CHECK(wrong == 0);
}

typedef struct {
    double border, interior;
} BandError;

static BandError band_error(const float *img, const float *ref)
{
    double sum[2] = {0, 0};
    long cnt[2] = {0, 0};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int edge = x < BAND || y < BAND || x >= W - BAND || y >= H - BAND;
            size_t i = 3 * ((size_t)y * W + (size_t)x);
            double e = rel_mse(img + i, ref + i, 3);
            sum[!edge] += e, cnt[!edge]++;
        }
    return (BandError){sum[0] / (double)cnt[0], sum[1] / (double)cnt[1]};
}

static void check_frame(const ReconPipeline *p, void *ctx)
{
    check_visible(recon_pipeline_result(p), recon_pipeline_gbuffer(p), *(const bool *)ctx);
}

static float *render_lr(unsigned seed, bool overscan)
{
    ReconOptions o = {.filter = "lr", .spp = SPP, .no_overscan = !overscan};
    return recon_test_render_pipeline(SCENE, seed, &o, check_frame, &overscan);
}

static void mean_se(const double *v, int k, double *mean, double *se)
{
    double m = 0.0, s = 0.0;
    for (int i = 0; i < k; ++i) m += v[i];
    m /= k;
    for (int i = 0; i < k; ++i) s += (v[i] - m) * (v[i] - m);
    *mean = m;
    *se = sqrt(s / (k - 1) / k);
}

int main(void)
{
    ReconOptions mc = {.filter = "none", .spp = 512};
    float *ref = recon_test_render(SCENE, 100, &mc, NULL, NULL);
    CHECK(ref != NULL);
    double border[2][SEEDS], interior[2][SEEDS];
    for (unsigned s = 0; s < SEEDS && ref; ++s)
        for (int on = 0; on < 2; ++on) {
            float *img = render_lr(s + 1, on);
            CHECK(img != NULL);
            if (!img) continue;
            BandError e = band_error(img, ref);
            border[on][s] = e.border, interior[on][s] = e.interior;
            free(img);
        }
    if (ref) {
        double bm[2], bse[2], im[2], ise[2];
        for (int on = 0; on < 2; ++on) {
            mean_se(border[on], SEEDS, &bm[on], &bse[on]);
            mean_se(interior[on], SEEDS, &im[on], &ise[on]);
        }
        printf("relMSE at %d spp (%d seeds), border band %d px: without overscan %.4g (+-%.2g), with %.4g (+-%.2g); "
               "interior %.4g (+-%.2g) and %.4g (+-%.2g)\n",
               SPP, SEEDS, BAND, bm[0], bse[0], bm[1], bse[1], im[0], ise[0], im[1], ise[1]);
        CHECK(bm[1] < bm[0]);
        CHECK(fabs(im[1] - im[0]) <= 4.0 * sqrt(ise[0] * ise[0] + ise[1] * ise[1]));
    }
    free(ref);
    CHECK_DONE();
}
