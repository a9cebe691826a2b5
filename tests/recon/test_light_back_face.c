/* Pixels that see the back of a one-sided area light, lit by another light. The shadow
 * filters divide each pixel's direct light by the unoccluded irradiance r(x) from every
 * emitter and multiply the filtered quotient back; a receiver on the light's own surface lies
 * in its plane, where the light subtends no solid angle, but Lambert's polygon formula (every
 * edge on the receiver's horizon) gave it anything up to pi, by the rounding of the hit point
 * off the plane: those pixels came out up to 14x too bright (AAF on this scene: 39x Monte
 * Carlo's relMSE at 16 spp; a random scene with a disk light seen edge on: 13x). The scene: a
 * quad light facing down, seen from above, and a sphere light above it. Every filter's error
 * at 16 spp must be below Monte Carlo's at 16 spp, and the light's back must have the
 * reference's mean. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"

enum { W = 64, H = 48 };

static const char *const SCENE =
    "LookAt 0 6 -4   0 2 0.5   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 50 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 48 ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.8 2 -0.8  0.8 2 -0.8  0.8 2 0.8  -0.8 2 0.8 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\n"
    "  Translate 2 5 1\n"
    "  Shape \"sphere\" \"float radius\" [ 0.3 ]\n"
    "AttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ 0.3 1 -0.3  0.9 1 -0.3  0.9 1 0.3  0.3 1 0.3 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n";

static bool back[W * H]; /* the pixels whose samples all hit the light's back (y = 2) */

static void find_back(const ReconPipeline *p, void *ctx)
{
    (void)ctx;
    const GBuffer *g = recon_pipeline_gbuffer(p);
    CHECK(g && g->mixed && g->pos4);
    for (int i = 0; g && g->mixed && g->pos4 && i < W * H; ++i)
        back[i] = g->hit[i] && !g->mixed[i] && fabsf(g->pos4[4 * i + 1] - 2.0f) < 1e-3f;
}

int main(void)
{
    ReconOptions ro = {.filter = "none", .spp = 1024};
    float *ref = recon_test_render(SCENE, 100, &ro, NULL, NULL);
    ReconOptions guides = {.filter = "aaf", .spp = 16}; /* a frame with guides, for the pixels' surfaces */
    free(recon_test_render_pipeline(SCENE, 1, &guides, find_back, NULL));
    int back_count = 0;
    for (int i = 0; i < W * H; ++i) back_count += back[i];
    const char *filters[] = {"aaf", "maaf", "fsf"};
    double e_mc = ref ? recon_test_seeds_rel_mse(SCENE, "none", 16, 2, ref, 3 * W * H) : 0.0;
    for (int f = 0; f < 3 && ref; ++f) {
        double e = 0.0, sum = 0.0, sum_ref = 0.0;
        for (unsigned seed = 1; seed <= 2; ++seed) {
            ReconOptions fo = {.filter = filters[f], .spp = 16};
            float *img = recon_test_render(SCENE, seed, &fo, NULL, NULL);
            CHECK(img != NULL);
            if (!img) continue;
            e += rel_mse(img, ref, 3 * W * H) / 2;
            for (int i = 0; i < W * H; ++i)
                for (int c = 0; back[i] && c < 3; ++c) sum += img[3 * i + c], sum_ref += ref[3 * i + c];
            free(img);
        }
        double ratio = sum_ref > 0.0 ? sum / sum_ref : 0.0;
        fprintf(stderr, "%s: relMSE %.4g (Monte Carlo %.4g), the light's back (%d pixels) %.4f of the reference\n",
                filters[f], e, e_mc, back_count, ratio);
        CHECK(e < e_mc);
        CHECK(fabs(ratio - 1.0) < 0.05);
    }
    CHECK(back_count > 50);
    free(ref);
    CHECK_DONE();
}
