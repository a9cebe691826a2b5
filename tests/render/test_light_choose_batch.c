/* The light choice of a wave's lanes in vectorised loops (lights_choose_sole_mesh_batch,
 * issue 22) against lights_choose, one lane at a time, bit for bit.
 *  - Scenes lit by one emitting mesh (LightSet.sole_mesh_end > 0): a quad (2 triangles) and
 *    fans of 7 and 61 triangles of unequal areas, so the run's CDF is uneven and its
 *    bisection takes steps of unequal halves (an odd count leaves a remainder too).
 *  - Every lane the batch calls regular gives lights_choose's index, stretched u.x and pmf
 *    with the same bits, and static_triangle is choice[index]'s; lanes with u_pick = 1 or NaN
 *    are not regular (lights_choose takes its full path there).
 *  - Samples on the CDF's steps (u.x placed on each cdf[k]) as well as random ones, so a
 *    bisection that compared with >= instead of > gives another triangle.
 *  - Any input keeps the index in the run (NaN samples included). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/light_choose.h"
#include "render_test_util.h"

enum { LANES = 4096 };

/* A fan of n triangles about (0, 2, 0) in the plane y = 2, facing down, their outer radii
 * different (unequal powers). n = 2 is a quad. */
static bool build(int n, TestLights *b)
{
    static char text[65536];
    char pts[16384] = "", idx[8192] = "";
    size_t np = 0, ni = 0;
    if (n == 2) {
        np += (size_t)snprintf(pts, sizeof pts, " -1 2 -1  1 2 -1  1 2 1  -1 2 1");
        ni += (size_t)snprintf(idx, sizeof idx, " 0 1 2  0 2 3");
    } else {
        np += (size_t)snprintf(pts, sizeof pts, " 0 2 0");
        for (int i = 0; i <= n; ++i) {
            double a = 3.0 * i / n, r = 0.5 + 0.9 * fabs(sin(1.7 * i));
            np += (size_t)snprintf(pts + np, sizeof pts - np, " %.6f 2 %.6f", r * cos(a), r * sin(a));
        }
        for (int i = 0; i < n; ++i) ni += (size_t)snprintf(idx + ni, sizeof idx - ni, " 0 %d %d", i + 2, i + 1);
    }
    snprintf(text, sizeof text,
             "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\nWorldBegin\n"
             "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 2 1 ]\n"
             "Shape \"trianglemesh\" \"point3 P\" [%s ] \"integer indices\" [%s ]\nAttributeEnd\n",
             pts, idx);
    return test_build_lights(text, b);
}

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

static void check(int n)
{
    TestLights b;
    if (!build(n, &b)) {
        CHECK(false);
        return;
    }
    const LightSet *L = &b.L;
    CHECK(L->count == n && L->sole_mesh_end > 0);
    if (L->sole_mesh_end <= 0) {
        test_lights_free(&b);
        return;
    }
    int first = L->sole_mesh_first, end = L->sole_mesh_end;
    static float u_pick[LANES], ux[LANES], pmf[LANES];
    static vec2 u[LANES];
    static int index[LANES], regular[LANES];
    Pcg32 rng;
    pcg32_seed(&rng, 11u, (uint64_t)n);
    float lo = L->cdf[first], hi = L->cdf[end];
    for (int k = 0; k < LANES; ++k) {
        u_pick[k] = pcg32_float(&rng);
        u[k] = v2(pcg32_float(&rng), pcg32_float(&rng));
        /* lanes on the CDF's steps: u.x whose target is cdf[i], or its neighbours */
        if (k % 4 == 1) {
            int i = first + (int)(pcg32_float(&rng) * (float)(end - first + 1));
            float x = (L->cdf[i] - lo) / (hi - lo);
            u[k].x = k % 8 == 1 ? x : nextafterf(x, k % 16 == 5 ? 0.0f : 1.0f);
        }
    }
    u_pick[7] = 1.0f, u_pick[8] = NAN, u_pick[9] = 0.0f, u_pick[10] = 0x1.fffffep-1f;
    u[11].x = NAN, u[12].x = 0.0f, u[13].x = 0x1.fffffep-1f, u[14].x = 1.0f;
    lights_choose_sole_mesh_batch(L, LANES, u_pick, u, index, ux, pmf, regular);
    int wrong = 0, regular_count = 0, outside = 0, seen = 0;
    static int picked[128];
    memset(picked, 0, sizeof picked);
    for (int k = 0; k < LANES; ++k) {
        outside += index[k] < first || index[k] >= end;
        if (!regular[k]) continue;
        ++regular_count;
        vec2 uu = u[k];
        float want_pmf = 0.0f;
        bool want_static = false;
        int want = lights_choose(L, u_pick[k], &uu, &want_pmf, &want_static);
        if (want != index[k] || !same_bits(uu.x, ux[k]) || !same_bits(want_pmf, pmf[k]) ||
            want_static != L->choice[index[k]].static_triangle)
            ++wrong;
        if (want >= 0 && want < 128) picked[want] = 1;
    }
    for (int i = 0; i < 128; ++i) seen += picked[i];
    if (wrong || outside) fprintf(stderr, "%d triangles: %d lanes differ, %d outside the run\n", n, wrong, outside);
    CHECK(wrong == 0 && outside == 0);
    CHECK(!regular[7] && !regular[8] && regular[9]);
    CHECK(regular_count > LANES * 9 / 10);
    CHECK(seen == n); /* every triangle picked by some lane */
    test_lights_free(&b);
}

int main(void)
{
    check(2);
    check(7);
    check(61);
    CHECK_DONE();
}
