/* Per-pixel AAF statistics (aaf_stats.c) from synthetic SampleRecords: shadow-ray distances,
 * reflector distances along the normal, CoC slopes of the thin lens, the light's Gaussian
 * width and plane, and the derived maps. Expected values are derived by hand below. */
#include <stdlib.h>

#include "check.h"
#include "recon/aaf/aaf_stats.h"

/* The statistics with the pipeline's shared guides, fed as the pipeline feeds them: every
 * sample to the GBuffer and the AAF sink, and the frame's sample count as the renderer adds it. */
typedef struct {
    GBuffer g;
    AafStats s;
} Fixture;

static bool fixture_init(Fixture *fx, int w, int h, ReconCamera cam)
{
    return gbuffer_init(&fx->g, w, h, cam) && aaf_stats_init(&fx->s, &fx->g);
}

static void fixture_add(Fixture *fx, int px, int py, const SampleRecord *r)
{
    gbuffer_add(&fx->g, px, py, r);
    aaf_stats_add(&fx->s, px, py, r);
    if (px >= 0 && py >= 0 && px < fx->g.width && py < fx->g.height) fx->g.frame.spp[py * fx->g.width + px] += 1.0f;
}

static bool fixture_derive(Fixture *fx, AafDerived *d)
{
    gbuffer_resolve_guides(&fx->g);
    return aaf_derive(&fx->s, d);
}

static void fixture_free(Fixture *fx)
{
    aaf_stats_free(&fx->s);
    gbuffer_free(&fx->g);
}

static SampleRecord surface_sample(void)
{
    SampleRecord r = {0};
    r.hit = true;
    r.p_world = v3(1.0f, 0.0f, 2.0f);
    r.n_shading = v3(0.0f, 1.0f, 0.0f);
    r.depth_cam = 4.0f;
    r.object_id = 7;
    r.albedo = v3(0.5f, 0.5f, 0.5f);
    return r;
}

static void test_coc_slope(void)
{
    /* R = 0.1, F = 5, one pixel spans 0.001 at depth 1: slope = (R/a)(1/F - 1/z) = 100 (0.2 - 1/z).
     * z = 10 -> 10 px; z = 2.5 (in front) -> -20 px; z = F -> 0; z = inf -> 20 px. */
    ReconCamera cam = {0.1f, 5.0f, 0.001f};
    CHECK_NEAR(recon_coc_slope_px(&cam, 10.0f), 10.0, 1e-4);
    CHECK_NEAR(recon_coc_slope_px(&cam, 2.5f), -20.0, 1e-4);
    CHECK_NEAR(recon_coc_slope_px(&cam, 5.0f), 0.0, 1e-5);
    CHECK_NEAR(recon_coc_slope_px(&cam, INFINITY), 20.0, 1e-4);
    CHECK(isfinite(recon_coc_slope_px(&cam, 0.0f)));
    ReconCamera pinhole = {0.0f, 5.0f, 0.001f};
    CHECK_NEAR(recon_coc_slope_px(&pinhole, 2.0f), 0.0, 0.0);
}

static void test_pixel_statistics(void)
{
    ReconCamera cam = {0.1f, 5.0f, 0.001f};
    Fixture fx;
    CHECK(fixture_init(&fx, 3, 2, cam));
    SampleRecord r = surface_sample();
    r.shadow_count = 1;
    r.bounce_count = 1;
    /* shadow ray 1: light 4 away, occluder 1 from the receiver -> d2 = 3, d2/d1 = 0.75 */
    r.shadow[0].d_light_world = 4.0f;
    r.shadow[0].d_occluder_world = 1.0f;
    r.shadow[0].light_p_world = v3(0, 5, 0);
    /* bounce 1: reflector 2 away at 60 degrees from the normal -> z = 2 cos 60 = 1 */
    r.bounce[0].d_hit_world = 2.0f;
    r.bounce[0].dir_world = v3(sinf((float)M_PI / 3), cosf((float)M_PI / 3), 0.0f);
    fixture_add(&fx, 1, 1, &r);
    /* shadow ray 2: light 6 away, occluder 4 from the receiver -> d2 = 2, ratio 1/3;
     * bounce 2 straight up, 3 away -> z = 3; a third, unoccluded ray and escaped bounce */
    r.shadow[0].d_light_world = 6.0f;
    r.shadow[0].d_occluder_world = 4.0f;
    r.bounce[0].d_hit_world = 3.0f;
    r.bounce[0].dir_world = v3(0, 1, 0);
    r.depth_cam = 6.0f;
    fixture_add(&fx, 1, 1, &r);
    r.shadow[0].d_light_world = 5.0f;
    r.shadow[0].d_occluder_world = INFINITY;
    r.bounce[0].d_hit_world = INFINITY;
    fixture_add(&fx, 1, 1, &r);
    /* a miss in pixel (0, 0): only the CoC of the background (z = inf -> 20 px) */
    SampleRecord miss = {0};
    miss.depth_cam = INFINITY;
    miss.object_id = -1;
    fixture_add(&fx, 0, 0, &miss);
    /* out-of-range pixels are ignored */
    fixture_add(&fx, 5, 5, &r);

    size_t i = 1 * 3 + 1;
    CHECK(fx.g.frame.spp[i] == 3.0f && fx.g.sums[i].hits == 3 && fx.s.shadow_rays[i] == 3 && fx.s.occluded_rays[i] == 2);
    CHECK_NEAR(fx.s.ratio_min[i], 1.0 / 3.0, 1e-6);
    CHECK_NEAR(fx.s.ratio_max[i], 0.75, 1e-6);
    CHECK_NEAR(fx.s.zmin[i], 1.0, 1e-6);
    CHECK_NEAR(fx.s.zmax[i], 3.0, 1e-6);
    /* depths 4, 6, 6: slopes 100 (0.2 - 0.25) = -5 and 100 (0.2 - 1/6) = 3.333 */
    CHECK_NEAR(fx.s.coc_min[i], -5.0, 1e-4);
    CHECK_NEAR(fx.s.coc_max[i], 10.0 / 3.0, 1e-4);
    CHECK_NEAR(fx.s.coc_min[0], 20.0, 1e-4);

    AafDerived d;
    CHECK(fixture_derive(&fx, &d));
    /* d1 = mean(4, 6, 5) = 5; d2min = (1/3) 5, d2max = 0.75 * 5 */
    CHECK_NEAR(d.d1[i], 5.0, 1e-6);
    CHECK_NEAR(d.d2min[i], 5.0 / 3.0, 1e-5);
    CHECK_NEAR(d.d2max[i], 3.75, 1e-5);
    /* guides: mean position, unit normal + object id, mean depth (4+6+6)/3; pixel size z * a */
    CHECK_NEAR(fx.g.pos4[4 * i + 0], 1.0, 1e-6);
    CHECK_NEAR(fx.g.pos4[4 * i + 3], 16.0 / 3.0, 1e-5);
    CHECK_NEAR(fx.g.nrm4[4 * i + 1], 1.0, 1e-6);
    CHECK_NEAR(fx.g.nrm4[4 * i + 3], 7.0, 0.0);
    CHECK_NEAR(fx.g.pixel_world[i], 16.0 / 3.0 * 0.001, 1e-8);
    CHECK(fx.g.hit[i] == 1 && fx.g.hit[0] == 0);
    CHECK_NEAR(fx.g.nrm4[3], -1.0, 0.0); /* no surface */
    aaf_derived_free(&d);
    fixture_free(&fx);
}

static void test_light_estimate(void)
{
    /* A square light of side 2 in the plane y = 5, sampled on a 100 x 100 grid of cell
     * centres: per-axis variance (a^2/12)(1 - 1/100^2). The uniform rectangle with these
     * variances has area a^2 = 4, so sigma = sqrt(4)/2 = 1 (to 1e-4) and the normal is +-y. */
    ReconCamera cam = {0.0f, 1.0f, 0.001f};
    Fixture fx;
    CHECK(fixture_init(&fx, 4, 4, cam));
    SampleRecord r = surface_sample();
    r.shadow_count = 1;
    r.shadow[0].d_light_world = 5.0f;
    r.shadow[0].d_occluder_world = INFINITY;
    for (int a = 0; a < 100; ++a)
        for (int b = 0; b < 100; ++b) {
            r.shadow[0].light_p_world = v3(-1.0f + (a + 0.5f) * 0.02f, 5.0f, 3.0f - 1.0f + (b + 0.5f) * 0.02f);
            fixture_add(&fx, (a * 100 + b) % 4, (a / 25) % 4, &r);
        }
    AafDerived d;
    CHECK(fixture_derive(&fx, &d));
    CHECK_NEAR(d.light_sigma_world, 1.0, 2e-3);
    CHECK_NEAR(fabsf(d.light_normal[1]), 1.0, 1e-4);
    CHECK_NEAR(d.light_normal[0], 0.0, 1e-3);
    CHECK_NEAR(d.sigma_light[5], d.light_sigma_world, 0.0);
    /* The rectangle for r(x): centre (0, 5, 3), half sides of length 1 (variance a^2/3 with
     * a = 1, up to the grid's 1 - 1/100^2). */
    CHECK_NEAR(d.light_center[1], 5.0, 1e-4);
    CHECK_NEAR(d.light_center[2], 3.0, 1e-4);
    CHECK(d.light_known);
    CHECK_NEAR(sqrtf(d.light_half_u[0] * d.light_half_u[0] + d.light_half_u[1] * d.light_half_u[1] +
                     d.light_half_u[2] * d.light_half_u[2]), 1.0, 1e-3);
    /* r(x) for the receiver of surface_sample: p = (1, 0, 2), normal +y, 5 below the light
     * plane, exactly under the corner (1, 5, 2) of the 2 x 2 square. r is the mean over the
     * square of cos cos / d^2, i.e. its projected solid angle over its area 4, and the
     * projected solid angle of a parallel rectangle seen from under a corner is pi times the
     * classic form factor (X = Y = 2/5). Computed here independently of the code under test;
     * 2e-3 covers the light rectangle estimated from a grid of samples. */
    {
        double X = 0.4, sx = sqrt(1 + X * X);
        double want = 0.5 * (2.0 * X / sx * atan(X / sx)) / 4.0;
        float *r = calloc(16, sizeof(float));
        fx.g.hit[15] = 0;
        aaf_unoccluded_irradiance(&d, r);
        CHECK_NEAR(r[5], want, 2e-3 * want);
        CHECK_NEAR(r[15], 0.0, 0.0); /* no surface in pixel (3, 3): 0 */
        /* a receiver facing away from the light sees nothing */
        fx.g.nrm4[4 * 5 + 1] = -1.0f;
        aaf_unoccluded_irradiance(&d, r);
        CHECK_NEAR(r[5], 0.0, 0.0);
        free(r);
    }
    aaf_derived_free(&d);
    fixture_free(&fx);
}

/* Exact lights: a shadow ray's own light sets the pixel's sigma (the smallest over its rays)
 * and the plane of eq. 12 (a rectangle's normal; for a sphere the receiver -> centre
 * direction). */
static void test_exact_lights(void)
{
    ReconCamera cam = {0.0f, 1.0f, 0.001f};
    AafLightGeom lights[2] = {{0}};
    lights[0].sigma_world = 0.5f; /* a square of side 1 facing down */
    lights[0].normal[1] = -1.0f;
    lights[1].sigma_world = 0.25f; /* a sphere centred above-right of the receiver */
    lights[1].center[0] = 4.0f;
    lights[1].center[1] = 3.0f;
    lights[1].center[2] = 2.0f;
    Fixture fx;
    CHECK(fixture_init(&fx, 2, 1, cam));
    fx.s.lights = lights;
    fx.s.light_count = 2;
    SampleRecord r = surface_sample(); /* receiver at (1, 0, 2) */
    r.shadow_count = 1;
    r.shadow[0].d_light_world = 5.0f;
    r.shadow[0].d_occluder_world = INFINITY;
    r.shadow[0].light_index = 0;
    fixture_add(&fx, 0, 0, &r);
    fixture_add(&fx, 0, 0, &r);
    r.shadow[0].light_index = 1;
    fixture_add(&fx, 1, 0, &r);
    r.shadow[0].light_index = 7; /* out of range: ignored */
    fixture_add(&fx, 1, 0, &r);
    AafDerived d;
    CHECK(fixture_derive(&fx, &d));
    CHECK(d.exact_lights);
    CHECK_NEAR(d.sigma_light[0], 0.5, 0.0);
    CHECK_NEAR(d.sigma_light[1], 0.25, 0.0);
    CHECK_NEAR(fabsf(d.plane4[1]), 1.0, 1e-6);
    /* receiver -> centre = (3, 3, 0) / (3 sqrt 2) */
    CHECK_NEAR(d.plane4[4 + 0], 1.0 / sqrt(2.0), 1e-6);
    CHECK_NEAR(d.plane4[4 + 1], 1.0 / sqrt(2.0), 1e-6);
    CHECK_NEAR(d.plane4[4 + 2], 0.0, 1e-6);
    aaf_derived_free(&d);
    fixture_free(&fx);
}

/* r(x) of the receiver of surface_sample (p = (1, 0, 2), normal +y) for one light list: the
 * value aaf_unoccluded_irradiance gives pixel 0. */
static double r_for_lights(AafLightGeom *lights, int count)
{
    ReconCamera cam = {0.0f, 1.0f, 0.001f};
    Fixture fx;
    CHECK(fixture_init(&fx, 1, 1, cam));
    fx.s.lights = lights;
    fx.s.light_count = count;
    SampleRecord r = surface_sample();
    fixture_add(&fx, 0, 0, &r);
    AafDerived d;
    CHECK(fixture_derive(&fx, &d));
    CHECK(d.lights == lights);
    float out = -1.0f;
    aaf_unoccluded_irradiance(&d, &out);
    aaf_derived_free(&d);
    fixture_free(&fx);
    return out;
}

static AafLightGeom triangle_light(float x0, float z0, float x1, float z1, float x2, float z2, float y)
{
    AafLightGeom L = {0};
    L.emitter = AAF_EMITTER_TRIANGLE;
    L.sigma_world = 0.5f;
    L.normal[1] = -1.0f; /* facing down */
    float v[3][3] = {{x0, y, z0}, {x1, y, z1}, {x2, y, z2}};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) L.tri[i][k] = v[i][k];
    L.center[0] = (x0 + x1 + x2) / 3.0f;
    L.center[1] = y;
    L.center[2] = (z0 + z1 + z2) / 3.0f;
    L.radiance_mean = 1.0f;
    return L;
}

/* With the renderer's emitters r(x) is exact: sum_l L_l Phi_l / sum_l L_l A_l, Phi the
 * projected solid angle. Closed forms: a 2 x 2 square (two triangles) seen from under its
 * corner (pi times the classic form factor), a disk on its axis (pi a^2 / (a^2 + h^2)), a
 * sphere straight above (pi (R/D)^2); one-sided emitters give nothing behind them. */
static void test_exact_irradiance(void)
{
    /* the square [-1, 1] x [2, 4] at y = 5, receiver under its corner (1, 2) */
    AafLightGeom sq[2] = {triangle_light(-1, 2, 1, 2, 1, 4, 5.0f), triangle_light(-1, 2, 1, 4, -1, 4, 5.0f)};
    /* pi F with F = (1/2pi) [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + (the same, X <-> Y)], X = Y = 2/5 */
    double X = 0.4, sx = sqrt(1 + X * X);
    double phi_square = 0.5 * (2.0 * X / sx * atan(X / sx));
    CHECK_NEAR(r_for_lights(sq, 2), phi_square / 4.0, 1e-5 * phi_square);
    /* twice the radiance on both halves: the same r (it is a ratio) */
    sq[0].radiance_mean = sq[1].radiance_mean = 2.0f;
    CHECK_NEAR(r_for_lights(sq, 2), phi_square / 4.0, 1e-5 * phi_square);
    /* the square below the receiver's horizon: nothing; above it but facing up (one-sided,
     * receiver behind it): nothing; two-sided: the same as facing the receiver */
    AafLightGeom below[2] = {triangle_light(-1, 2, 1, 2, 1, 4, -5.0f), triangle_light(-1, 2, 1, 4, -1, 4, -5.0f)};
    CHECK_NEAR(r_for_lights(below, 2), 0.0, 0.0);
    for (int i = 0; i < 2; ++i) sq[i].normal[1] = 1.0f;
    CHECK_NEAR(r_for_lights(sq, 2), 0.0, 0.0);
    for (int i = 0; i < 2; ++i) sq[i].two_sided = true;
    CHECK_NEAR(r_for_lights(sq, 2), phi_square / 4.0, 1e-5 * phi_square);

    /* a disk of radius 1, 2 above the receiver, facing down: Phi = pi/5, weight pi */
    AafLightGeom disk = {0};
    disk.emitter = AAF_EMITTER_DISK;
    disk.radius_world = 1.0f;
    disk.normal[1] = -1.0f;
    disk.center[0] = 1.0f, disk.center[1] = 2.0f, disk.center[2] = 2.0f;
    disk.radiance_mean = 3.0f;
    CHECK_NEAR(r_for_lights(&disk, 1), 1.0 / 5.0, 2e-3 / 5.0); /* a 16-gon of the disk's area */
    /* a sphere of radius 1 centred 4 above: Phi = pi/16, weight pi R^2 */
    AafLightGeom sphere = {0};
    sphere.emitter = AAF_EMITTER_SPHERE;
    sphere.radius_world = 1.0f;
    sphere.center[0] = 1.0f, sphere.center[1] = 4.0f, sphere.center[2] = 2.0f;
    sphere.radiance_mean = 1.0f;
    CHECK_NEAR(r_for_lights(&sphere, 1), 1.0 / 16.0, 1e-5 / 16.0); /* closed form above the horizon */
    /* off to the side, 60 degrees from the normal (still wholly above the horizon): Phi = pi
     * (R/D)^2 cos 60 */
    AafLightGeom oblique = sphere;
    oblique.center[0] = 1.0f + 4.0f * (float)sin(M_PI / 3.0), oblique.center[1] = 4.0f * (float)cos(M_PI / 3.0);
    CHECK_NEAR(r_for_lights(&oblique, 1), 0.5 / 16.0, 1e-5 / 16.0);
    /* cut by the horizon, its centre on it: more than nothing and less than the cap that just
     * touches the horizon from above (every direction of it higher); and the polygon of a cap
     * just cut agrees with the closed form of the cap just touching, to the 16-gon's accuracy */
    AafLightGeom cut = sphere;
    cut.center[0] = 5.0f, cut.center[1] = 0.0f;
    double r_cut = r_for_lights(&cut, 1);
    CHECK(r_cut > 0.0 && r_cut < 0.25 / 16.0);
    AafLightGeom edge = sphere; /* tangent to the horizon from above: cos t = sin a = 1/4 */
    double t_edge = acos(0.25);
    edge.center[0] = 1.0f + 4.0f * (float)sin(t_edge), edge.center[1] = 4.0f * (float)cos(t_edge);
    double r_above = r_for_lights(&edge, 1);
    edge.center[0] = 1.0f + 4.0f * (float)sin(t_edge + 1e-4), edge.center[1] = 4.0f * (float)cos(t_edge + 1e-4);
    double r_below = r_for_lights(&edge, 1); /* the polygon, just cut */
    CHECK_NEAR(r_above, 0.25 / 16.0, 1e-5 / 16.0);
    CHECK_NEAR(r_below / r_above, 1.0, 4e-3);
    /* both: the radiance-weighted mix, sum L Phi / sum L A */
    AafLightGeom both[2] = {disk, sphere};
    double want = (3.0 * M_PI / 5.0 + M_PI / 16.0) / (3.0 * M_PI + M_PI);
    CHECK_NEAR(r_for_lights(both, 2), want, 2e-3 * want);
}

/* Mixed pixels: samples on two objects (motion blur), hits and misses, normals far apart, a
 * large depth spread or an unfilterable surface mark the pixel; identical samples do not. */
static void test_mixed_pixels(void)
{
    ReconCamera cam = {0.0f, 1.0f, 0.001f};
    Fixture fx;
    CHECK(fixture_init(&fx, 6, 1, cam));
    SampleRecord r = surface_sample();
    for (int k = 0; k < 4; ++k) fixture_add(&fx, 0, 0, &r); /* pixel 0: clean */
    fixture_add(&fx, 1, 0, &r);                              /* pixel 1: two objects */
    r.object_id = 8;
    fixture_add(&fx, 1, 0, &r);
    r = surface_sample();
    fixture_add(&fx, 2, 0, &r); /* pixel 2: a hit and a miss */
    SampleRecord miss = {0};
    miss.depth_cam = INFINITY;
    miss.object_id = -1;
    fixture_add(&fx, 2, 0, &miss);
    fixture_add(&fx, 3, 0, &r); /* pixel 3: normals 90 degrees apart (|mean| = 0.71) */
    r.n_shading = v3(1.0f, 0.0f, 0.0f);
    fixture_add(&fx, 3, 0, &r);
    r = surface_sample();
    fixture_add(&fx, 4, 0, &r); /* pixel 4: depths 4 and 8 (std/mean = 1/3) */
    r.depth_cam = 8.0f;
    fixture_add(&fx, 4, 0, &r);
    r = surface_sample();
    r.unfilterable = true; /* pixel 5: glass */
    fixture_add(&fx, 5, 0, &r);
    AafDerived d;
    CHECK(fixture_derive(&fx, &d));
    CHECK(fx.g.mixed[0] == 0);
    for (int i = 1; i < 6; ++i) CHECK(fx.g.mixed[i] == 1);
    aaf_derived_free(&d);
    fixture_free(&fx);
}

/* The unfiltered light is split per channel: indirect first, the rest direct. */
static void test_unfiltered_split(void)
{
    ReconCamera cam = {0.0f, 1.0f, 0.001f};
    Fixture fx;
    CHECK(fixture_init(&fx, 1, 1, cam));
    SampleRecord r = surface_sample();
    r.direct = v3(1.0f, 1.0f, 1.0f);
    r.indirect = v3(0.5f, 0.0f, 2.0f);
    r.unfiltered = v3(1.0f, 0.5f, 1.0f);
    fixture_add(&fx, 0, 0, &r);
    CHECK_NEAR(fx.g.sums[0].unf_indirect_sum[0], 0.5, 0.0);
    CHECK_NEAR(fx.g.sums[0].unf_direct_sum[0], 0.5, 0.0);
    CHECK_NEAR(fx.g.sums[0].unf_indirect_sum[1], 0.0, 0.0);
    CHECK_NEAR(fx.g.sums[0].unf_direct_sum[1], 0.5, 0.0);
    CHECK_NEAR(fx.g.sums[0].unf_indirect_sum[2], 1.0, 0.0);
    CHECK_NEAR(fx.g.sums[0].unf_direct_sum[2], 0.0, 0.0);
    fixture_free(&fx);
}

int main(void)
{
    test_exact_lights();
    test_exact_irradiance();
    test_mixed_pixels();
    test_unfiltered_split();
    test_coc_slope();
    test_pixel_statistics();
    test_light_estimate();
    CHECK_DONE();
}
