/* The per-sample light choice: a light by power (lights_pick), then the triangle of an
 * emitting mesh from u.x (lights_pick_in_mesh, light_mesh_pick.c), inline for the
 * integrator. */
#ifndef WEDGE_RENDER_LIGHT_CHOOSE_H
#define WEDGE_RENDER_LIGHT_CHOOSE_H

#include "render/light.h"

/* The first i with cdf[i + 1] > target, else count - 1, skipping empty lights. The answer
 * stays in [lo, lo + len - 1] and each step halves len whatever the comparison says (cdf is
 * non-decreasing), as in lights_pick_in_mesh, so the comparison is a conditional move, not a
 * branch on the random u that mispredicts half the time. */
static inline int lights_cdf_cell(const LightSet *set, float target)
{
    int lo = 0;
    for (int len = set->count; len > 1;) {
        int half = len / 2;
        lo = set->cdf[lo + half] > target ? lo : lo + half;
        len -= half;
    }
    /* skip empty lights; the power test first, as in lights_pick_in_mesh (lo + 1 <= count) */
    while (set->cdf[lo + 1] - set->cdf[lo] <= 0.0f && lo < set->count - 1) ++lo;
    return lo;
}

/* lights_pick_in_mesh's re-pick of the triangle within the run [first, end) of light li's mesh
 * (the run lights_mesh_run gives). */
static inline int lights_pick_in_run(const LightSet *set, int first, int end, int li, vec2 *u, float *pmf)
{
    float lo = set->cdf[first], hi = set->cdf[end];
    float target = lo + u->x * (hi - lo);
    /* The first k in [first, end - 1) with cdf[k + 1] > target, else end - 1. The answer
     * stays in [a, a + len - 1]; each step halves len whatever the comparison says, so the
     * loop's branch depends on the mesh only and the comparison becomes a conditional move
     * (u->x is random: as a branch it mispredicted half the time, a visible cost on a
     * two-triangle quad light). NaN cannot occur (target is finite), and the comparison is
     * the one of a plain bisection, so the same k results. */
    int a = first;
    for (int len = end - first; len > 1;) {
        int half = len / 2;
        a = set->cdf[a + half] > target ? a : a + half;
        len -= half;
    }
    /* Skip zero-power triangles. The power test comes first: the bound's test alone depends
     * on the random a (on a two-triangle quad light a mispredicted branch every other
     * sample), the power test is nearly always false. (cdf[a + 1] exists: end <= count.) */
    while (!(set->cdf[a + 1] > set->cdf[a]) && a < end - 1) ++a;
    float w = set->cdf[a + 1] - set->cdf[a];
    if (!(w > 0.0f)) return li;
    float x = (target - set->cdf[a]) / w;
    /* rounding can put target a hair outside the chosen interval */
    /* fminf(fmaxf(x, 0), 1 - 2^-24) inline (x is finite and never -0: (target - cdf[a])
     * is +0 when the two are equal) */
    x = x > 0.0f ? x : 0.0f;
    u->x = x < 0x1.fffffep-1f ? x : 0x1.fffffep-1f;
    *pmf = set->choice ? set->choice[a].pmf : lights_pmf(set, a); /* the same value */
    return a;
}

/* lights_pick, then lights_pick_in_mesh on the light it picked, with the same results bit
 * for bit (*pmf written as they write it, u->x stretched as they do), and *static_triangle
 * = light_is_static_triangle of the answer when it is >= 0. Through set->choice, so only
 * for a set from lights_build; inline, as the integrator calls it once a vertex. */
static inline int lights_choose(const LightSet *set, float u_pick, vec2 *u, float *pmf, bool *static_triangle)
{
    int lo, first, end;
    /* One emitting mesh holds every light with power (sole_mesh_end > 0): any target below
     * the total lands in its run (a light before it has no width to land in), where
     * lights_pick_in_run re-picks from u->x whatever light was picked, so the first pick
     * is skipped; *pmf is the one lights_pick_in_run writes either way, and its w > 0 by
     * the run's powers. The target at or above the total, or NaN, takes the full path. */
    if (set->sole_mesh_end > 0 && u_pick * set->power_total < set->power_total) {
        lo = first = set->sole_mesh_first, end = set->sole_mesh_end;
    } else {
        if (!(set->power_total > 0.0f)) return -1;
        float target = u_pick * set->power_total;
        /* one light with power: the search's answer for every target in [0, total)
         * (LightSet.sole_light); the rest (a target at or above the total, NaN) searches */
        bool sole = set->sole_light >= 0 && target >= 0.0f && target < set->power_total;
        lo = sole ? set->sole_light : lights_cdf_cell(set, target);
        const LightChoice *c = &set->choice[lo];
        *pmf = c->pmf; /* lights_pick's quotient: lights_pmf is the same expression */
        if (!(c->pmf > 0.0f)) return -1;
        first = c->mesh_first, end = c->mesh_end;
    }
    if (end > 0) lo = lights_pick_in_run(set, first, end, lo, u, pmf);
    *static_triangle = set->choice[lo].static_triangle;
    return lo;
}

/* lights_choose for lanes [0, count) of a set from lights_build with a sole mesh
 * (sole_mesh_end > 0), from the lanes' choice samples u_pick[k] and position samples u[k]:
 * where regular[k], lights_choose(set, u_pick[k], &u[k], ...) returns index[k], stretches
 * u[k].x to ux[k] and writes pmf[k], bit for bit (its static_triangle is
 * set->choice[index[k]].static_triangle); where not, lights_choose takes its full path and
 * the lane's other outputs mean nothing. Any input is safe (index[k] stays in the run).
 * Vectorised (light_choose_batch.c). */
void lights_choose_sole_mesh_batch(const LightSet *set, int count, const float *restrict u_pick,
                                   const vec2 *restrict u, int *restrict index, float *restrict ux,
                                   float *restrict pmf, int *restrict regular);

#endif
