/* Samples of an emitting mesh's triangles, each lane its own triangle, in one batch
 * (light_sample_triangles_batch, issue 22: the wave groups a large mesh's lanes together).
 *  - The batch equals light_sample lane by lane, bit for bit (ok and, where ok, wi, dist,
 *    p_light, pdf), on a curved one-sided mesh (a 6 x 5 patch of a cylinder: 60 triangles,
 *    every normal different, so a lane that read another lane's or the first triangle's
 *    vertices or normal gives other bits) and on its two-sided copy, with receivers on both
 *    sides of it (half the one-sided lanes are refused) and an odd count, so that a
 *    remainder runs too.
 *  - The same lanes through light_sample_triangle_batch, one triangle at a time, give the
 *    same bits: the per-lane batch is the single-light batch with the lane's light. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/light.h"
#include "render/tracer.h"
#include "render_test_util.h"

enum { LANES = 1001, COLS = 6, ROWS = 5 };

/* the patch's points: a cylinder's arc across, 0.4 apart up it */
static void patch_at(void *ctx, int c, int r, double p[3])
{
    (void)ctx;
    double a = -0.8 + 1.6 * c / COLS;
    p[0] = 1.5 * sin(a), p[1] = 0.4 * r, p[2] = 2.0 - 1.5 * cos(a);
}

/* A cylinder patch of COLS x ROWS quads as a trianglemesh emitting L (two_sided or not). */
static bool build(bool two_sided, TestLights *b)
{
    char text[12288];
    size_t len = 0;
    bool ok = test_appendf(text, sizeof text, &len,
                           "LookAt 0 2 -5  0 0.3 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\nWorldBegin\n"
                           "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 2 1 ] \"bool twosided\" %s\nShape \"trianglemesh\" ",
                           two_sided ? "true" : "false") &&
              test_grid_mesh(text, sizeof text, COLS, ROWS, patch_at, NULL);
    len = strlen(text);
    ok = ok && test_appendf(text, sizeof text, &len, "\nAttributeEnd\n");
    return ok && test_build_lights(text, b);
}

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

static void check(bool two_sided)
{
    TestLights b;
    if (!build(two_sided, &b)) {
        CHECK(false);
        return;
    }
    const LightSet *L = &b.L;
    CHECK(L->count == 2 * COLS * ROWS);
    static float p[3][LANES], u[2][LANES], wi[3][LANES], dist[LANES], pl[3][LANES], pdf[LANES];
    static float wi1[3][LANES], dist1[LANES], pl1[3][LANES], pdf1[LANES];
    static int ok[LANES], ok1[LANES], tri[LANES];
    Pcg32 rng;
    pcg32_seed(&rng, 5u, 9u);
    int refused = 0, triangles_seen = 0;
    for (int k = 0; k < LANES; ++k) {
        /* receivers inside the cylinder (the lit side) and outside it (behind the patch) */
        double a = 1.6 * pcg32_float(&rng) - 0.8, rad = k % 2 ? 0.5 * pcg32_float(&rng) : 1.7 + pcg32_float(&rng);
        p[0][k] = (float)(rad * sin(a)), p[1][k] = 2.0f * pcg32_float(&rng), p[2][k] = (float)(2.0 - rad * cos(a));
        u[0][k] = pcg32_float(&rng), u[1][k] = pcg32_float(&rng);
        tri[k] = (int)(pcg32_float(&rng) * (float)L->count) % L->count;
    }
    const float *pp[3] = {p[0], p[1], p[2]}, *uu[2] = {u[0], u[1]};
    TriangleSampleBatch out = {{wi[0], wi[1], wi[2]}, dist, {pl[0], pl[1], pl[2]}, pdf, ok};
    light_sample_triangles_batch(L->lights, tri, LANES, pp, uu, &out);
    int mismatched = 0, mismatched1 = 0;
    for (int k = 0; k < LANES; ++k) {
        LightSample ls;
        bool want = light_sample(L, &b.tr, tri[k], v3(p[0][k], p[1][k], p[2][k]), 0.0f, v2(u[0][k], u[1][k]), &ls);
        refused += !want;
        if ((ok[k] != 0) != want) ++mismatched;
        else if (want && !(same_bits(wi[0][k], ls.wi.x) && same_bits(wi[1][k], ls.wi.y) && same_bits(wi[2][k], ls.wi.z) &&
                           same_bits(dist[k], ls.dist) && same_bits(pl[0][k], ls.p_light.x) &&
                           same_bits(pl[1][k], ls.p_light.y) && same_bits(pl[2][k], ls.p_light.z) && same_bits(pdf[k], ls.pdf)))
            ++mismatched;
        /* the single-light batch for this lane alone */
        const float *p1[3] = {&p[0][k], &p[1][k], &p[2][k]}, *u1[2] = {&u[0][k], &u[1][k]};
        TriangleSampleBatch o1 = {{&wi1[0][k], &wi1[1][k], &wi1[2][k]}, &dist1[k], {&pl1[0][k], &pl1[1][k], &pl1[2][k]}, &pdf1[k], &ok1[k]};
        light_sample_triangle_batch(&L->lights[tri[k]], 1, p1, u1, &o1);
        if (ok1[k] != ok[k] || (ok[k] && !(same_bits(wi1[0][k], wi[0][k]) && same_bits(dist1[k], dist[k]) && same_bits(pdf1[k], pdf[k]))))
            ++mismatched1;
    }
    for (int t = 0; t < L->count; ++t) {
        int seen = 0;
        for (int k = 0; k < LANES; ++k) seen |= tri[k] == t;
        triangles_seen += seen;
    }
    if (mismatched || mismatched1)
        fprintf(stderr, "two_sided %d: %d lanes differ from light_sample, %d from the single-light batch\n", two_sided,
                mismatched, mismatched1);
    CHECK(mismatched == 0 && mismatched1 == 0);
    CHECK(triangles_seen == L->count);
    /* one-sided: the receivers behind the patch are refused; two-sided: none */
    CHECK(two_sided ? refused == 0 : refused > LANES / 4);
    test_lights_free(&b);
}

int main(void)
{
    check(false);
    check(true);
    CHECK_DONE();
}
