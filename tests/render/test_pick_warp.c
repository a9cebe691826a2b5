/* Two branch-free rewrites against the plain code they replace, value for value:
 * lights_pick's bisection against a linear scan of the CDF (zero-power lights, ties, every
 * count from 1 to 13, targets on and between the CDF's steps), and the concentric disk map
 * against its two-branch textbook form (Shirley and Chiu 1997) on a grid that hits both
 * wedges, their boundaries and the centre; the map's points lie in the unit disk. The run
 * forms of the concentric and cosine-hemisphere maps (warp_batch.c) against the inline ones. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "render/light.h"
#include "render/warp.h"

/* lights_pick as a linear scan: the first light whose CDF step lies above the target, the
 * empty lights after it skipped. */
static int pick_scan(const LightSet *set, float u, float *pmf)
{
    if (!(set->power_total > 0.0f)) return -1;
    float target = u * set->power_total;
    int i = 0;
    while (i < set->count - 1 && !(set->cdf[i + 1] > target)) ++i;
    while (i < set->count - 1 && set->cdf[i + 1] - set->cdf[i] <= 0.0f) ++i;
    *pmf = (set->cdf[i + 1] - set->cdf[i]) / set->power_total;
    return *pmf > 0.0f ? i : -1;
}

static vec2 concentric_reference(vec2 u)
{
    float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
    if (ox == 0.0f && oy == 0.0f) return v2(0.0f, 0.0f);
    float s, c;
    if (fabsf(ox) > fabsf(oy)) {
        sincos_quarter_pi((WEDGE_PI / 4.0f) * (oy / ox), &s, &c);
        return v2(ox * c, ox * s);
    }
    sincos_quarter_pi((WEDGE_PI / 4.0f) * (ox / oy), &s, &c);
    return v2(oy * s, oy * c);
}

int main(void)
{
    /* lights_pick */
    float cdf[14];
    LightSet set;
    memset(&set, 0, sizeof set);
    set.cdf = cdf;
    int mismatches = 0, picks = 0;
    for (int count = 1; count <= 13; ++count) {
        for (int pattern = 0; pattern < 8; ++pattern) {
            cdf[0] = 0.0f;
            for (int i = 0; i < count; ++i) {
                /* some lights of zero power (delta_every lights have none), unequal powers */
                float power = ((i * 7 + pattern) % 5 == 0) ? 0.0f : (float)(1 + (i * 3 + pattern) % 4);
                cdf[i + 1] = cdf[i] + power;
            }
            set.count = count;
            set.power_total = cdf[count];
            for (int k = 0; k <= 997; ++k) {
                float u = k < 997 ? (float)k / 997.0f : 0x1.fffffep-1f;
                float pmf_a = -1.0f, pmf_b = -2.0f;
                int a = lights_pick(&set, u, &pmf_a), b = pick_scan(&set, u, &pmf_b);
                mismatches += a != b || (a >= 0 && pmf_a != pmf_b);
                ++picks;
            }
            /* targets exactly on each step of the CDF */
            for (int i = 0; i <= count && set.power_total > 0.0f; ++i) {
                float u = cdf[i] / set.power_total, pmf_a = -1.0f, pmf_b = -2.0f;
                if (!(u < 1.0f)) continue;
                int a = lights_pick(&set, u, &pmf_a), b = pick_scan(&set, u, &pmf_b);
                mismatches += a != b || (a >= 0 && pmf_a != pmf_b);
                ++picks;
            }
        }
    }
    CHECK(picks > 100000);
    CHECK(mismatches == 0);

    /* warp_disk_concentric: every bit as the two-branch form, inside the unit disk */
    enum { N = 513 };
    int differ = 0, outside = 0;
    for (int i = 0; i <= N; ++i)
        for (int j = 0; j <= N; ++j) {
            vec2 u = v2(i < N ? (float)i / N : 0x1.fffffep-1f, j < N ? (float)j / N : 0x1.fffffep-1f);
            vec2 a = warp_disk_concentric(u), b = concentric_reference(u);
            differ += memcmp(&a, &b, sizeof a) != 0;
            outside += a.x * a.x + a.y * a.y > 1.0f + 1e-6f;
        }
    srand(7);
    for (int k = 0; k < 100000; ++k) {
        vec2 u = v2((float)(rand() >> 7) * 0x1p-24f, (float)(rand() >> 7) * 0x1p-24f);
        vec2 a = warp_disk_concentric(u), b = concentric_reference(u);
        differ += memcmp(&a, &b, sizeof a) != 0;
    }
    CHECK(differ == 0);
    CHECK(outside == 0);

    /* the run forms (warp_batch.c, vectorised in the copy this CPU runs) against the inline
     * maps, every bit, for run lengths that leave vector remainders */
    enum { RUN = 67 };
    vec2 u[RUN];
    float x[RUN], y[RUN], z[RUN];
    int run_differ = 0, runs = 0;
    for (int len = 0; len <= RUN; len += 1 + len / 3) {
        for (int k = 0; k < 200; ++k) {
            for (int i = 0; i < len; ++i) {
                u[i] = v2((float)(rand() >> 7) * 0x1p-24f, (float)(rand() >> 7) * 0x1p-24f);
                if ((i + k) % 11 == 0) u[i] = v2(0.5f, 0.5f);     /* the centre */
                if ((i + k) % 13 == 0) u[i].x = u[i].y;           /* a wedge boundary */
                if ((i + k) % 17 == 0) u[i].y = 0x1.fffffep-1f;   /* the edge */
            }
            warp_disk_concentric_run(len, u, x, y);
            for (int i = 0; i < len; ++i) {
                vec2 a = warp_disk_concentric(u[i]);
                run_differ += memcmp(&a.x, &x[i], sizeof x[i]) != 0 || memcmp(&a.y, &y[i], sizeof y[i]) != 0;
            }
            warp_cosine_hemisphere_run(len, u, x, y, z);
            for (int i = 0; i < len; ++i) {
                vec3 a = warp_cosine_hemisphere(u[i]);
                run_differ += memcmp(&a.x, &x[i], sizeof x[i]) != 0 || memcmp(&a.y, &y[i], sizeof y[i]) != 0 ||
                              memcmp(&a.z, &z[i], sizeof z[i]) != 0;
            }
            runs += len;
        }
    }
    printf("runs: %d values, %d differ\n", runs, run_differ);
    CHECK(runs > 40000 && run_differ == 0);
    CHECK_DONE();
}
