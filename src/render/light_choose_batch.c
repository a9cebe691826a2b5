/* lights_choose for a wave's lanes at once, where one emitting mesh holds every light with
 * power (LightSet.sole_mesh_end > 0): see light_choose.h.
 *
 * lights_choose picks a path's light in a chain of dependent steps: the target from u.x,
 * a bisection of the mesh's run of the power CDF (log2 of its triangle count loads, each
 * waiting on the one before), the stretch of u.x by a division. One path at a time that
 * chain is the integrator's longest per-path cost on a scene lit by one large mesh (18% of
 * panel_mesh's CPU, 7% of spot_area_mm's quad, perf). Here each step is a loop over the
 * lanes, vectorised (the CDF's loads become gathers), with lights_pick_in_run's operations
 * in its order, so each lane's answer is the scalar one bit for bit. */
#include "render/light_choose.h"

#include "core/vectorise.h"

/* The batch for count <= CHOOSE_CHUNK lanes (target on the stack); inlined into each of the
 * batch's instruction-set copies (else it is compiled once, for the baseline). */
enum { CHOOSE_CHUNK = 256 };
static inline __attribute__((always_inline)) void choose_chunk(const LightSet *set, int count,
                                                               const float *restrict u_pick, const vec2 *restrict u,
                                                               int *restrict index, float *restrict ux,
                                                               float *restrict pmf, int *restrict regular)
{
    const float *restrict cdf = set->cdf;
    const int first = set->sole_mesh_first, end = set->sole_mesh_end;
    const float total = set->power_total, lo = cdf[first], hi = cdf[end];
    float target[CHOOSE_CHUNK];
    for (int k = 0; k < count; ++k) {
        /* lights_choose's test for the run (the rest take its full path) */
        regular[k] = u_pick[k] * total < total;
        target[k] = lo + u[k].x * (hi - lo);
        index[k] = first;
    }
    /* lights_pick_in_run's bisection: the steps' lengths are the run's alone, so the lanes
     * take them together; each lane's answer stays in [first, end - 1] whatever its target */
    for (int len = end - first; len > 1;) {
        int half = len / 2;
        for (int k = 0; k < count; ++k) index[k] = cdf[index[k] + half] > target[k] ? index[k] : index[k] + half;
        len -= half;
    }
    /* Every light of the run has power (lights_find_sole_mesh): cdf[a + 1] > cdf[a], so its
     * skip of empty lights stays put and w > 0; *pmf is choice[a].pmf = lights_pmf(a), the
     * same quotient. */
    for (int k = 0; k < count; ++k) {
        int a = index[k];
        float c0 = cdf[a], w = cdf[a + 1] - c0;
        float x = (target[k] - c0) / w;
        x = x > 0.0f ? x : 0.0f;
        ux[k] = x < 0x1.fffffep-1f ? x : 0x1.fffffep-1f;
        pmf[k] = w / total;
    }
}

WEDGE_VECTORISED void lights_choose_sole_mesh_batch(const LightSet *set, int count, const float *restrict u_pick,
                                                    const vec2 *restrict u, int *restrict index,
                                                    float *restrict ux, float *restrict pmf,
                                                    int *restrict regular)
{
    for (int k0 = 0; k0 < count; k0 += CHOOSE_CHUNK) {
        int m = count - k0 < CHOOSE_CHUNK ? count - k0 : CHOOSE_CHUNK;
        choose_chunk(set, m, u_pick + k0, u + k0, index + k0, ux + k0, pmf + k0, regular + k0);
    }
}
