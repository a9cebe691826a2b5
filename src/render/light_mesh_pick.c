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
#include "render/light_choose.h"

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

int lights_pick_in_mesh(const LightSet *set, const Tracer *tr, int li, vec2 *u, float *pmf)
{
    int first, end;
    return lights_mesh_run(set, tr, li, &first, &end) ? lights_pick_in_run(set, first, end, li, u, pmf) : li;
}
