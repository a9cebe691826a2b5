/* FSF's shadow filter beside a light it does not filter along. FSF shears along one planar
 * light; a sample whose shadow ray went to another emitter has a light point off that light, so
 * the light's box profile gives it no weight and the filter averages the pixel's other samples
 * alone. Each sample's value is the chosen light's share over its choice probability, so that
 * average is the pixel's light over the probability of choosing FSF's light: the filter must
 * match its samples to the pixel's mean over those on its light, not over all of them (a
 * random scene with a small sphere light beside a triangle light came out 1.5x too bright
 * where it was filtered). The scene: the small soft-shadow scene (recon_test_util.h) and a
 * far sphere light of about the quad's power, so that it is picked for about half the shadow
 * rays while giving the floor under a tenth of its light (FSF's share rule still filters
 * there). The filtered pixels' mean must be the reference's within the noise. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"

enum { W = 40, H = 40 };

static float filtered[W * H]; /* fsf.sigma_px of the last FSF frame */

static void keep_sigma(const ReconResult *res, void *ctx)
{
    (void)ctx;
    for (int k = 0; k < res->aov_count; ++k)
        if (!strcmp(res->aovs[k].name, "fsf.sigma_px")) memcpy(filtered, res->aovs[k].data, sizeof filtered);
}

int main(void)
{
    char text[8192];
    snprintf(text, sizeof text,
             "%sAttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 18 18 18 ]\n  Translate 10 12 6\n"
             "  Shape \"sphere\" \"float radius\" [ 0.3 ]\nAttributeEnd\n",
             SHADOW_SCENE);
    ReconOptions none = {.filter = "none", .spp = 1024};
    float *ref = recon_test_render(text, 100, &none, NULL, NULL);
    double fsf_sum = 0.0, ref_sum = 0.0, mc_sum = 0.0;
    int pixels = 0;
    for (unsigned seed = 1; seed <= 2 && ref; ++seed) {
        ReconOptions fo = {.filter = "fsf", .spp = 16}, mo = {.filter = "none", .spp = 16};
        memset(filtered, 0, sizeof filtered);
        float *f = recon_test_render(text, seed, &fo, keep_sigma, NULL);
        float *mc = recon_test_render(text, seed, &mo, NULL, NULL);
        for (int i = 0; f && mc && i < W * H; ++i) {
            if (!(filtered[i] > 1.0f)) continue;
            ++pixels;
            for (int c = 0; c < 3; ++c) fsf_sum += f[3 * i + c], ref_sum += ref[3 * i + c], mc_sum += mc[3 * i + c];
        }
        free(f);
        free(mc);
    }
    free(ref);
    double fsf_ratio = ref_sum > 0.0 ? fsf_sum / ref_sum : 0.0, mc_ratio = ref_sum > 0.0 ? mc_sum / ref_sum : 0.0;
    fprintf(stderr, "%d filtered pixels (2 seeds): mean over the reference's: fsf %.4f, Monte Carlo %.4f\n", pixels,
            fsf_ratio, mc_ratio);
    CHECK(pixels > W * H / 4); /* the floor is filtered, not passed through by the share rule */
    CHECK(fabs(mc_ratio - 1.0) < 0.02);
    CHECK(fabs(fsf_ratio - 1.0) < 0.03);
    CHECK_DONE();
}
