/* A spot light's samples for many receivers at once (light_sample_point_batch, issue 22).
 *  - Closed form: for receivers inside the full cone, in the falloff band and outside it,
 *    the batch's radiance is I smoothstep(cos_t) / d^2 with pbrt-v4's SmoothStep between
 *    cos(coneangle) and cos(coneangle - conedeltaangle), computed here in double; outside
 *    the cone there is no sample. Teeth: the band is sampled densely, so a select that
 *    returned 1 or 0 in the band, or the band's value outside it, fails.
 *  - The batch equals light_sample receiver by receiver, bit for bit (ok, wi, dist, Li),
 *    on random receivers and on receivers placed exactly on the cone's two edges, in odd
 *    counts so that the vector loop's remainder runs too; also for a spot without a band
 *    (conedeltaangle 0) and for a point light. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/light.h"
#include "render/tracer.h"
#include "render_test_util.h"

enum { RECEIVERS = 4099 };

/* The test scene (a floor) lit by `light` alone. */
static bool build(const char *light, TestLights *b)
{
    char text[1024];
    snprintf(text, sizeof text,
             "LookAt 0 2 -5  0 0.3 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 45 ]\n"
             "WorldBegin\n%s\n"
             "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1  0 3 2 ]\n",
             light);
    return test_build_lights(text, b);
}

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* A receiver at angle theta (radians) from the light's axis, at distance r. */
static vec3 at_angle(const Light *l, double theta, double phi, double r)
{
    vec3 a = l->w_world, t, s;
    v3_basis(a, &t, &s);
    double st = sin(theta), ct = cos(theta);
    vec3 d = v3_add(v3_scale(a, (float)ct), v3_add(v3_scale(t, (float)(st * cos(phi))), v3_scale(s, (float)(st * sin(phi)))));
    return v3_add(l->p_world, v3_scale(d, (float)r));
}

/* Receivers: random points of a box around the light, points on the cone's two edges (the
 * cosines spot_falloff compares with), the light's own position, a row across the band. */
static int receivers(const Light *l, float p[3][RECEIVERS], double cone_deg, double delta_deg)
{
    Pcg32 rng;
    pcg32_seed(&rng, 7u, 11u);
    int n = 0;
    for (; n < RECEIVERS - 600; ++n) {
        vec3 q = v3_add(l->p_world, v3(4.0f * pcg32_float(&rng) - 2.0f, 4.0f * pcg32_float(&rng) - 3.0f, 4.0f * pcg32_float(&rng) - 2.0f));
        p[0][n] = q.x, p[1][n] = q.y, p[2][n] = q.z;
    }
    double edges[2] = {cone_deg, cone_deg - delta_deg};
    for (int e = 0; e < 2; ++e)
        for (int k = 0; k < 100; ++k, ++n) {
            vec3 q = at_angle(l, edges[e] * M_PI / 180.0 + (k % 5 - 2) * 1e-7, 0.37 * k, 0.5 + 0.03 * k);
            p[0][n] = q.x, p[1][n] = q.y, p[2][n] = q.z;
        }
    p[0][n] = l->p_world.x, p[1][n] = l->p_world.y, p[2][n] = l->p_world.z;
    ++n;
    for (; n < RECEIVERS; ++n) { /* across the band and beyond, from the axis out */
        double theta = (cone_deg + 3.0) * M_PI / 180.0 * (n - (RECEIVERS - 398)) / 398.0;
        vec3 q = at_angle(l, theta, 1.3 * n, 1.7);
        p[0][n] = q.x, p[1][n] = q.y, p[2][n] = q.z;
    }
    return n;
}

/* The batch against light_sample, receiver by receiver, in counts that leave remainders. */
static void test_batch_equals_single(const char *light, double cone_deg, double delta_deg)
{
    TestLights b;
    CHECK(build(light, &b));
    int li = b.L.delta_every_count > 0 ? b.L.delta_every[0] : -1;
    CHECK(li >= 0);
    if (li < 0) return;
    const Light *l = &b.L.lights[li];
    static float p[3][RECEIVERS], wi[3][RECEIVERS], dist[RECEIVERS], Li[3][RECEIVERS];
    static int ok[RECEIVERS];
    int n = receivers(l, p, cone_deg, delta_deg);
    int counts[3] = {n, 13, 1};
    int mismatches = 0, lit = 0, dark = 0;
    for (int c = 0; c < 3; ++c) {
        const float *pos[3] = {p[0], p[1], p[2]};
        LightSampleBatch out = {{wi[0], wi[1], wi[2]}, dist, {Li[0], Li[1], Li[2]}, ok};
        light_sample_point_batch(l, counts[c], pos, &out);
        for (int k = 0; k < counts[c]; ++k) {
            LightSample ls;
            bool want = light_sample(&b.L, &b.tr, li, v3(p[0][k], p[1][k], p[2][k]), 0.0f, v2(0.5f, 0.5f), &ls);
            if (want != (ok[k] != 0)) {
                ++mismatches;
                continue;
            }
            if (!want) {
                ++dark;
                continue;
            }
            ++lit;
            bool same = same_bits(ls.wi.x, wi[0][k]) && same_bits(ls.wi.y, wi[1][k]) && same_bits(ls.wi.z, wi[2][k]) &&
                        same_bits(ls.dist, dist[k]) && same_bits(ls.Li.x, Li[0][k]) && same_bits(ls.Li.y, Li[1][k]) &&
                        same_bits(ls.Li.z, Li[2][k]);
            mismatches += !same;
        }
    }
    CHECK(mismatches == 0);
    CHECK(lit > 100);
    if (l->kind == LIGHT_SPOT) CHECK(dark > 100); /* the cone leaves receivers unlit */
    test_lights_free(&b);
}

/* pbrt-v4's SmoothStep of the spot, in double. */
static double smoothstep_d(double x, double a, double b)
{
    if (a == b) return x < a ? 0.0 : 1.0;
    double t = (x - a) / (b - a);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return t * t * (3.0 - 2.0 * t);
}

/* The batch's radiance against I smoothstep(cos_t) / d^2 (away from the edges, where a
 * rounding of cos_t could fall on either side), to 1e-5 of the full cone's I / d^2. */
static void test_closed_form(void)
{
    const double cone = 30.0, delta = 10.0, I = 5.0;
    TestLights b;
    CHECK(build("LightSource \"spot\" \"rgb I\" [ 5 5 5 ] \"point3 from\" [ 0.3 2 -0.2 ] \"point3 to\" [ -0.1 0 0.4 ]"
                " \"float coneangle\" [ 30 ] \"float conedeltaangle\" [ 10 ]",
                &b));
    const Light *l = &b.L.lights[b.L.delta_every[0]];
    enum { N = 997 };
    static float p[3][N], wi[3][N], dist[N], Li[3][N];
    static int ok[N];
    double theta[N];
    for (int k = 0; k < N; ++k) { /* 0 .. 35 degrees from the axis */
        theta[k] = (cone + 5.0) * M_PI / 180.0 * k / (N - 1);
        vec3 q = at_angle(l, theta[k], 0.71 * k, 1.0 + 0.002 * k);
        p[0][k] = q.x, p[1][k] = q.y, p[2][k] = q.z;
    }
    const float *pos[3] = {p[0], p[1], p[2]};
    LightSampleBatch out = {{wi[0], wi[1], wi[2]}, dist, {Li[0], Li[1], Li[2]}, ok};
    light_sample_point_batch(l, N, pos, &out);
    double lo = cos(cone * M_PI / 180.0), hi = cos((cone - delta) * M_PI / 180.0);
    int in_band = 0, wrong = 0;
    for (int k = 0; k < N; ++k) {
        double deg = theta[k] * 180.0 / M_PI;
        if (fabs(deg - cone) < 1e-3 || fabs(deg - (cone - delta)) < 1e-3) continue;
        double dx = l->p_world.x - (double)p[0][k], dy = l->p_world.y - (double)p[1][k], dz = l->p_world.z - (double)p[2][k];
        double d2 = dx * dx + dy * dy + dz * dz;
        double cos_t = -(dx * l->w_world.x + dy * l->w_world.y + dz * l->w_world.z) / sqrt(d2);
        double want = I * smoothstep_d(cos_t, lo, hi) / d2;
        in_band += deg > cone - delta && deg < cone;
        if (want == 0.0) {
            wrong += ok[k] != 0;
        } else {
            /* float's cos_t moves the smoothstep by a few 1e-7 of its full value near the edge */
            bool bad = !ok[k] || fabs(Li[0][k] - want) > 1e-5 * I / d2 || Li[1][k] != Li[0][k] || Li[2][k] != Li[0][k];
            if (bad) fprintf(stderr, "%.4f degrees: Li %.7g, closed form %.7g\n", deg, Li[0][k], want);
            wrong += bad;
        }
    }
    CHECK(wrong == 0);
    CHECK(in_band > 200);
    test_lights_free(&b);
}

int main(void)
{
    test_closed_form();
    test_batch_equals_single("LightSource \"spot\" \"rgb I\" [ 30 20 10 ] \"point3 from\" [ 0.4 2.3 -1.5 ]"
                             " \"point3 to\" [ -0.4 0 0.6 ] \"float coneangle\" [ 22 ] \"float conedeltaangle\" [ 4 ]",
                             22.0, 4.0);
    test_batch_equals_single("LightSource \"spot\" \"rgb I\" [ 3 3 3 ] \"point3 from\" [ 0 2 0 ] \"point3 to\" [ 0 0 0 ]"
                             " \"float coneangle\" [ 40 ] \"float conedeltaangle\" [ 0 ]",
                             40.0, 0.0);
    test_batch_equals_single("LightSource \"point\" \"rgb I\" [ 3 2 1 ] \"point3 from\" [ 0.2 1.5 -0.3 ]", 30.0, 5.0);
    CHECK_DONE();
}
