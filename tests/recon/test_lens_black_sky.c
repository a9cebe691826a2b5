/* Bright defocused emitters over a black sky (no environment light). A pixel whose samples all
 * escaped holds no light wherever it looked, so the lens filter leaves it as it is (AAF since
 * docs/algorithms.md 3.2; FSF since 2026-12-02, recon/background.h): before, FSF's lens filter
 * gathered the emitters' light into those pixels, a square halo round every small defocused
 * light (bokeh_bright at 128x96, 16 spp: 4.9x Monte Carlo's relMSE; here 14.6x). Both must leave
 * each all-escaped pixel black and reach an error at 16 spp below Monte Carlo's. (MAAF's lens
 * still fills some of them, 24 of 3838 here: the same rule cost it 10% on the defocus bench
 * scene, docs/benchmarks.md "Random scenes, second round".) */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"

enum { W = 64, H = 48 };

static const char *const SCENE =
    "LookAt 0 1 -5   0 1 0   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ] \"float lensradius\" [ 0.12 ] \"float focaldistance\" [ 5 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 48 ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 40 40 40 ]\n"
    "  Translate -0.5 1.6 -2.5\n"
    "  Shape \"sphere\" \"float radius\" [ 0.06 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 40 20 10 ]\n"
    "  Translate 0.6 1.9 -2\n"
    "  Shape \"sphere\" \"float radius\" [ 0.05 ]\n"
    "AttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n";

static bool escaped[W * H]; /* pixels none of whose samples hit anything */

static void find_escaped(const ReconPipeline *p, void *ctx)
{
    (void)ctx;
    const GBuffer *g = recon_pipeline_gbuffer(p);
    CHECK(g && g->hit);
    for (int i = 0; g && g->hit && i < W * H; ++i) escaped[i] = !g->hit[i];
}

int main(void)
{
    ReconOptions ro = {.filter = "none", .spp = 1024};
    float *ref = recon_test_render(SCENE, 100, &ro, NULL, NULL);
    double e_mc = ref ? recon_test_seeds_rel_mse(SCENE, "none", 16, 2, ref, 3 * W * H) : 0.0;
    /* the lens filters alone (the shadows of these sphere lights are not what is tested, and fsf
     * filters those of triangle lights only) */
    const char *filters[] = {"soft_shadows=none,defocus=aaf", "soft_shadows=none,defocus=fsf"};
    for (int f = 0; f < 2 && ref; ++f) {
        double e = 0.0;
        int count = 0, lit = 0;
        for (unsigned seed = 1; seed <= 2; ++seed) {
            ReconOptions fo = {.filter = filters[f], .spp = 16};
            float *img = recon_test_render_pipeline(SCENE, seed, &fo, find_escaped, NULL);
            CHECK(img != NULL);
            if (!img) continue;
            e += rel_mse(img, ref, 3 * W * H) / 2;
            for (int i = 0; i < W * H; ++i) {
                count += escaped[i];
                lit += escaped[i] && img[3 * i] + img[3 * i + 1] + img[3 * i + 2] != 0.0f;
            }
            free(img);
        }
        fprintf(stderr, "%s: relMSE %.4g (Monte Carlo %.4g), %d of %d all-escaped pixels not black\n", filters[f], e, e_mc, lit,
                count);
        CHECK(e < e_mc);
        CHECK(count > 1000); /* the sky: most of the upper half */
        CHECK(lit == 0);
    }
    free(ref);
    CHECK_DONE();
}
