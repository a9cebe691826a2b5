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
 *    the hemisphere instead of the sphere fails the mean of z.
 *
 * Second, a constant sky sampled by cosine at a Lambert receiver (light_sky_cosine and its
 * batch, issue 22, docs/algorithms.md "A constant sky sampled by cosine at a Lambert receiver").
 *  - The batch equals light_sky_cosine lane by lane, bit for bit: the direction, the
 *    density and the answer on Lambert lanes (random normals, axis normals, uniform
 *    directions from light_sample_sky_batch and the direction -n, whose density is 0), and
 *    the other lanes left as they were; an odd count, so the vector loop's remainder runs.
 *  - Closed form: about a tilted normal n, over a stratified grid of uniform directions, every
 *    direction is a unit vector on n's side with density cos / pi, and the moments are the
 *    cosine-weighted hemisphere's: mean cos 2/3, mean cos^2 1/2, mean direction (2/3) n
 *    (the uniform hemisphere would give 1/2, 1/3 and (1/2) n).
 *  - The estimator it feeds: the sky's irradiance at a plane is its cosine integral pi L
 *    (test_closed_forms renders it; here the density's normalisation: the mean of cos /
 *    pdf over the grid is pi).
 * Teeth: without + n (the uniform direction kept) fails the side and the moments; a density
 * of 1 / (4 pi) fails the density check; the batch's pdf or select changed fails the bit
 * comparison. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/light.h"
#include "render/tracer.h"
#include "render/warp.h"
#include "render_test_util.h"

enum { SAMPLES = 4099, GRID = 61, COSINE_SAMPLES = 2051, M = 200 };
#define PI 3.14159265358979323846

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

static vec3 random_unit(Pcg32 *rng)
{
    vec3 u = warp_uniform_sphere(v2(pcg32_float(rng), pcg32_float(rng)));
    return v3_scale(u, 1.0f / sqrtf(v3_dot(u, u)));
}

/* The sky's uniform directions of the cell centres of an M x M grid of samples. */
static void sky_grid(float gw[3][M * M])
{
    static float g[2][M * M];
    for (int i = 0; i < M; ++i)
        for (int j = 0; j < M; ++j) g[0][i * M + j] = ((float)i + 0.5f) / M, g[1][i * M + j] = ((float)j + 0.5f) / M;
    const float *guv[2] = {g[0], g[1]};
    float *gout[3] = {gw[0], gw[1], gw[2]};
    light_sample_sky_batch(M * M, guv, gout);
}

/* light_sample_sky_batch against light_sample, and the uniform sphere's moments */
static void check_uniform(TestLights *b)
{
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
        bool ok = light_sample(&b->L, &b->tr, 0, p, 0.0f, v2(u[0][k], u[1][k]), &ls);
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
    static float gw[3][M * M];
    sky_grid(gw);
    double mean[3] = {0, 0, 0}, z2 = 0.0;
    for (int k = 0; k < M * M; ++k) {
        for (int c = 0; c < 3; ++c) mean[c] += gw[c][k];
        z2 += (double)gw[2][k] * gw[2][k];
    }
    for (int c = 0; c < 3; ++c) CHECK_NEAR(mean[c] / (M * M), 0.0, 1e-4);
    CHECK_NEAR(z2 / (M * M), 1.0 / 3.0, 1e-4);
}

/* light_sky_cosine_batch against light_sky_cosine, and the cosine hemisphere's moments */
static void check_cosine(TestLights *b)
{
    /* lanes: normals, the sky's uniform directions, Lambert or not, the earlier pdf and ok */
    static float u[2][COSINE_SAMPLES], n[3][COSINE_SAMPLES], wi[3][COSINE_SAMPLES], wi0[3][COSINE_SAMPLES];
    static float pdf[COSINE_SAMPLES], pdf0[COSINE_SAMPLES];
    static int lambert[COSINE_SAMPLES], ok[COSINE_SAMPLES], ok0[COSINE_SAMPLES];
    Pcg32 rng;
    pcg32_seed(&rng, 11u, 3u);
    for (int k = 0; k < COSINE_SAMPLES; ++k) u[0][k] = pcg32_float(&rng), u[1][k] = pcg32_float(&rng);
    const float *uv[2] = {u[0], u[1]};
    float *w[3] = {wi[0], wi[1], wi[2]};
    light_sample_sky_batch(COSINE_SAMPLES, uv, w);
    static const vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    int opposite = 0;
    for (int k = 0; k < COSINE_SAMPLES; ++k) {
        vec3 nk = k < 6 ? axes[k] : random_unit(&rng);
        if (k % 97 == 5) { /* the uniform direction -n: n + d = 0, density 0 */
            wi[0][k] = -nk.x, wi[1][k] = -nk.y, wi[2][k] = -nk.z;
            ++opposite;
        }
        n[0][k] = nk.x, n[1][k] = nk.y, n[2][k] = nk.z;
        lambert[k] = k % 5 != 3;
        pdf[k] = LIGHT_SKY_PDF;
        ok[k] = k % 11 != 7;
        for (int c = 0; c < 3; ++c) wi0[c][k] = wi[c][k];
        pdf0[k] = pdf[k], ok0[k] = ok[k];
    }
    const float *nn[3] = {n[0], n[1], n[2]};
    light_sky_cosine_batch(COSINE_SAMPLES, nn, lambert, w, pdf, ok);
    int bad = 0, zero_density = 0;
    for (int k = 0; k < COSINE_SAMPLES; ++k) {
        if (!lambert[k]) {
            bad += !same_bits(wi[0][k], wi0[0][k]) || !same_bits(wi[1][k], wi0[1][k]) || !same_bits(wi[2][k], wi0[2][k]) ||
                   !same_bits(pdf[k], pdf0[k]) || ok[k] != ok0[k];
            continue;
        }
        LightSample ls;
        vec3 p = v3(0.1f * (float)(k % 9), 0.5f, -0.3f);
        CHECK(light_sample(&b->L, &b->tr, 0, p, 0.0f, v2(u[0][k], u[1][k]), &ls));
        ls.wi = v3(wi0[0][k], wi0[1][k], wi0[2][k]); /* the lane's uniform direction (-n on some) */
        LightSample before = ls;
        bool yes = light_sky_cosine(&b->L, v3(n[0][k], n[1][k], n[2][k]), p, &ls);
        zero_density += !yes;
        if (!yes) bad += memcmp(&ls, &before, sizeof ls) != 0; /* left unchanged */
        vec3 lane = yes ? v3(wi[0][k], wi[1][k], wi[2][k]) : v3(wi0[0][k], wi0[1][k], wi0[2][k]);
        bad += !same_bits(ls.wi.x, lane.x) || !same_bits(ls.wi.y, lane.y) || !same_bits(ls.wi.z, lane.z);
        bad += !same_bits(yes ? ls.pdf : pdf0[k], pdf[k]) || ok[k] != (ok0[k] & yes);
        if (yes) bad += !same_bits(ls.n_light.x, -lane.x) || !(ls.pdf > 0.0f) || isfinite(ls.dist) || ls.delta;
    }
    CHECK(bad == 0);
    CHECK(opposite > 0 && zero_density > 0); /* some -n lanes are Lambert ones */

    /* the cosine-weighted hemisphere about a tilted normal, on a stratified grid */
    static float gw[3][M * M];
    sky_grid(gw);
    vec3 nt = v3_normalize(v3(0.3f, 0.8f, -0.5f));
    double mean_cos = 0.0, mean_cos2 = 0.0, inv_pdf_cos = 0.0, mean_w[3] = {0, 0, 0};
    int off_side = 0, not_unit = 0, wrong_pdf = 0, count = 0;
    for (int k = 0; k < M * M; ++k) {
        LightSample ls = {.wi = v3(gw[0][k], gw[1][k], gw[2][k]), .Li = v3s(1.0f), .pdf = LIGHT_SKY_PDF};
        if (!light_sky_cosine(&b->L, nt, v3s(0.0f), &ls)) continue;
        ++count;
        double c = (double)nt.x * ls.wi.x + (double)nt.y * ls.wi.y + (double)nt.z * ls.wi.z;
        double len = sqrt((double)ls.wi.x * ls.wi.x + (double)ls.wi.y * ls.wi.y + (double)ls.wi.z * ls.wi.z);
        off_side += !(c > 0.0);
        not_unit += fabs(len - 1.0) > 1e-6;
        wrong_pdf += fabs(ls.pdf - c / PI) > 1e-6;
        mean_cos += c, mean_cos2 += c * c, inv_pdf_cos += c / ls.pdf;
        mean_w[0] += ls.wi.x, mean_w[1] += ls.wi.y, mean_w[2] += ls.wi.z;
    }
    CHECK(count == M * M);
    CHECK(off_side == 0);
    CHECK(not_unit == 0);
    CHECK(wrong_pdf == 0);
    CHECK_NEAR(mean_cos / count, 2.0 / 3.0, 1e-3);
    CHECK_NEAR(mean_cos2 / count, 0.5, 1e-3);
    CHECK_NEAR(inv_pdf_cos / count, PI, 1e-4);
    CHECK_NEAR(mean_w[0] / count, 2.0 / 3.0 * nt.x, 1e-3);
    CHECK_NEAR(mean_w[1] / count, 2.0 / 3.0 * nt.y, 1e-3);
    CHECK_NEAR(mean_w[2] / count, 2.0 / 3.0 * nt.z, 1e-3);
}

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
    check_uniform(&b);
    check_cosine(&b);
    test_lights_free(&b);
    CHECK_DONE();
}
