/* AAF through the reconstruction pipeline, end to end on small scenes (pipeline.c and
 * aaf/aaf_method.c with the real renderer):
 *  - soft shadows: at equal average spp, AAF's relMSE against a high-spp reference is at
 *    least 2x lower than plain Monte Carlo's (issue 6), and the error keeps falling along a
 *    mu sweep (consistency);
 *  - a scene with all three effects: every layer finite, every effect filtered, spp map
 *    consistent with the frame.
 * Images are tiny so that the test stays fast under sanitizers. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon_test_util.h"
#include "recon/aaf/aaf_params.h"
#include "recon/pipeline.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

/* Soft shadows, one-bounce indirect light from a red wall, and a thin lens. */
static const char *ALL_EFFECTS_SCENE =
    "LookAt 0 1.2 -4   0 0.5 0   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ] \"float lensradius\" [ 0.1 ] \"float focaldistance\" [ 4 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 20 ] \"string filename\" [ \"t.exr\" ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 2 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 10 10 10 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.5 3 -0.5  0.5 3 -0.5  0.5 3 0.5  -0.5 3 0.5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.6 0.6 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -3 0 -5  3 0 -5  3 0 3  -3 0 3 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
    "AttributeBegin\n"
    "  Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.1 0.1 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -3 0 1.5  3 0 1.5  3 3 1.5  -3 3 1.5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    "  Translate 0.2 0.5 0\n"
    "  Shape \"sphere\" \"float radius\" [ 0.5 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    "  Translate -0.9 0.3 -1.5\n"
    "  Shape \"sphere\" \"float radius\" [ 0.3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n" /* glass: unfilterable, its light passes through the filters */
    "  Material \"dielectric\" \"float eta\" [ 1.5 ]\n"
    "  Translate 0.9 0.3 -1.0\n"
    "  Shape \"sphere\" \"float radius\" [ 0.3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n" /* glossy coat: phong exponent and a delta-free glossy lobe */
    "  Material \"coateddiffuse\" \"rgb reflectance\" [ 0.2 0.5 0.2 ] \"float roughness\" [ 0.05 ]\n"
    "  Translate -0.3 0.2 -2.0\n"
    "  Shape \"sphere\" \"float radius\" [ 0.2 ]\n"
    "AttributeEnd\n";

/* Indirect light only: a point light (hard shadows, no shadow filter) beside a red wall; the
 * floor and a sphere get one bounce of red light. */
static const char *INDIRECT_SCENE =
    "LookAt 0 2.5 -4   0 0.3 0.5   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 64 ] \"string filename\" [ \"t.exr\" ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 2 ]\n"
    "WorldBegin\n"
    "LightSource \"point\" \"rgb I\" [ 6 6 6 ] \"point3 from\" [ 0.5 2.5 0 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.6 0.6 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -3 0 -5  3 0 -5  3 0 3  -3 0 3 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
    "AttributeBegin\n"
    "  Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.1 0.1 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -3 0 1.5  3 0 1.5  3 3 1.5  -3 3 1.5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n"
    "AttributeBegin\n"
    "  Translate -0.4 0.4 0.3\n"
    "  Shape \"sphere\" \"float radius\" [ 0.4 ]\n"
    "AttributeEnd\n";

/* Defocus only: focused on an empty plane between a sphere (in front) and a checkered wall
 * (behind), lit by a point light: every surface is out of focus, the regime the defocus
 * filter is for. */
static const char *DEFOCUS_SCENE =
    "LookAt 0 0.5 -3   0 0.5 1   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ] \"float lensradius\" [ 0.5 ] \"float focaldistance\" [ 3.5 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 128 ] \"integer yresolution\" [ 128 ] \"string filename\" [ \"t.exr\" ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "LightSource \"point\" \"rgb I\" [ 20 20 20 ] \"point3 from\" [ 0 2 -2 ]\n"
    "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" [ 10 ] \"float vscale\" [ 10 ]\n"
    "        \"rgb tex1\" [ 0.9 0.9 0.9 ] \"rgb tex2\" [ 0.1 0.1 0.1 ]\n"
    "Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -4 -3 4  4 -3 4  4 4 4  -4 4 4 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "  \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.7 0.2 ]\n"
    "AttributeBegin\n"
    "  Translate 0.3 0.4 -0.5\n"
    "  Shape \"sphere\" \"float radius\" [ 0.3 ]\n"
    "AttributeEnd\n";

/* Motion blur and defocus over soft shadows (issue 6, the dark speckled ring of the default
 * scene): a sphere in front of the focal plane moving across a lit floor during the shutter,
 * so the pixels around it mix sphere and floor samples (over the shutter and over the lens). */
static const char *MOTION_SCENE =
    "LookAt 0 1.6 -5.5   0 0.6 0   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 30 ] \"float lensradius\" [ 0.08 ] \"float focaldistance\" [ 5.6 ]\n"
    "  \"float shutteropen\" [ 0 ] \"float shutterclose\" [ 1 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 36 ] \"string filename\" [ \"t.exr\" ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 18 17 15 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.6 3 -0.6  0.6 3 -0.6  0.6 3 0.6  -0.6 3 0.6 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.6 0.6 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -6  4 0 -6  4 0 3  -4 0 3 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
    "AttributeBegin\n"
    "  Material \"diffuse\" \"rgb reflectance\" [ 0.15 0.25 0.8 ]\n"
    "  ActiveTransform StartTime\n"
    "  Translate -0.5 0.35 -1.6\n"
    "  ActiveTransform EndTime\n"
    "  Translate 0.0 0.35 -1.6\n"
    "  ActiveTransform All\n"
    "  Shape \"sphere\" \"float radius\" [ 0.35 ]\n"
    "AttributeEnd\n";

/* Plain Monte Carlo image (mean colour), 3 floats per pixel. */
static float *render_mc(const char *text, unsigned seed, int spp, int *w, int *h)
{
    SceneDesc scene;
    Renderer *r;
    if (!recon_test_renderer(text, seed, spp, false, &scene, &r)) return NULL;
    *w = renderer_width(r);
    *h = renderer_height(r);
    Frame f;
    frame_init(&f, *w, *h);
    render_pass(r, 0, NULL, spp, &f, NULL);
    float *rgb = malloc(3 * sizeof(float) * (size_t)(*w) * (size_t)(*h));
    frame_resolve3(&f, f.color, rgb);
    frame_free(&f);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return rgb;
}

/* One filtered render through the pipeline; free with run_free. */
typedef struct {
    SceneDesc scene;
    Renderer *r;
    ReconPipeline *p;
    const ReconResult *res;
    const float *spp;   /* the frame's samples per pixel */
} Run;

static void run_free(Run *run)
{
    recon_pipeline_destroy(run->p);
    renderer_destroy(run->r);
    scene_desc_free(&run->scene);
    memset(run, 0, sizeof *run);
}

static bool render_filtered(const char *text, unsigned seed, float mu, int spp_budget, Run *run)
{
    memset(run, 0, sizeof *run);
    if (!recon_test_renderer(text, seed, 16, false, &run->scene, &run->r)) return false;
    ReconOptions o = {.filter = "aaf", .mu = mu, .spp = spp_budget};
    Diag d = {0};
    bool ok = recon_pipeline_create(run->r, &o, &run->p, &d) && recon_pipeline_render(run->p, &d);
    if (!ok) {
        fprintf(stderr, "%s\n", d.message);
        run_free(run);
        return false;
    }
    run->res = recon_pipeline_result(run->p);
    const Frame *f = &recon_pipeline_gbuffer(run->p)->frame;
    run->spp = f->spp;
    double sum = 0;
    for (int i = 0; i < f->width * f->height; ++i) sum += f->spp[i];
    CHECK_NEAR(run->res->spp_avg, sum / (f->width * f->height), 1e-6 * run->res->spp_avg);
    return true;
}

/* The AOV layer called name, or NULL. */
static const float *aov(const ReconResult *res, const char *name)
{
    for (int k = 0; k < res->aov_count; ++k)
        if (!strcmp(res->aovs[k].name, name)) return res->aovs[k].data;
    return NULL;
}

/* The Monte Carlo side of an equal-spp comparison: the smallest square count >= spp_avg, so
 * the stratified sampler gets a full k x k grid (a prime count would stratify it in strips
 * only and flatter the filter). */
static int mc_spp_at_least(double spp_avg)
{
    int k = (int)ceil(sqrt(spp_avg) - 1e-9);
    return k * k;
}

static bool all_finite(const float *a, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(a[i])) return false;
    return true;
}

static void test_shadows_beat_monte_carlo_and_converge(void)
{
    int w = 0, h = 0;
    float *ref = render_mc(SHADOW_SCENE, 99, 512, &w, &h);
    CHECK(ref != NULL);
    if (!ref) return;
    size_t n3 = 3 * (size_t)w * (size_t)h;
    double prev = 1e30;
    float mus[3] = {1.0f, 2.0f, 4.0f};
    for (int m = 0; m < 3; ++m) {
        Run run;
        CHECK(render_filtered(SHADOW_SCENE, 1, mus[m], 0, &run));
        if (!run.res) continue;
        ReconResult res = *run.res;
        CHECK_STR(recon_choice_name(&res.choice, EFFECT_SOFT_SHADOWS), "aaf");
        CHECK_STR(recon_choice_name(&res.choice, EFFECT_INDIRECT), "none");
        CHECK(all_finite(res.rgb, n3));
        double err = rel_mse(res.rgb, ref, n3);
        /* Monte Carlo with (at least) the same average number of samples per pixel */
        float *mc = render_mc(SHADOW_SCENE, 2, mc_spp_at_least(res.spp_avg), &w, &h);
        double err_mc = mc ? rel_mse(mc, ref, n3) : 0.0;
        fprintf(stderr, "mu %.0f: spp_avg %.2f relMSE aaf %.3g, mc %.3g (ratio %.2f)\n", mus[m], res.spp_avg, err,
                err_mc, err_mc / err);
        if (mus[m] == 2.0f) CHECK(2.0 * err <= err_mc); /* issue 6: >= 2x lower at the default mu */
        CHECK(err < prev);                               /* consistency: falls as mu grows */
        prev = err;
        free(mc);
        run_free(&run);
    }
    free(ref);
}

/* Issue 6: at equal average spp, AAF's relMSE is at least 2x lower than Monte Carlo's, at
 * the default mu (indirect light, defocus); and consistency: at twice the default mu the
 * error is lower still. */
static void test_beats_monte_carlo(const char *name, const char *scene, Effect effect, float mu_default)
{
    int w = 0, h = 0;
    float *ref = render_mc(scene, 99, 256, &w, &h);
    CHECK(ref != NULL);
    if (!ref) return;
    size_t n3 = 3 * (size_t)w * (size_t)h;
    Run run;
    CHECK(render_filtered(scene, 1, 0.0f, 0, &run));
    if (run.res) {
        ReconResult res = *run.res;
        CHECK_STR(recon_choice_name(&res.choice, effect), "aaf");
        CHECK(all_finite(res.rgb, n3));
        double err = rel_mse(res.rgb, ref, n3);
        float *mc = render_mc(scene, 2, mc_spp_at_least(res.spp_avg), &w, &h);
        double err_mc = mc ? rel_mse(mc, ref, n3) : 0.0;
        fprintf(stderr, "%s: spp_avg %.2f relMSE aaf %.3g, mc %.3g (ratio %.2f)\n", name, res.spp_avg, err, err_mc,
                err_mc / err);
        CHECK(2.0 * err <= err_mc);
        free(mc);
        run_free(&run);
        Run run2;
        CHECK(render_filtered(scene, 1, 2.0f * mu_default, 0, &run2));
        if (run2.res) {
            double err2 = rel_mse(run2.res->rgb, ref, n3);
            fprintf(stderr, "%s at mu %.0f: spp_avg %.2f relMSE aaf %.3g\n", name, 2.0 * mu_default, run2.res->spp_avg,
                    err2);
            CHECK(err2 < err);
            run_free(&run2);
        }
    }
    free(ref);
}

/* Mixed pixels (motion blur and defocus over a filtered shadow): pixels whose samples hit the
 * moving sphere and the floor must stay out of the world-space filters; before the fix they
 * were compared against phantom guides (a dark and bright speckled ring). */
static void test_motion_mixed_pixels(void)
{
    int w = 0, h = 0;
    float *ref = render_mc(MOTION_SCENE, 99, 512, &w, &h);
    CHECK(ref != NULL);
    if (!ref) return;
    size_t n3 = 3 * (size_t)w * (size_t)h;
    Run run;
    CHECK(render_filtered(MOTION_SCENE, 1, 0.0f, 0, &run));
    if (run.res) {
        ReconResult res = *run.res;
        CHECK(all_finite(res.rgb, n3));
        float *mc = render_mc(MOTION_SCENE, 2, mc_spp_at_least(res.spp_avg), &w, &h);
        double err = rel_mse(res.rgb, ref, n3), err_mc = mc ? rel_mse(mc, ref, n3) : 0.0;
        fprintf(stderr, "motion: spp_avg %.2f relMSE aaf %.3g, mc %.3g (ratio %.2f)\n", res.spp_avg, err, err_mc,
                err_mc / err);
        /* Measured when this was written: with the mixed-pixel test disabled the ring makes
         * AAF's relMSE 4.8x Monte Carlo's at equal spp; with it, 1.2x (motion blur itself is
         * not filtered, and the defocus filter pays for its samples). The bar sits between. */
        CHECK(err <= 2.0 * err_mc);
        free(mc);
        run_free(&run);
    }
    free(ref);
}

static void test_all_effects_finite(void)
{
    Run run;
    CHECK(render_filtered(ALL_EFFECTS_SCENE, 3, 0.0f, 0, &run));
    if (!run.res) return;
    ReconResult res = *run.res;
    size_t n = (size_t)res.width * (size_t)res.height;
    CHECK(all_finite(res.rgb, 3 * n));
    const Effect filtered[3] = {EFFECT_SOFT_SHADOWS, EFFECT_DEFOCUS, EFFECT_INDIRECT};
    for (int k = 0; k < 3; ++k) {
        Effect e = filtered[k];
        char name[64];
        snprintf(name, sizeof name, "aaf.beta_px.%s", effect_name(e));
        const float *beta_px = aov(&res, name);
        CHECK(effect_in(renderer_effects(run.r), e));
        CHECK_STR(recon_choice_name(&res.choice, e), "aaf");
        CHECK(beta_px != NULL);
        if (beta_px) {
            CHECK(all_finite(beta_px, n));
            for (size_t i = 0; i < n; ++i) CHECK(beta_px[i] >= 0.0f);
        }
    }
    CHECK(res.pass1_spp == 16);
    CHECK(res.spp_avg >= 16.0);
    CHECK(res.seconds_filter >= 0.0 && res.seconds_kernels >= 0.0);
    CHECK(res.device[0] != '\0');
    run_free(&run);
}

/* A defocused sphere alone in the frame (the corners see nothing): with no light at infinity
 * the rays that escape see black, so pixels whose pass-1 rays all escaped keep their pass-1
 * samples and stay black; add an environment light and the same pixels see a (uniformly
 * lit) background at infinity and are sampled by the defocus rule like any other. */
static const char *LONE_SPHERE_SCENE =
    "LookAt 0 0 -3   0 0 0   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ] \"float lensradius\" [ 0.2 ] \"float focaldistance\" [ 2 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 24 ] \"string filename\" [ \"t.exr\" ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "LightSource \"point\" \"rgb I\" [ 10 10 10 ] \"point3 from\" [ 0 2 -2 ]\n"
    "%s"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"sphere\" \"float radius\" [ 0.5 ]\n";

static void test_black_background_not_resampled(void)
{
    char text[2048];
    int corner[4][2] = {{0, 0}, {23, 0}, {0, 23}, {23, 23}};
    for (int lit = 0; lit < 2; ++lit) {
        snprintf(text, sizeof text, LONE_SPHERE_SCENE, lit ? "LightSource \"infinite\" \"rgb L\" [ 0.3 0.3 0.3 ]\n" : "");
        Run run;
        if (!render_filtered(text, 3, 0.0f, 0, &run)) {
            CHECK(false);
            continue;
        }
        ReconResult res = *run.res;
        res.rgb = run.res->rgb;
        const float *spp = run.spp;
        CHECK(aov(&res, "aaf.beta_px.defocus") != NULL);
        int more = 0;
        for (int k = 0; k < 4; ++k) {
            size_t i = (size_t)corner[k][1] * 24 + (size_t)corner[k][0];
            if (!lit) {
                CHECK(spp[i] == (float)res.pass1_spp);
                CHECK(res.rgb[3 * i] == 0.0f && res.rgb[3 * i + 1] == 0.0f && res.rgb[3 * i + 2] == 0.0f);
            }
            more += spp[i] > (float)res.pass1_spp;
        }
        if (lit) CHECK(more == 4);
        /* the sphere's pixels are sampled past pass 1 either way */
        CHECK(spp[12 * 24 + 12] > (float)res.pass1_spp);
        run_free(&run);
    }
}

int main(void)
{
    test_shadows_beat_monte_carlo_and_converge();
    test_beats_monte_carlo("indirect", INDIRECT_SCENE, EFFECT_INDIRECT, aaf_indirect_config_default().mu);
    test_beats_monte_carlo("defocus", DEFOCUS_SCENE, EFFECT_DEFOCUS, aaf_defocus_config_default().mu);
    test_motion_mixed_pixels();
    test_all_effects_finite();
    test_black_background_not_resampled();
    CHECK_DONE();
}
