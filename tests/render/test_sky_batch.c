/* A constant sky's samples for many receivers at once (light_sample_sky_batch, issue 22,
 * docs/design.md 12.23).
 *  - The batch equals light_sample sample by sample, bit for bit (the direction; pdf
 *    LIGHT_SKY_PDF, Li the light's, an infinite distance and not delta on light_sample's
 *    side), on random position samples, a grid that holds both ends of [0, 1) and the
 *    values where the square root's argument 1 - z^2 is 0, in an odd count so that the
 *    vector loop's remainder runs too.
 *  - Closed form: the directions are unit vectors, z = 1 - 2 u.x, and over a stratified
 *    grid of u their mean is the uniform sphere's, 0 in each coordinate, and the mean of z^2
 *    is 1/3. Teeth: sine and cosine swapped, or phi scaled, fails the bit comparison;
 *    the hemisphere instead of the sphere fails the mean of z. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/light.h"
#include "render/tracer.h"
#include "render_test_util.h"

enum { SAMPLES = 4099, GRID = 61 };

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

int main(void)
{
    TestLights b;
    if (!test_build_lights("LookAt 0 2 -5  0 0.3 0  0 1 0\n"
                           "Camera \"perspective\" \"float fov\" [ 45 ]\n"
                           "WorldBegin\n"
                           "LightSource \"infinite\" \"rgb L\" [ 0.55 0.65 0.85 ]\n"
                           "Shape \"sphere\" \"float radius\" [ 1 ]\n",
                           &b)) {
        CHECK(false);
        return 1;
    }
    CHECK(b.L.count == 1 && light_is_constant_sky(&b.L.lights[0]));
    static float u[2][SAMPLES], wi[3][SAMPLES];
    int n = 0;
    /* a grid with both ends and the middle of each axis */
    for (int i = 0; i < GRID; ++i)
        for (int j = 0; j < GRID; ++j, ++n) {
            u[0][n] = i == GRID - 1 ? 0x1.fffffep-1f : (float)i / (GRID - 1);
            u[1][n] = j == GRID - 1 ? 0x1.fffffep-1f : (float)j / (GRID - 1);
        }
    Pcg32 rng;
    pcg32_seed(&rng, 5u, 9u);
    for (; n < SAMPLES; ++n) u[0][n] = pcg32_float(&rng), u[1][n] = pcg32_float(&rng);
    const float *uv[2] = {u[0], u[1]};
    float *out[3] = {wi[0], wi[1], wi[2]};
    light_sample_sky_batch(SAMPLES, uv, out);

    int bad = 0, not_unit = 0, z_off = 0;
    for (int k = 0; k < SAMPLES; ++k) {
        LightSample ls;
        vec3 p = v3(0.3f * (float)(k % 7), 1.0f, -0.2f * (float)(k % 5)); /* the receiver does not matter */
        bool ok = light_sample(&b.L, &b.tr, 0, p, 0.0f, v2(u[0][k], u[1][k]), &ls);
        if (!ok || !same_bits(ls.wi.x, wi[0][k]) || !same_bits(ls.wi.y, wi[1][k]) || !same_bits(ls.wi.z, wi[2][k]))
            ++bad;
        if (!same_bits(ls.pdf, LIGHT_SKY_PDF) || ls.delta || isfinite(ls.dist)) ++bad;
        double len = sqrt((double)wi[0][k] * wi[0][k] + (double)wi[1][k] * wi[1][k] + (double)wi[2][k] * wi[2][k]);
        if (fabs(len - 1.0) > 1e-6) ++not_unit;
        if (!same_bits(wi[2][k], 1.0f - 2.0f * u[0][k])) ++z_off;
    }
    CHECK(bad == 0);
    CHECK(not_unit == 0);
    CHECK(z_off == 0);

    /* the uniform sphere's moments on a stratified grid (cell centres) */
    enum { M = 200 };
    static float g[2][M * M], gw[3][M * M];
    for (int i = 0; i < M; ++i)
        for (int j = 0; j < M; ++j) g[0][i * M + j] = ((float)i + 0.5f) / M, g[1][i * M + j] = ((float)j + 0.5f) / M;
    const float *guv[2] = {g[0], g[1]};
    float *gout[3] = {gw[0], gw[1], gw[2]};
    light_sample_sky_batch(M * M, guv, gout);
    double mean[3] = {0, 0, 0}, z2 = 0.0;
    for (int k = 0; k < M * M; ++k) {
        for (int c = 0; c < 3; ++c) mean[c] += gw[c][k];
        z2 += (double)gw[2][k] * gw[2][k];
    }
    for (int c = 0; c < 3; ++c) CHECK_NEAR(mean[c] / (M * M), 0.0, 1e-4);
    CHECK_NEAR(z2 / (M * M), 1.0 / 3.0, 1e-4);
    test_lights_free(&b);
    CHECK_DONE();
}
