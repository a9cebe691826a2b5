/* The shadow filters under an area light that moves during the shutter (docs/algorithms.md 1.9
 * and 9.29; src/recon/aaf/aaf_light_sweep.h, src/recon/maaf/maaf_light_sweep.h). A 0.8 x 0.8
 * square light 3 units over a floor slides 2.4 units along x over the shutter. Checked:
 *  - the quadrature's nodes and weights integrate u^d exactly for d <= 15;
 *  - renderer_light_info_at gives the light's pose at a shutter time, and shutter open by default;
 *  - r(x) from aaf_light_sweep's emitters equals the time mean of the closed-form projected solid
 *    angle of the square (a point under a parallel rectangle) over the shutter, at floor points
 *    under, beside and far from the light's path; the pose at shutter open does not;
 *  - MAAF's swept light: its centre and extent, and its mean y-factors equal the mean of the
 *    factor over samples drawn as the renderer draws them (a uniform time, then a uniform point
 *    on the light's pose at that time), which the uniform density over the extent does not;
 *    a static light is left as it was;
 *  - through the pipeline, on the floor without occluder, AAF, MAAF and FSF at 8 spp are within
 *    1.5x of Monte Carlo's error at 8 spp (stratified samples of this smooth light leave little
 *    noise to filter: 1.1x, 1.1x and 0.45x here). With r(x) from the pose at shutter open they
 *    were 16x, 3x and 23x: the demodulated visibility is flat only with the time-mean r. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "recon/aaf/aaf_light_sweep.h"
#include "recon/maaf/maaf_light_sweep.h"
#include "recon/polygon_irradiance.h"
#include "moving_light_scene.h"
#include "recon_test_util.h"

/* the light from x = -1.2 to 1.2; a box creeping far away gives the scene its motion either way */
static const char *const MOVING = MOVING_LIGHT_HEAD
    "  ActiveTransform StartTime\n  Translate -1.2 0 0\n  ActiveTransform EndTime\n  Translate 1.2 0 0\n"
    "  ActiveTransform All\n" MOVING_LIGHT_AND_FLOOR;
static const char *const STILL = MOVING_LIGHT_HEAD MOVING_LIGHT_AND_FLOOR
    "AttributeBegin\n  ActiveTransform StartTime\n  Translate 5 0 5\n  ActiveTransform EndTime\n  Translate 5.1 0 5\n"
    "  ActiveTransform All\n  Shape \"sphere\" \"float radius\" [ 0.1 ]\nAttributeEnd\n";

enum { HALF_MOTION_TENTHS = 12 }; /* the light's centre goes from -1.2 to 1.2 */
static const double LIGHT_HALF = 0.4, LIGHT_HEIGHT = 3.0;

/* Projected solid angle of the rectangle [0, a] x [0, b] parallel to the receiver at height h
 * over one corner (pi times the form factor of a differential area to a parallel rectangle). */
static double corner_phi(double a, double b, double h)
{
    double ra = sqrt(a * a + h * h), rb = sqrt(b * b + h * h);
    return 0.5 * (a / ra * atan(b / ra) + b / rb * atan(a / rb));
}

/* The square light centred at (cx, h, 0) seen from the floor point (x, 0, z) facing up. */
static double square_phi(double cx, double x, double z)
{
    double x0 = cx - LIGHT_HALF - x, x1 = cx + LIGHT_HALF - x, z0 = -LIGHT_HALF - z, z1 = LIGHT_HALF - z;
    return corner_phi(x1, z1, LIGHT_HEIGHT) - corner_phi(x0, z1, LIGHT_HEIGHT) - corner_phi(x1, z0, LIGHT_HEIGHT) +
           corner_phi(x0, z0, LIGHT_HEIGHT);
}

static double center_at(double u) { return 0.1 * HALF_MOTION_TENTHS * (2.0 * u - 1.0); }

/* r(x) up to the light's radiance: the emitters' sum of radiance times projected solid angle */
static double emitters_phi(const AafLightGeom *em, int count, double x, double z)
{
    double p[3] = {x, 0.0, z}, n[3] = {0.0, 1.0, 0.0}, sum = 0.0;
    for (int e = 0; e < count; ++e) {
        double v[3][3];
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) v[i][k] = em[e].tri[i][k];
        sum += em[e].radiance_mean * polygon_projected_solid_angle(p, n, v, 3);
    }
    return sum / 5.0;
}

static void check_quadrature(void)
{
    double prev = 0.0;
    for (int d = 0; d <= 15; ++d) {
        double s = 0.0;
        for (int k = 0; k < AAF_SWEEP_NODES; ++k) {
            double w, u = aaf_sweep_node(k, &w);
            if (d == 0) {
                CHECK(u > prev && u < 1.0);
                prev = u;
            }
            s += w * pow(u, d);
        }
        CHECK_NEAR(s, 1.0 / (d + 1), 1e-13);
    }
}

static void check_poses_and_r(void)
{
    SceneDesc scene;
    Renderer *r = NULL;
    if (!recon_test_renderer(MOVING, 1, 4, false, &scene, &r)) {
        CHECK(false);
        return;
    }
    int count = renderer_light_count(r);
    CHECK(count == 2);
    RenderLightInfo open, at0, mid, end;
    CHECK(renderer_light_info(r, 0, &open) && renderer_light_info_at(r, 0, 0.0f, &at0));
    CHECK(renderer_light_info_at(r, 0, 0.5f, &mid) && renderer_light_info_at(r, 0, 1.0f, &end));
    CHECK(open.moving && mid.moving);
    CHECK(memcmp(&open, &at0, sizeof open) == 0);
    CHECK_NEAR(mid.center_world.x - open.center_world.x, 1.2, 1e-5);
    CHECK_NEAR(end.center_world.x - open.center_world.x, 2.4, 1e-5);
    CHECK_NEAR(end.center_world.y, open.center_world.y, 1e-6);

    AafLightGeom lights[2], *em = NULL;
    aaf_lights_from_renderer(r, lights, count);
    int n = aaf_light_sweep(r, lights, count, &em);
    CHECK(n == 2 * AAF_SWEEP_NODES && em);
    static const double pts[][2] = {{0.0, 0.0}, {-1.5, 0.3}, {0.7, -1.2}, {2.5, 0.0}, {-3.5, 1.0}, {1.6, 2.5}};
    double worst = 0.0, open_worst = 0.0;
    for (size_t i = 0; i < sizeof pts / sizeof pts[0] && em; ++i) {
        enum { STEPS = 20000 }; /* the time mean by the midpoint rule, far finer than the quadrature */
        double mean = 0.0;
        for (int s = 0; s < STEPS; ++s) mean += square_phi(center_at((s + 0.5) / STEPS), pts[i][0], pts[i][1]) / STEPS;
        double got = emitters_phi(em, n, pts[i][0], pts[i][1]);
        double at_open = emitters_phi(lights, count, pts[i][0], pts[i][1]);
        CHECK_NEAR(at_open, square_phi(center_at(0.0), pts[i][0], pts[i][1]), 1e-6 * mean); /* the closed form */
        worst = fmax(worst, fabs(got / mean - 1.0));
        open_worst = fmax(open_worst, fabs(at_open / mean - 1.0));
    }
    printf("r(x) from the sweep: worst relative error %.2e (the pose at shutter open: %.2f)\n", worst, open_worst);
    CHECK(worst < 2e-4);
    CHECK(open_worst > 0.5);
    free(em);

    /* MAAF's swept light along the quad's edges */
    MaafLight ml;
    MaafSweep poses;
    memset(&ml, 0, sizeof ml);
    ml.t1[0] = 1.0f;
    ml.t2[2] = -1.0f;
    CHECK(maaf_light_sweep(r, 0, 0.0f, &poses, &ml));
    CHECK_NEAR(ml.center[0], 0.0, 1e-5);
    CHECK_NEAR(ml.center[1], 3.0, 1e-5);
    CHECK_NEAR(ml.lo[0], -1.6, 1e-5);
    CHECK_NEAR(ml.hi[0], 1.6, 1e-5);
    CHECK_NEAR(ml.lo[1], -0.4, 1e-5);
    CHECK_NEAR(ml.hi[1], 0.4, 1e-5);
    CHECK(ml.sweep_nodes == MAAF_SWEEP_NODES);
    maaf_light_design(0.4f, 2, &ml);
    /* the factor's mean over samples drawn as the renderer draws them (stratified in time and
     * on the light) against the design's mean; and against the uniform density over the extent */
    enum { T = 512, Y = 64 };
    double want[2][2][2] = {{{0}}}, flat[2][2][2] = {{{0}}};
    for (int a = 0; a < 2; ++a)
        for (int p = 0; p < 2; ++p) {
            for (int t = 0; t < T; ++t)
                for (int j = 0; j < Y; ++j) {
                    double y = (2.0 * (j + 0.5) / Y - 1.0) * LIGHT_HALF + (a == 0 ? center_at((t + 0.5) / T) : 0.0);
                    float c[2];
                    maaf_light_factor(&ml, a, p, (float)y, c);
                    for (int k = 0; k < 2; ++k) want[a][p][k] += c[k] / ((double)T * Y);
                }
            for (int j = 0; j < T; ++j) {
                float c[2];
                maaf_light_factor(&ml, a, p, (float)(ml.lo[a] + (ml.hi[a] - ml.lo[a]) * (j + 0.5) / T), c);
                for (int k = 0; k < 2; ++k) flat[a][p][k] += c[k] / T;
            }
            for (int k = 0; k < 2; ++k) CHECK_NEAR(ml.mean[a][p][k], want[a][p][k], 2e-3 * fabs(want[a][p][0]) + 1e-5);
        }
    printf("MAAF mean c_0 along the motion: %.5f, of the samples %.5f, uniform over the extent %.5f\n", ml.mean[0][0][0],
           want[0][0][0], flat[0][0][0]);
    CHECK(fabs(flat[0][0][0] - want[0][0][0]) > 0.02 * want[0][0][0]); /* the density matters */
    renderer_destroy(r);
    scene_desc_free(&scene);

    /* a static light: no sweep, nothing changed */
    CHECK(recon_test_renderer(STILL, 1, 4, false, &scene, &r));
    CHECK(renderer_light_info(r, 0, &open) && !open.moving);
    aaf_lights_from_renderer(r, lights, 2);
    CHECK(aaf_light_sweep(r, lights, 2, &em) == 0 && em == NULL);
    MaafLight before = ml;
    CHECK(!maaf_light_sweep(r, 0, 0.0f, &poses, &ml));
    CHECK(memcmp(&before, &ml, sizeof ml) == 0);
    renderer_destroy(r);
    scene_desc_free(&scene);
}

/* relMSE at 8 spp of Monte Carlo, AAF and MAAF against a 512-spp Monte Carlo reference, on the
 * unoccluded floor under the moving light, mean over two seeds */
static void check_pipeline(void)
{
    float *ref = recon_test_render_spp(MOVING, "none", 7, 512, NULL, NULL);
    CHECK(ref != NULL);
    if (!ref) return;
    size_t n3 = 3 * 24 * 24;
    static const char *const filters[] = {"none", "soft_shadows=aaf,motion=none", "soft_shadows=maaf,motion=none",
                                          "soft_shadows=fsf,motion=none"};
    double err[4] = {0, 0, 0, 0};
    for (int f = 0; f < 4; ++f)
        for (unsigned seed = 1; seed <= 2; ++seed) {
            float *img = recon_test_render_spp(MOVING, filters[f], seed, 8, NULL, NULL);
            CHECK(img != NULL);
            if (img) err[f] += 0.5 * rel_mse(img, ref, n3);
            free(img);
        }
    printf("relMSE at 8 spp: Monte Carlo %.3e, aaf %.3e, maaf %.3e, fsf %.3e\n", err[0], err[1], err[2], err[3]);
    CHECK(err[1] < 1.5 * err[0]);
    CHECK(err[2] < 1.5 * err[0]);
    CHECK(err[3] < 1.5 * err[0]);
    free(ref);
}

int main(void)
{
    check_quadrature();
    check_poses_and_r();
    check_pipeline();
    return check_failures ? 1 : 0;
}
