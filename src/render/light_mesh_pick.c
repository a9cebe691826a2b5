/* Choosing the triangle of an emitting mesh from the light-position sample (sample reuse).
 *
 * wedge keeps one Light per emitting triangle and picks one with the light-choice sample,
 * then a point on it with the light-position sample. For a mesh of several triangles the
 * triangle is then chosen by a dimension that is stratified on its own (1D), so each
 * triangle receives a random subset of the position strata: the 2D jittering of the
 * position no longer covers the emitter evenly, and the penumbra variance falls as N^-1
 * instead of up to N^-1.5 (docs/benchmarks.md, "Peers": Mitsuba 3, which picks the triangle
 * of a mesh emitter from the position sample, reached half of wedge's error per sample on
 * the soft-shadow bench at 1024 spp).
 *
 * Here the light-choice sample only picks the mesh (the probability of landing in its run
 * of triangles is unchanged), and u.x of the position sample picks the triangle inside the
 * mesh by the same power CDF and is stretched back to [0, 1): a stratum of u.x then maps to
 * one triangle (or two, at a boundary) and the position strata tile the whole emitter. Each
 * triangle keeps its probability P(mesh) * power_k / power_mesh = power_k / power_total =
 * lights_pmf(k), so the MIS weights, which use lights_pmf, stay correct. */
#include "render/light.h"

#include <math.h>

bool lights_mesh_run(const LightSet *set, const Tracer *tr, int li, int *first, int *end)
{
    const Light *l = &set->lights[li];
    if (l->kind != LIGHT_AREA || l->layer < 0 || l->layer >= tr->layer_count) return false;
    const Geom *g = &tr->layers[l->layer].geoms[l->geom];
    if (g->kind != GEOM_TRIANGLES || g->light_first < 0 || g->triangle_count < 2) return false;
    *first = g->light_first, *end = g->light_first + g->triangle_count;
    if (*end > set->count) return false;
    return set->cdf[*end] > set->cdf[*first];
}

/* The re-pick within the run [first, end) of light li's mesh. */
static inline int pick_in_run(const LightSet *set, int first, int end, int li, vec2 *u, float *pmf)
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

int lights_pick_in_mesh(const LightSet *set, const Tracer *tr, int li, vec2 *u, float *pmf)
{
    int first, end;
    return lights_mesh_run(set, tr, li, &first, &end) ? pick_in_run(set, first, end, li, u, pmf) : li;
}

int lights_choose(const LightSet *set, float u_pick, vec2 *u, float *pmf, bool *static_triangle)
{
    if (!(set->power_total > 0.0f)) return -1;
    int lo = lights_cdf_cell(set, u_pick * set->power_total);
    const LightChoice *c = &set->choice[lo];
    *pmf = c->pmf; /* lights_pick's quotient: lights_pmf is the same expression */
    if (!(c->pmf > 0.0f)) return -1;
    if (c->mesh_end > 0) lo = pick_in_run(set, c->mesh_first, c->mesh_end, lo, u, pmf);
    *static_triangle = set->choice[lo].static_triangle;
    return lo;
}
