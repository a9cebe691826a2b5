/* MAAF's light table from the renderer's lights (see maaf_lights.h).
 *
 * A mesh light's triangles are lights of one shape and share its centroid, its axes (the first
 * triangle's first edge), its extent, its sweep and, mostly, its y-design. Each is found once a
 * shape (ShapeSummary) instead of once per triangle over every other triangle: the table of a
 * 3200-triangle mesh light took 0.4 s that way (docs/benchmarks.md, "Mesh area lights of thousands
 * of triangles").
 * Every value and every order of additions is the per-triangle form's, so the table is the same
 * bit for bit. */
#include "recon/maaf/maaf_lights.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "recon/maaf/maaf_filter.h"
#include "recon/maaf/maaf_light_sweep.h"
#include "recon/maaf/maaf_vertex_extent.h"

/* EXTENT_PLAIN_MAX: a shape of at most this many distinct vertices projects them all (the tree of
 * maaf_vertex_extent.h pays from a few hundred) */
enum { EXTENT_CACHE = 8, EXTENT_PLAIN_MAX = 128 };

/* What the lights of one emitter shape have in common, gathered in light order. */
typedef struct {
    double c[3], area;   /* the sums of area x centroid and of area over the shape's area lights */
    int first_tri;       /* its first triangle light (-1: none) */
    int sweep_from;      /* the first light whose sweep is set (-1: none yet) */
    int design_from;     /* the last light given a y-design (-1: none yet) */
    float (*verts)[3];   /* the distinct vertices of its triangle lights (NULL: none, or out of memory) */
    int vert_count;
    MaafVertexExtent *vert_extent; /* the same in a tree (NULL: few vertices, or out of memory) */
    /* extents already projected, by the normal that set their axes: a planar mesh's triangles'
     * normals, each from its own edges, differ in the last bits, and take a few values */
    int extents, extent_next;
    float extent_normal[EXTENT_CACHE][3], extent_lo[EXTENT_CACHE][2], extent_hi[EXTENT_CACHE][2];
} ShapeSummary;

static float dot3(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static bool is_area(const RenderLightInfo *b) { return b->kind == RENDER_LIGHT_AREA; }

static int cmp_vertex(const void *a, const void *b) { return memcmp(a, b, sizeof(float[3])); }

static void free_summaries(ShapeSummary *s, const RenderLightInfo *info, int count);

/* Summaries indexed by shape in *out (NULL when no area light has a shape). False when out of
 * memory: a shape without its vertices would give each triangle its own box, a narrower light
 * than the shape's, so that is no table to filter with. */
static bool summarise_shapes(const RenderLightInfo *info, int count, ShapeSummary **out)
{
    *out = NULL;
    int top = -1;
    for (int l = 0; l < count; ++l)
        if (is_area(&info[l]) && info[l].shape > top) top = info[l].shape;
    if (top < 0) return true;
    ShapeSummary *s = calloc((size_t)top + 1, sizeof *s);
    if (!s) return false;
    for (int k = 0; k <= top; ++k) s[k].first_tri = s[k].sweep_from = s[k].design_from = -1;
    for (int l = 0; l < count; ++l) {
        const RenderLightInfo *b = &info[l];
        if (!is_area(b) || b->shape < 0) continue;
        ShapeSummary *h = &s[b->shape];
        h->c[0] += b->area_world * b->center_world.x;
        h->c[1] += b->area_world * b->center_world.y;
        h->c[2] += b->area_world * b->center_world.z;
        h->area += b->area_world;
        if (b->is_triangle && h->first_tri < 0) h->first_tri = l;
        if (b->is_triangle) h->vert_count += 3;
    }
    for (int k = 0; k <= top; ++k) {
        size_t n = (size_t)s[k].vert_count;
        s[k].vert_count = 0;
        if (n && !(s[k].verts = malloc(n * sizeof *s[k].verts))) {
            free_summaries(s, info, count);
            return false;
        }
    }
    for (int l = 0; l < count; ++l) {
        const RenderLightInfo *b = &info[l];
        ShapeSummary *h = is_area(b) && b->shape >= 0 && b->is_triangle ? &s[b->shape] : NULL;
        for (int v = 0; h && h->verts && v < 3; ++v) {
            float *q = h->verts[h->vert_count++];
            q[0] = b->tri_world[v].x, q[1] = b->tri_world[v].y, q[2] = b->tri_world[v].z;
        }
    }
    /* shared vertices once: a min or max does not see repeats */
    for (int k = 0; k <= top; ++k) {
        if (!s[k].verts) continue;
        qsort(s[k].verts, (size_t)s[k].vert_count, sizeof *s[k].verts, cmp_vertex);
        int kept = 0;
        for (int v = 0; v < s[k].vert_count; ++v)
            if (kept == 0 || memcmp(s[k].verts[v], s[k].verts[kept - 1], sizeof *s[k].verts) != 0)
                memcpy(s[k].verts[kept++], s[k].verts[v], sizeof *s[k].verts);
        s[k].vert_count = kept;
        /* out of memory for the tree: the plain loop, the same floats (maaf_vertex_extent.h) */
        if (kept > EXTENT_PLAIN_MAX) s[k].vert_extent = maaf_vertex_extent_create((const float(*)[3])s[k].verts, kept);
    }
    *out = s;
    return true;
}

static void free_summaries(ShapeSummary *s, const RenderLightInfo *info, int count)
{
    if (!s) return;
    int top = -1;
    for (int l = 0; l < count; ++l)
        if (is_area(&info[l]) && info[l].shape > top) top = info[l].shape;
    for (int k = 0; k <= top; ++k) free(s[k].verts), maaf_vertex_extent_destroy(s[k].vert_extent);
    free(s);
}

/* A planar triangle's axes, along its shape's first triangle's first edge (every triangle of the
 * shape must use the same axes: a pixel's sums mix samples from all of them), and its extent. */
static void triangle_axes(const RenderLightInfo *info, const float n[3], ShapeSummary *h, int l, MaafLight *ml)
{
    const RenderLightInfo *ft = &info[h ? h->first_tri : l];
    float e[3] = {ft->tri_world[1].x - ft->tri_world[0].x, ft->tri_world[1].y - ft->tri_world[0].y,
                  ft->tri_world[1].z - ft->tri_world[0].z};
    float en = dot3(e, n);
    for (int k = 0; k < 3; ++k) e[k] -= en * n[k];
    float len = sqrtf(dot3(e, e));
    for (int k = 0; k < 3; ++k) ml->t1[k] = len > 0.0f ? e[k] / len : 0.0f;
    ml->t2[0] = n[1] * ml->t1[2] - n[2] * ml->t1[1];
    ml->t2[1] = n[2] * ml->t1[0] - n[0] * ml->t1[2];
    ml->t2[2] = n[0] * ml->t1[1] - n[1] * ml->t1[0];
    /* the axes follow from the shape's first edge and this normal alone, and the centre is the
     * shape's: a planar mesh's triangles (one normal) share the extent, projected once */
    for (int k = 0; h && k < h->extents; ++k)
        if (memcmp(h->extent_normal[k], n, sizeof h->extent_normal[k]) == 0) {
            memcpy(ml->lo, h->extent_lo[k], sizeof ml->lo);
            memcpy(ml->hi, h->extent_hi[k], sizeof ml->hi);
            return;
        }
    if (!h || !h->verts) { /* a triangle of no shape: its own vertices */
        float own[3][3];
        for (int v = 0; v < 3; ++v) own[v][0] = info[l].tri_world[v].x, own[v][1] = info[l].tri_world[v].y, own[v][2] = info[l].tri_world[v].z;
        maaf_vertex_extent_plain((const float(*)[3])own, 3, ml->center, ml->t1, ml->t2, ml->lo, ml->hi);
        return;
    }
    if (h->vert_extent)
        maaf_vertex_extent_along(h->vert_extent, ml->center, ml->t1, ml->t2, ml->lo, ml->hi);
    else
        maaf_vertex_extent_plain((const float(*)[3])h->verts, h->vert_count, ml->center, ml->t1, ml->t2, ml->lo, ml->hi);
    int k = h->extent_next;
    h->extent_next = (k + 1) % EXTENT_CACHE;
    if (h->extents < EXTENT_CACHE) ++h->extents;
    memcpy(h->extent_normal[k], n, sizeof h->extent_normal[k]);
    memcpy(h->extent_lo[k], ml->lo, sizeof h->extent_lo[k]);
    memcpy(h->extent_hi[k], ml->hi, sizeof h->extent_hi[k]);
}

/* Light l's swept light from the first triangle of its shape that has one: the sweep is the
 * shape's (its centroid, extent and poses over every triangle, along the shape's axes),
 * whichever of its triangles asks. False when there is none. */
static bool copy_shape_sweep(const ShapeSummary *h, const MaafLight *lights, MaafLight *ml)
{
    if (!h || h->sweep_from < 0) return false;
    const MaafLight *mk = &lights[h->sweep_from];
    memcpy(ml->center, mk->center, sizeof ml->center);
    memcpy(ml->lo, mk->lo, sizeof ml->lo);
    memcpy(ml->hi, mk->hi, sizeof ml->hi);
    ml->sweep = mk->sweep;
    ml->sweep_nodes = mk->sweep_nodes;
    return true;
}

/* The lights given a y-design of their own, found by what the design depends on (its band and
 * extents, maaf_light_design_copy's comparisons), so that a light finds an earlier one with the
 * same design without comparing itself with every earlier light: a curved mesh light's triangles
 * each have extents of their own, and that search was quadratic in them (10,000 triangles: 5e7
 * comparisons, most of the table's time). Open addressing, -1 empty. Every earlier light with the
 * same design holds the same band and means bit for bit, so whichever one is found gives the copy
 * the scan in light order gave. */
typedef struct {
    int *slot;
    size_t mask;
} DesignIndex;

static uint64_t mix_bits(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull; /* FNV-1a */
    return h;
}

static uint64_t design_hash(float omega_y_max, const MaafLight *l)
{
    /* + 0.0f: -0 and +0 compare equal in maaf_light_design_copy, so they must hash alike */
    float key[5] = {omega_y_max + 0.0f, l->lo[0] + 0.0f, l->hi[0] + 0.0f, l->lo[1] + 0.0f, l->hi[1] + 0.0f};
    uint64_t h = mix_bits(14695981039346656037ull, key, sizeof key);
    h = mix_bits(h, &l->sweep_nodes, sizeof l->sweep_nodes);
    if (l->sweep_nodes && l->sweep) h = mix_bits(h, l->sweep, sizeof *l->sweep);
    return h;
}

static void design_index_init(DesignIndex *x, int count)
{
    size_t cap = 16;
    while (cap < 2 * (size_t)(count > 0 ? count : 1)) cap *= 2;
    x->slot = malloc(cap * sizeof *x->slot);
    x->mask = cap - 1;
    if (x->slot)
        for (size_t i = 0; i < cap; ++i) x->slot[i] = -1;
}

/* Copies into ml the design of an indexed light with ml's band and extents; false when none. */
static bool design_index_copy(const DesignIndex *x, const MaafLight *lights, float sigma, MaafLight *ml)
{
    float wy = sigma > 0.0f && isfinite(sigma) ? 2.0f / sigma : 0.0f;
    if (!x->slot || !(wy > 0.0f)) return false;
    for (size_t i = design_hash(wy, ml) & x->mask; x->slot[i] >= 0; i = (i + 1) & x->mask)
        if (maaf_light_design_copy(&lights[x->slot[i]], sigma, ml)) return true;
    return false;
}

static void design_index_add(DesignIndex *x, const MaafLight *ml, int l)
{
    if (!x->slot || !(ml->omega_y_max > 0.0f)) return;
    size_t i = design_hash(ml->omega_y_max, ml) & x->mask;
    while (x->slot[i] >= 0) i = (i + 1) & x->mask;
    x->slot[i] = l;
}

bool maaf_lights_from_renderer(const Renderer *r, const AafLightGeom *geoms, int count, int pairs, float kappa,
                               MaafLight *lights)
{
    for (int l = 0; l < count; ++l) memset(&lights[l], 0, sizeof lights[l]);
    RenderLightInfo *info = calloc(count > 0 ? (size_t)count : 1, sizeof *info);
    if (!info) return false;
    for (int l = 0; l < count; ++l)
        if (!renderer_light_info(r, l, &info[l])) info[l].kind = RENDER_LIGHT_POINT;
    ShapeSummary *summary = NULL;
    /* the poses of each light that sweeps its own (a shape's first moving triangle, a disk), kept
     * until the table is done: its shape's other triangles and the design index read them */
    bool any_moving = false;
    for (int l = 0; l < count; ++l) any_moving = any_moving || (is_area(&info[l]) && info[l].moving);
    MaafSweep **poses = any_moving ? calloc((size_t)count, sizeof *poses) : NULL;
    if (!summarise_shapes(info, count, &summary) || (any_moving && !poses)) {
        free_summaries(summary, info, count);
        free(poses);
        free(info);
        return false;
    }
    DesignIndex designs;
    design_index_init(&designs, count); /* out of memory (no slots): every light designs its own, the same design */
    bool ok = true;
    for (int l = 0; l < count; ++l) {
        MaafLight *ml = &lights[l];
        if (!is_area(&info[l]) || !(geoms[l].sigma_world > 0.0f)) continue;
        ShapeSummary *h = info[l].shape >= 0 ? &summary[info[l].shape] : NULL; /* NULL: a light of no shape */
        double c[3], area;
        if (h) {
            memcpy(c, h->c, sizeof c), area = h->area;
        } else {
            c[0] = info[l].area_world * info[l].center_world.x, c[1] = info[l].area_world * info[l].center_world.y;
            c[2] = info[l].area_world * info[l].center_world.z, area = info[l].area_world;
        }
        for (int k = 0; k < 3; ++k) ml->center[k] = area > 0.0 ? (float)(c[k] / area) : 0.0f;
        const float *n = geoms[l].normal;
        bool planar = dot3(n, n) > 0.5f;
        if (planar && info[l].is_triangle) {
            triangle_axes(info, n, h, l, ml);
        } else {
            if (planar) maaf_basis(n, ml->t1, ml->t2); /* disk; a sphere's axes face each receiver */
            float half = 0.5f * sqrtf((float)M_PI) * geoms[l].radius_world; /* box of the same area */
            ml->lo[0] = ml->lo[1] = -half;
            ml->hi[0] = ml->hi[1] = half;
        }
        /* a moving planar light: its swept light (maaf_light_sweep.h), one sweep a shape: the
         * sweep reads every triangle of the shape at each pose, so a mesh light's triangles each
         * sweeping it cost O(triangles^2) poses (minutes for a few thousand) */
        bool shape_sweep = h && info[l].is_triangle;
        if (info[l].moving && !(shape_sweep && copy_shape_sweep(h, lights, ml))) {
            /* without its poses a moving light would be designed as if it stood still */
            if (!(poses[l] = malloc(sizeof *poses[l]))) {
                ok = false;
                break;
            }
            if (!maaf_light_sweep(r, l, 0.5f * sqrtf((float)M_PI) * geoms[l].radius_world, poses[l], ml))
                free(poses[l]), poses[l] = NULL;
        }
        if (shape_sweep && info[l].moving && h->sweep_from < 0 && ml->sweep_nodes != 0) h->sweep_from = l;
        if (!(ml->hi[0] > ml->lo[0]) || !(ml->hi[1] > ml->lo[1]) || !isfinite(ml->hi[0] - ml->lo[0] + ml->hi[1] - ml->lo[1]))
            continue; /* degenerate: omega_y_max stays 0, its samples are not used */
        /* the knob scales the whole design: Omega_y_max = kappa 2 / sigma_light; the triangles of
         * one mesh light have one design, made once (any earlier light with the same design gives
         * it: the shape's last first, then the rest in order) */
        float sigma = geoms[l].sigma_world / kappa;
        bool copied = h && h->design_from >= 0 && maaf_light_design_copy(&lights[h->design_from], sigma, ml);
        if (!copied) copied = design_index_copy(&designs, lights, sigma, ml);
        if (!copied) {
            maaf_light_design(sigma, pairs, ml);
            design_index_add(&designs, ml, l);
        }
        if (h) h->design_from = l;
    }
    for (int l = 0; poses && l < count; ++l) lights[l].sweep = NULL, free(poses[l]);
    free(poses);
    free_summaries(summary, info, count);
    free(designs.slot);
    free(info);
    if (!ok)
        for (int l = 0; l < count; ++l) memset(&lights[l], 0, sizeof lights[l]);
    return ok;
}
