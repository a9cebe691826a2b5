/* Point, spot and distant lights are lit at every path vertex, not picked (light.h,
 * LIGHTS_DELTA_EVERY_MAX). Checked on a diffuse plane (reflectance rho) seen through a
 * nearly parallel pinhole camera, where a distant light of radiance L arriving at angle
 * theta gives the radiance rho L cos(theta) / pi everywhere:
 *  - with up to LIGHTS_DELTA_EVERY_MAX distant lights every sample has the closed-form sum
 *    of their radiances, so 1 spp is exact in every pixel (a one-light pick gives each
 *    sample one light's share divided by its probability: far off, sample by sample);
 *  - with one more they join the pick: single samples scatter, and the mean over many
 *    samples is still the closed form;
 *  - beside an area light (a sphere: E = pi L_s (r/d)^2 straight below) the pick holds only
 *    the area light, whose MIS weights must use that pick's probability: the sum of both
 *    closed forms. */
#include "check.h"
#include "render/light.h"
#include "render_test_util.h"

#define PI 3.14159265358979323846

static const char *HEADER =
    "LookAt 0 0.8 -3  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 0.02 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ]\n"
    "Sampler \"stratified\" \"integer xsamples\" [ %d ] \"integer ysamples\" [ %d ] \"bool jitter\" [ true ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    "  Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n";
static const double RHO = 0.5;

/* n distant lights of radiance L_k = 0.3 + 0.1 k from directions spread over the upper
 * hemisphere (all above the plane); appends them to text and returns the plane's radiance. */
static double add_distant_lights(char *text, size_t cap, int n)
{
    double want = 0.0;
    for (int k = 0; k < n; ++k) {
        double L = 0.3 + 0.1 * k, phi = 2.0 * PI * k / n, dx = cos(phi), dz = sin(phi), dy = 0.2 + 0.4 * k;
        size_t used = strlen(text);
        snprintf(text + used, cap - used,
                 "LightSource \"distant\" \"rgb L\" [ %g %g %g ] \"point3 from\" [ %.17g %.17g %.17g ] \"point3 to\" [ 0 0 0 ]\n", L,
                 L, L, dx, dy, dz);
        want += RHO * L * dy / sqrt(dx * dx + dy * dy + dz * dz) / PI;
    }
    return want;
}

/* Renders at n x n spp; returns the largest relative deviation of a pixel from want and
 * stores the image mean. */
static double render_deviation(const char *lights_text, int n, double want, double *mean, int *delta_every)
{
    static char text[16384];
    int used = snprintf(text, sizeof text, HEADER, n, n);
    snprintf(text + used, sizeof text - (size_t)used, "%s", lights_text);
    TestRender t;
    RenderOptions o = {0};
    o.threads = 2;
    o.seed = 5;
    if (!test_render(text, &o, &t)) return INFINITY;
    *delta_every = renderer_integrator_scene(t.r)->lights->delta_every_count;
    double worst = 0.0, sum = 0.0;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            double rgb[3];
            test_pixel(&t, x, y, rgb);
            sum += rgb[0];
            double dev = fabs(rgb[0] / want - 1.0);
            if (!(dev <= worst)) worst = dev; /* NaN counts as the worst */
        }
    CHECK(test_frame_finite(&t.frame));
    test_render_free(&t);
    *mean = sum / 16.0;
    return worst;
}

int main(void)
{
    char lights[8192];
    double mean;
    int every;

    /* the largest set lit at every vertex: one sample per pixel is the closed form */
    lights[0] = '\0';
    double want = add_distant_lights(lights, sizeof lights, LIGHTS_DELTA_EVERY_MAX);
    double dev = render_deviation(lights, 1, want, &mean, &every);
    fprintf(stderr, "%d distant lights, 1 spp: worst pixel %.2e off (delta_every %d)\n", LIGHTS_DELTA_EVERY_MAX, dev, every);
    CHECK(every == LIGHTS_DELTA_EVERY_MAX);
    CHECK(dev < 1e-5);

    /* one more: picked. Single samples are far off; the mean of 32x32 per pixel is not */
    lights[0] = '\0';
    want = add_distant_lights(lights, sizeof lights, LIGHTS_DELTA_EVERY_MAX + 1);
    dev = render_deviation(lights, 1, want, &mean, &every);
    fprintf(stderr, "%d distant lights, 1 spp: worst pixel %.2e off (delta_every %d)\n", LIGHTS_DELTA_EVERY_MAX + 1, dev,
            every);
    CHECK(every == 0);
    CHECK(dev > 0.1); /* measured 0.39: the cosines range from 0.2 to 0.96 */
    render_deviation(lights, 32, want, &mean, &every);
    fprintf(stderr, "%d distant lights, 1024 spp: mean %.6f want %.6f\n", LIGHTS_DELTA_EVERY_MAX + 1, mean, want);
    CHECK_NEAR(mean / want, 1.0, 0.01);

    /* lights on both sides of the plane, one sample per pixel: those below it send nothing
     * and get no shadow ray (the wave decides this without a branch for a Lambert receiver
     * of a distant or point light: integrator.c, wave_vertex_rays), those above give the
     * closed form, and a point light above its own closed form rho I cos / (pi d^2) */
    {
        lights[0] = '\0';
        want = add_distant_lights(lights, sizeof lights, 2);
        size_t used = strlen(lights);
        double I = 2.0, h = 3.0; /* a point light of intensity I straight above the origin */
        snprintf(lights + used, sizeof lights - used,
                 "LightSource \"distant\" \"rgb L\" [ 5 5 5 ] \"point3 from\" [ 0.3 -1 0.2 ] \"point3 to\" [ 0 0 0 ]\n"
                 "LightSource \"point\" \"rgb I\" [ 7 7 7 ] \"point3 from\" [ 0 -0.5 0 ]\n"
                 "LightSource \"point\" \"rgb I\" [ %g %g %g ] \"point3 from\" [ 0 %g 0 ]\n"
                 "LightSource \"distant\" \"rgb L\" [ 0 0 0 ] \"point3 from\" [ 0 1 0 ] \"point3 to\" [ 0 0 0 ]\n",
                 I, I, I, h);
        want += RHO * I / (h * h) / PI; /* the pixels see points within 1e-3 of the origin */
        static char text[16384];
        int n = snprintf(text, sizeof text, HEADER, 1, 1);
        snprintf(text + n, sizeof text - (size_t)n, "%s", lights);
        TestRender t;
        RenderOptions o = {0};
        o.threads = 2, o.seed = 5;
        CHECK(test_render(text, &o, &t));
        double worst = 0.0;
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                double rgb[3];
                test_pixel(&t, x, y, rgb);
                double d = fabs(rgb[0] / want - 1.0);
                if (!(d <= worst)) worst = d;
            }
        fprintf(stderr, "lights on both sides, 1 spp: worst pixel %.2e off; %lld shadow rays for %lld camera rays\n", worst,
                t.stats.rays_shadow, t.stats.rays_primary);
        CHECK(worst < 1e-5);
        /* the two distant lights and the point light above; none for those below or the dark one */
        CHECK(t.stats.rays_primary == 16 && t.stats.rays_shadow == 3 * 16);
        CHECK(t.stats.guarded_events == 0);
        test_render_free(&t);
    }

    /* a sphere light straight above (radius r at height d) beside two distant lights */
    {
        double Ls = 4.0, r = 0.3, d = 1.5;
        lights[0] = '\0';
        double want_delta = add_distant_lights(lights, sizeof lights, 2);
        size_t used = strlen(lights);
        snprintf(lights + used, sizeof lights - used,
                 "AttributeBegin\n Translate 0 %g 0\n AreaLightSource \"diffuse\" \"rgb L\" [ %g %g %g ]\n"
                 " Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
                 " Shape \"sphere\" \"float radius\" [ %g ]\nAttributeEnd\n",
                 d, Ls, Ls, Ls, r);
        want = want_delta + RHO * PI * Ls * (r / d) * (r / d) / PI;
        render_deviation(lights, 64, want, &mean, &every);
        fprintf(stderr, "sphere + 2 distant, 4096 spp: mean %.6f want %.6f (rel %.4f)\n", mean, want, mean / want - 1.0);
        CHECK(every == 2);
        CHECK_NEAR(mean / want, 1.0, 0.01);
    }
    CHECK_DONE();
}
