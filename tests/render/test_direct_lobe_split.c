/* The first hit's direct light split by lobe (SampleRecord.direct_glossy), checked per sample
 * and against a closed form.
 *
 * Scene: three quads side by side under a constant white sky (an `infinite` light, L = 1),
 * direct light only: a Lambert quad, a checkerboard of two base reflectances under a rough
 * dielectric coat (coateddiffuse), and a rough conductor.
 *
 *  - per sample: direct_glossy is +0 at a Lambert hit, all of the direct light at a conductor
 *    (to rounding), and between 0 and the direct light at the coated checks;
 *  - closed form: the coat's base lobe is f_d = s (1 - F(cos_o)) (1 - F(cos_i)) / pi
 *    (bsdf_glossy.c coated_base_f) and its albedo a_d = s (1 - F(cos_o)) (1 - fdr_ext), with
 *    fdr_ext = integral over the hemisphere of F(cos_i) cos_i / pi. So under a constant sky L
 *    the diffuse lobe's direct light over the diffuse albedo has the expectation
 *    L integral (1 - F(cos_i)) cos_i / pi dw / (1 - fdr_ext) = L, whatever the base and the
 *    viewing direction: the mean of (direct - direct_glossy) / albedo_diffuse over each check
 *    colour's samples must be 1 (within 3%: about 6 standard errors of the mean here);
 *  - the glossy lobe does not see the base: its mean light is the same over both check
 *    colours (within 5%; the two colours sample the same viewing directions).
 * A split that kept the BSDF sample's glossy part in the diffuse part (only the light sample
 * split) gave ratio means of 1.64 (dark) / 1.04 (bright) and failed. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "render_test_util.h"

static const char *SCENE =
    "LookAt 0 4 -3  0 0 0.3  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 60 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 64 ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n"
    "AttributeBegin\n"
    "  Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -3 0 -2  -1 0 -2  -1 0 3  -3 0 3 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    "  Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 8 ] \"float vscale\" [ 8 ]"
    " \"rgb tex1\" [ 0.8 0.8 0.8 ] \"rgb tex2\" [ 0.1 0.1 0.1 ]\n"
    "  Material \"coateddiffuse\" \"texture reflectance\" \"checks\" \"float roughness\" [ 0.2 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -1 0 -2  1 0 -2  1 0 3  -1 0 3 ] \"integer indices\" [ 0 2 1 0 3 2 ]"
    " \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    "  Material \"conductor\" \"float roughness\" [ 0.2 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ 1 0 -2  3 0 -2  3 0 3  1 0 3 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
    "AttributeEnd\n";

typedef struct {
    long lambert, lambert_bad, conductor, conductor_bad, coated_bad;
    long n[2];             /* coated samples per check colour (0: dark, 1: bright) */
    double ratio_sum[2];   /* (direct - direct_glossy) / albedo_diffuse, green channel */
    double glossy_sum[2];  /* direct_glossy, green channel */
} Tally;

/* |a - b| within rounding of sums of a few terms of magnitude m */
static bool near(float a, float b, float m) { return fabsf(a - b) <= 1e-5f * (m + 1e-6f); }

static void sink_add(void *ctx, int px, int py, const SampleRecord *r)
{
    (void)px, (void)py;
    Tally *t = ctx;
    if (!r->hit) return;
    float d[3] = {r->direct.x, r->direct.y, r->direct.z}, g[3] = {r->direct_glossy.x, r->direct_glossy.y, r->direct_glossy.z};
    float m = fmaxf(d[0], fmaxf(d[1], d[2]));
    if (r->albedo_glossy.x == 0.0f) { /* Lambert */
        t->lambert++;
        for (int k = 0; k < 3; ++k) t->lambert_bad += !(g[k] == 0.0f && !signbit(g[k]));
    } else if (r->albedo_diffuse.x == 0.0f) { /* conductor */
        t->conductor++;
        for (int k = 0; k < 3; ++k) t->conductor_bad += !near(g[k], d[k], m);
    } else { /* coated */
        for (int k = 0; k < 3; ++k) t->coated_bad += !(g[k] >= 0.0f && g[k] <= d[k] * (1.0f + 1e-5f) + 1e-7f);
        int c = r->albedo_diffuse.y > 0.3f;
        t->n[c]++;
        t->ratio_sum[c] += (r->direct.y - r->direct_glossy.y) / r->albedo_diffuse.y;
        t->glossy_sum[c] += r->direct_glossy.y;
    }
}

int main(void)
{
    Tally t;
    memset(&t, 0, sizeof t);
    SampleSink sink = {sink_add, &t};
    RenderOptions o = {0};
    o.seed = 3;
    o.threads = 1;
    TestRender tr;
    CHECK(test_render_sink(SCENE, &o, &sink, &tr));
    test_render_free(&tr);
    double ratio[2], glossy[2];
    for (int c = 0; c < 2; ++c) {
        ratio[c] = t.n[c] > 0 ? t.ratio_sum[c] / (double)t.n[c] : NAN;
        glossy[c] = t.n[c] > 0 ? t.glossy_sum[c] / (double)t.n[c] : NAN;
    }
    fprintf(stderr, "lambert %ld (bad %ld), conductor %ld (bad %ld), coated dark %ld / bright %ld (bad %ld)\n", t.lambert,
            t.lambert_bad, t.conductor, t.conductor_bad, t.n[0], t.n[1], t.coated_bad);
    fprintf(stderr, "diffuse direct / albedo_diffuse: dark %.4f, bright %.4f (closed form 1); glossy: %.4f / %.4f\n",
            ratio[0], ratio[1], glossy[0], glossy[1]);
    CHECK(t.lambert > 1000 && t.conductor > 1000 && t.n[0] > 1000 && t.n[1] > 1000);
    CHECK(t.lambert_bad == 0 && t.conductor_bad == 0 && t.coated_bad == 0);
    CHECK(fabs(ratio[0] - 1.0) < 0.03 && fabs(ratio[1] - 1.0) < 0.03);
    CHECK(fabs(glossy[0] / glossy[1] - 1.0) < 0.05);
    CHECK_DONE();
}
