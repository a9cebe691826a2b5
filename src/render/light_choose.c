/* lights_choose for a batch of picks at once (declared in light_choose.h). */
#include "render/light_choose.h"

#include "core/vectorise.h"

/* Each loop below does one step of lights_choose for every pick, so the steps are vector
 * operations (the cdf and choice reads are gathers) instead of one dependent chain of loads,
 * compares and a division per pick. Every pick goes through the same operations in the same
 * order as in lights_choose, so the answers are the same bits. */
static WEDGE_VECTORISED void choose_chunk(const LightSet *set, int n, const float *restrict u_pick,
                                          float *restrict u_x, int *restrict index, float *restrict pmf,
                                          bool *restrict static_triangle)
{
    const float *restrict cdf = set->cdf;
    const LightChoice *restrict choice = set->choice;
    int count = set->count;
    float power = set->power_total;
    int lo[LIGHTS_CHOOSE_CHUNK], a[LIGHTS_CHOOSE_CHUNK], len[LIGHTS_CHOOSE_CHUNK], end[LIGHTS_CHOOSE_CHUNK];
    float target[LIGHTS_CHOOSE_CHUNK], target_run[LIGHTS_CHOOSE_CHUNK], ux_out[LIGHTS_CHOOSE_CHUNK], pmf_out[LIGHTS_CHOOSE_CHUNK];
    /* lights_cdf_cell's bisection: its steps depend on count only */
    for (int k = 0; k < n; ++k) lo[k] = 0, target[k] = u_pick[k] * power;
    for (int l = count; l > 1;) {
        int half = l / 2;
        for (int k = 0; k < n; ++k) lo[k] = cdf[lo[k] + half] > target[k] ? lo[k] : lo[k] + half;
        l -= half;
    }
    /* its skip of empty lights, not needed where no light is empty (the loop never runs) */
    if (!set->cdf_increasing)
        for (int k = 0; k < n; ++k)
            while (cdf[lo[k] + 1] - cdf[lo[k]] <= 0.0f && lo[k] < count - 1) ++lo[k];
    /* the light's pmf and the run of its mesh (0, 0 when it has none: length 0) */
    int len_max = 0;
    for (int k = 0; k < n; ++k) {
        const LightChoice *c = &choice[lo[k]];
        pmf[k] = c->pmf;
        int first = c->mesh_first;
        end[k] = c->mesh_end;
        len[k] = end[k] - first;
        a[k] = first;
        float cl = cdf[first], ch = cdf[end[k]];
        target_run[k] = cl + u_x[k] * (ch - cl);
        len_max = len[k] > len_max ? len[k] : len_max;
    }
    /* lights_pick_in_run's bisection, each pick over its own run: a step with half = 0
     * (the run already down to one triangle, or no run) leaves a as it is */
    for (int l = len_max; l > 1;) {
        int half_max = l / 2;
        for (int k = 0; k < n; ++k) {
            int half = len[k] / 2;
            a[k] = cdf[a[k] + half] > target_run[k] ? a[k] : a[k] + half;
            len[k] -= half;
        }
        l -= half_max;
    }
    /* its skip of zero-power triangles, again only where some light is empty */
    if (!set->cdf_increasing)
        for (int k = 0; k < n; ++k)
            if (end[k] > 0)
                while (!(cdf[a[k] + 1] > cdf[a[k]]) && a[k] < end[k] - 1) ++a[k];
    /* lights_choose's outcomes as selects: -1 when the light's pmf is not > 0; the light
     * as picked when it has no run or its triangle's cell is empty; else the triangle, with
     * u.x stretched over its cell and its pmf. (The quotient of a lane that keeps its u.x
     * is computed and dropped.) */
    const float *restrict cdf_next = cdf + 1;
    for (int k = 0; k < n; ++k) {
        int ak = a[k];
        float w = cdf_next[ak] - cdf[ak];
        bool ok = pmf[k] > 0.0f, stretch = ok & (end[k] > 0) & (w > 0.0f);
        float x = (target_run[k] - cdf[ak]) / w, pmf_triangle = choice[ak].pmf;
        x = x > 0.0f ? x : 0.0f;
        x = x < 0x1.fffffep-1f ? x : 0x1.fffffep-1f;
        /* into local arrays first: a select written back in place becomes a masked store,
         * which GCC then will not order against the gathers */
        ux_out[k] = stretch ? x : u_x[k];
        pmf_out[k] = stretch ? pmf_triangle : pmf[k];
        index[k] = !ok ? -1 : stretch ? ak : lo[k];
    }
    for (int k = 0; k < n; ++k) u_x[k] = ux_out[k], pmf[k] = pmf_out[k];
    for (int k = 0; k < n; ++k) {
        int i = index[k] >= 0 ? index[k] : 0;
        static_triangle[k] = (index[k] >= 0) & choice[i].static_triangle;
    }
}

void lights_choose_batch(const LightSet *set, int n, const float *u_pick, float *u_x, int *index, float *pmf,
                         bool *static_triangle)
{
    if (!(set->power_total > 0.0f)) {
        for (int k = 0; k < n; ++k) index[k] = -1, pmf[k] = 0.0f, static_triangle[k] = false;
        return;
    }
    for (int k0 = 0; k0 < n; k0 += LIGHTS_CHOOSE_CHUNK) {
        int m = n - k0 < LIGHTS_CHOOSE_CHUNK ? n - k0 : LIGHTS_CHOOSE_CHUNK;
        choose_chunk(set, m, u_pick + k0, u_x + k0, index + k0, pmf + k0, static_triangle + k0);
    }
}
