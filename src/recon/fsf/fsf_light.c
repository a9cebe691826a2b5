/* The light frame and unoccluded irradiance of FSF (fsf_light.h). */
#include "recon/fsf/fsf_light.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recon/aaf/aaf_light_sweep.h"
#include "recon/emitter_boundary.h"
#include "recon/emitter_facing.h"
#include "recon/moving_lights.h"
#include "recon/polygon_irradiance.h"
#include "recon/recon_parallel.h"
#include "recon/shared_triangles.h"

FsfGrid fsf_light_grid(const FsfLight *l)
{
    FsfGrid g = fsf_grid_nodes(l->half_m[0], l->half_m[1], FSF_LIGHT_SHIFT_NODES);
    g.reach_sigmas = FSF_REACH_SIGMAS_NARROW;
    g.ramp_m[0] = l->ramp_m[0];
    g.ramp_m[1] = l->ramp_m[1];
    return g;
}

bool fsf_pixel_creased(const GBuffer *g, size_t i)
{
    const GBufferSums *s = &g->sums[i];
    if (s->hits <= 0) return false;
    float len2 = s->nrm_sum[0] * s->nrm_sum[0] + s->nrm_sum[1] * s->nrm_sum[1] + s->nrm_sum[2] * s->nrm_sum[2];
    float limit = FSF_CREASE_MEAN_NORMAL * (float)s->hits;
    return len2 < limit * limit;
}

float fsf_light_power_share(const Renderer *r)
{
    FsfLight light;
    Diag quiet = {0};
    if (!fsf_light_from_renderer(r, &light, &quiet)) return 0.0f;
    double mine = 0.0, all = 0.0;
    for (int l = 0; l < renderer_light_count(r); ++l) {
        RenderLightInfo b;
        if (!renderer_light_info(r, l, &b)) continue;
        if (b.kind != RENDER_LIGHT_AREA) return 0.0f;
        double power = (double)v3_luminance(b.radiance) * b.area_world;
        all += power;
        if (b.is_triangle && b.shape == light.shape) mine += power;
    }
    return all > 0.0 ? (float)(mine / all) : 0.0f;
}

/* Along the unit axis `axis` (index a of the sweep's), a translating light's pose extent (at
 * shutter open) w and its motion m (the centroid from shutter open to close): its samples'
 * density is the trapezoid box(w) * box(m), whose ramps are min(w, |m|) wide (docs/algorithms.md
 * 10, "The swept light's density"). */
static float swept_ramp(const ReconLightSweep *sw, const float axis[3], int a, float *pose, float *motion)
{
    double m = 0.0;
    for (int k = 0; k < 3; ++k) m += (sw->end_centre[1][k] - sw->end_centre[0][k]) * axis[k];
    double width = sw->end_hi[0][a] - sw->end_lo[0][a];
    *pose = (float)width, *motion = (float)m;
    return (float)fmin(width, fabs(m));
}

bool fsf_light_from_renderer(const Renderer *r, FsfLight *out, Diag *d)
{
    int count = renderer_light_count(r), best = -1;
    float best_power = 0.0f;
    /* the brightest emitter shape: luminance times its triangles' total area, summed a shape at
     * a time in one pass over the lights (a mesh light has a light per triangle: a sum per light
     * over every light would be quadratic in them); its first triangle stands for it */
    int shapes = 0;
    for (int l = 0; l < count; ++l) {
        RenderLightInfo a;
        if (renderer_light_info(r, l, &a) && a.kind == RENDER_LIGHT_AREA && a.is_triangle && a.shape + 2 > shapes)
            shapes = a.shape + 2; /* slot shape + 1: shape -1 (none) has its own */
    }
    float *power = calloc(shapes > 0 ? (size_t)shapes : 1, sizeof *power);
    int *first_of = malloc((shapes > 0 ? (size_t)shapes : 1) * sizeof *first_of);
    if (!power || !first_of) {
        free(power), free(first_of);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF's light");
        return false;
    }
    for (int k = 0; k < shapes; ++k) first_of[k] = -1;
    for (int l = 0; l < count; ++l) {
        RenderLightInfo b;
        if (!renderer_light_info(r, l, &b) || b.kind != RENDER_LIGHT_AREA || !b.is_triangle || b.shape < -1) continue;
        /* a degenerate triangle (a latitude-longitude sphere's poles have rings of them) emits
         * nothing and has no normal to set the axes */
        if (!(b.area_world > 0.0f) || !(v3_length2(b.normal_world) > 0.5f)) continue;
        power[b.shape + 1] += v3_luminance(b.radiance) * b.area_world;
        if (first_of[b.shape + 1] < 0) first_of[b.shape + 1] = l;
    }
    /* in the order of the shapes' first triangles, the first of the brightest */
    for (int l = 0; l < count; ++l) {
        RenderLightInfo a;
        if (!renderer_light_info(r, l, &a) || a.kind != RENDER_LIGHT_AREA || !a.is_triangle || a.shape < -1 ||
            first_of[a.shape + 1] != l)
            continue;
        if (power[a.shape + 1] > best_power) best_power = power[a.shape + 1], best = l;
    }
    free(power), free(first_of);
    if (best < 0) {
        diag_set(d, WEDGE_EXIT_USAGE, (SrcLoc){0},
                 "--filter fsf filters soft shadows of a planar area light made of triangles; the scene has none");
        return false;
    }
    RenderLightInfo first;
    renderer_light_info(r, best, &first);
    vec3 c = v3s(0.0f);
    float area = 0.0f;
    for (int m = 0; m < count; ++m) {
        RenderLightInfo b;
        if (!renderer_light_info(r, m, &b) || b.kind != RENDER_LIGHT_AREA || !b.is_triangle || b.shape != first.shape ||
            !(b.area_world > 0.0f))
            continue;
        c = v3_madd(c, b.center_world, b.area_world);
        area += b.area_world;
    }
    c = v3_scale(c, 1.0f / area);
    /* u along the first triangle's shortest edge, projected into the light's plane */
    vec3 n = first.normal_world, e = v3_sub(first.tri_world[1], first.tri_world[0]);
    for (int k = 1; k < 3; ++k) {
        vec3 f = v3_sub(first.tri_world[(k + 1) % 3], first.tri_world[k]);
        if (v3_length2(f) < v3_length2(e)) e = f;
    }
    vec3 u = v3_madd(e, n, -v3_dot(e, n));
    u = v3_scale(u, 1.0f / v3_length(u));
    vec3 v = v3_cross(n, u);
    float half[2] = {0.0f, 0.0f}, ramp[2] = {0.0f, 0.0f}, pose[2] = {0.0f, 0.0f}, motion[2] = {0.0f, 0.0f};
    if (first.moving) {
        /* the swept light (moving_lights.h): centre the poses' mean, half extents those of the
         * union of its poses around it, and along each axis the ramp of its samples' density,
         * the trapezoid of the pose's extent convolved with the motion's (docs/algorithms.md
         * 10, "The swept light's density") */
        float axes[2][3] = {{u.x, u.y, u.z}, {v.x, v.y, v.z}};
        ReconLightSweep sw;
        if (!recon_light_sweep(r, best, 0.0f, axes[0], axes[1], &sw) || !sw.ends_ok[0] || !sw.ends_ok[1]) {
            diag_set(d, WEDGE_EXIT_USAGE, (SrcLoc){0}, "--filter fsf: the moving area light's poses cannot be read");
            return false;
        }
        c = v3((float)sw.centre[0], (float)sw.centre[1], (float)sw.centre[2]);
        for (int a = 0; a < 2; ++a) {
            half[a] = fmaxf(-sw.lo[a], sw.hi[a]);
            ramp[a] = swept_ramp(&sw, axes[a], a, &pose[a], &motion[a]);
            if (!(ramp[a] > FSF_RAMP_MIN_REL * half[a])) ramp[a] = 0.0f; /* a motion too small to tell: the box */
        }
    } else {
        for (int m = 0; m < count; ++m) {
            RenderLightInfo b;
            if (!renderer_light_info_at(r, m, -1.0f, &b) || b.kind != RENDER_LIGHT_AREA || !b.is_triangle ||
                b.shape != first.shape)
                continue;
            for (int k = 0; k < 3; ++k) {
                vec3 q = v3_sub(b.tri_world[k], c);
                half[0] = fmaxf(half[0], fabsf(v3_dot(q, u)));
                half[1] = fmaxf(half[1], fabsf(v3_dot(q, v)));
            }
        }
    }
    if (!(half[0] > 0.0f && half[1] > 0.0f && isfinite(half[0]) && isfinite(half[1]))) {
        diag_set(d, WEDGE_EXIT_USAGE, (SrcLoc){0}, "--filter fsf: the area light has no extent");
        return false;
    }
    out->centre_world = c;
    out->normal_world = n;
    out->axis_world[0] = u;
    out->axis_world[1] = v;
    out->half_m[0] = half[0];
    out->half_m[1] = half[1];
    for (int a = 0; a < 2; ++a) out->ramp_m[a] = ramp[a], out->pose_m[a] = pose[a], out->motion_m[a] = motion[a];
    out->shape = first.shape;
    /* a moving light's samples are uniform over each pose (the swept density is built on that):
     * its fill is the pose's at shutter open, over the pose's own rectangle */
    float rect = first.moving ? pose[0] * pose[1] : 4.0f * half[0] * half[1];
    out->fill = rect > 0.0f ? area / rect : 1.0f;
    return true;
}

typedef struct {
    const Renderer *r;
    int shape; /* the share's emitter shape (>= 0) */
    const unsigned char *hit;
    const float *pos4, *nrm4;
    float *irradiance, *share; /* either may be NULL */
    const FsfShadeInputs *before; /* NULL: every pixel */
    int count;                    /* the renderer's lights */
    const RenderLightInfo *info;  /* theirs (info_ok[l]: renderer_light_info's result), or NULL: asked per pixel */
    const bool *info_ok;
    const SharedTriangles *tris;  /* the triangle lights, light l being triangle tri_of[l] (NULL: one at a time) */
    const int *tri_of;
    /* planar mesh emitters summed through their boundary (emitter_boundary.h): light l belongs
     * to group group_of[l] (-1: none), whose lights are first[g], next[first[g]], ... (-1 ends) */
    const int *group_of, *group_first, *group_next;
    EmitterBoundary *const *groups;
    /* curved mesh emitters summed through their facing parts (emitter_facing.h): group g's when
     * facing[g] is set (groups[g] NULL) */
    EmitterFacing *const *facing;
    int *const *facing_member; /* group g's lights in the order its EmitterFacing has its triangles */
    int group_count;
    /* the lights a pixel visits: each group's first and every light in none, in light order
     * (NULL: all); a mesh of 40,000 triangles otherwise costs each pixel 40,000 skips */
    const int *lead;
    int lead_count;
} ShadeJob;

/* Light l's info, from the job's table when it has one: renderer_light_info per pixel and light
 * took a fifth of the plan's share stage (a matrix and a cross product each time). */
static bool light_at(const ShadeJob *j, int l, RenderLightInfo *b)
{
    if (!j->info) return renderer_light_info(j->r, l, b);
    *b = j->info[l];
    return j->info_ok[l];
}

/* the pixel's inputs to shade_range are bit-equal to before's */
static bool same_inputs(const ShadeJob *j, size_t i)
{
    const FsfShadeInputs *b = j->before;
    return b->hit[i] == j->hit[i] && memcmp(b->pos4 + 4 * i, j->pos4 + 4 * i, 3 * sizeof(float)) == 0 &&
           memcmp(b->nrm4 + 4 * i, j->nrm4 + 4 * i, 3 * sizeof(float)) == 0;
}

/* Projected solid angle of a sphere or disk emitter seen from p (normal nr), as a small
 * source: the sphere's cap pi sin^2(a) cos(t) while it is above the horizon (0 below: the cap
 * that straddles it is rare and only moves a threshold), a disk as area cos cos / D^2. */
static double round_phi(const RenderLightInfo *b, vec3 p, vec3 nr)
{
    vec3 to = v3_sub(b->center_world, p);
    double D2 = v3_length2(to), D = sqrt(D2);
    if (!(D > 0.0)) return 0.0;
    double cos_t = v3_dot(nr, to) / D;
    if (!(cos_t > 0.0)) return 0.0;
    if (v3_length2(b->normal_world) < 0.5f) { /* a sphere: no normal */
        double rad = sqrt(b->area_world / (4.0 * M_PI));
        double sin_a = D > rad ? rad / D : 1.0;
        return M_PI * sin_a * sin_a * cos_t;
    }
    double cos_e = -v3_dot(b->normal_world, to) / D;
    if (b->two_sided) cos_e = fabs(cos_e);
    return cos_e > 0.0 ? b->area_world * cos_e * cos_t / D2 : 0.0;
}

/* p is behind the one-sided emitter triangle b, or in its plane (polygon_plane_side) */
static bool culled(const RenderLightInfo *b, vec3 pv)
{
    double p[3] = {pv.x, pv.y, pv.z}, q[3] = {b->center_world.x, b->center_world.y, b->center_world.z};
    double nl[3] = {b->normal_world.x, b->normal_world.y, b->normal_world.z};
    double side = polygon_plane_side(p, q, nl);
    return side == 0.0 || (!b->two_sided && side < 0.0);
}

/* Triangle light l's luminance times its projected solid angle from p (normal nr). */
static double triangle_light_phi(const ShadeJob *j, SharedTrianglesAt *at, int l, const RenderLightInfo *b, vec3 pv,
                                 const double p[3], const double nr[3])
{
    if (culled(b, pv)) return 0.0;
    double v[3][3];
    for (int k = 0; k < 3; ++k) v[k][0] = b->tri_world[k].x, v[k][1] = b->tri_world[k].y, v[k][2] = b->tri_world[k].z;
    double tri_phi = at ? shared_triangles_phi(j->tris, at, j->tri_of[l]) : polygon_projected_solid_angle(p, nr, v, 3);
    return (double)v3_luminance(b->radiance) * tri_phi;
}

/* A curved group's triangle that emitter_facing_phi sums alone, by the per-triangle rule
 * (triangle_light_phi's, without the luminance the group's sum takes): t indexes the group's
 * lights as emitter_facing_create was given them. */
typedef struct {
    const ShadeJob *j;
    SharedTrianglesAt *at;
    const int *member; /* the group's lights, in the order its triangles were given */
    vec3 pv;
    const double *p, *nr;
} FacingAlone;

static double facing_alone(void *ctx, int t)
{
    const FacingAlone *c = ctx;
    RenderLightInfo b;
    int l = c->member[t];
    if (!light_at(c->j, l, &b) || culled(&b, c->pv)) return 0.0;
    if (c->at) return shared_triangles_phi(c->j->tris, c->at, c->j->tri_of[l]);
    double v[3][3];
    for (int k = 0; k < 3; ++k) v[k][0] = b.tri_world[k].x, v[k][1] = b.tri_world[k].y, v[k][2] = b.tri_world[k].z;
    return polygon_projected_solid_angle(c->p, c->nr, v, 3);
}

/* Both sums over the emitters at once: every triangle's projected solid angle (the cost: an
 * atan2 per edge) is computed once for the irradiance and the share, each summed in the
 * emitters' order as alone. */
static void shade_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const ShadeJob *j = ctx;
    int count = j->count;
    SharedTrianglesAt *at = j->tris ? shared_triangles_at_create(j->tris) : NULL;
    /* this range's receiver values for each curved group, made when a pixel first needs them */
    EmitterFacingAt **facing_at = j->facing ? calloc((size_t)j->group_count, sizeof *facing_at) : NULL;
    for (size_t i = begin; i < end; ++i) {
        if (j->before && same_inputs(j, i)) continue; /* both outputs hold this pixel's sums */
        if (j->irradiance) j->irradiance[i] = 0.0f;
        if (j->share) j->share[i] = 0.0f;
        if (!j->hit[i]) continue;
        double p[3] = {j->pos4[4 * i], j->pos4[4 * i + 1], j->pos4[4 * i + 2]};
        double nr[3] = {j->nrm4[4 * i], j->nrm4[4 * i + 1], j->nrm4[4 * i + 2]};
        vec3 pv = v3((float)p[0], (float)p[1], (float)p[2]), nv = v3((float)nr[0], (float)nr[1], (float)nr[2]);
        double irr = 0.0, sum = 0.0, own = 0.0;
        if (at) shared_triangles_receiver(at, p, nr);
        for (int m = 0; m < (j->lead ? j->lead_count : count); ++m) {
            int l = j->lead ? j->lead[m] : m;
            int g = j->group_of ? j->group_of[l] : -1;
            if (g >= 0 && l != j->group_first[g]) continue; /* summed with its group's first light */
            RenderLightInfo b;
            if (!light_at(j, l, &b) || b.kind != RENDER_LIGHT_AREA) continue;
            if (!b.is_triangle) { /* only the share counts what FSF cannot filter along */
                if (j->share) sum += (double)v3_luminance(b.radiance) * round_phi(&b, pv, nv);
                continue;
            }
            double phi, group_phi;
            EmitterFacingAt *fat = NULL;
            if (g >= 0 && facing_at && j->facing[g] && !facing_at[g]) facing_at[g] = emitter_facing_at_create(j->facing[g]);
            if (g >= 0 && facing_at && j->facing[g]) fat = facing_at[g];
            if (g < 0) {
                phi = triangle_light_phi(j, at, l, &b, pv, p, nr);
            } else if (fat) {
                FacingAlone alone = {j, at, j->facing_member[g], pv, p, nr};
                phi = (double)v3_luminance(b.radiance) * emitter_facing_phi(j->facing[g], fat, p, nr, facing_alone, &alone);
            } else if (!j->groups[g]) { /* a curved group, out of memory for its receiver values */
                phi = 0.0;
                for (int k = l; k >= 0; k = j->group_next[k]) {
                    RenderLightInfo bk;
                    if (light_at(j, k, &bk)) phi += triangle_light_phi(j, at, k, &bk, pv, p, nr);
                }
            } else if (culled(&b, pv)) {
                /* behind the plane of the one-sided mesh, or in it (where each triangle's projected
                 * solid angle is 0 too): its triangles differ from b's test by rounding alone */
                phi = 0.0;
            } else if (emitter_boundary_phi(j->groups[g], p, nr, &group_phi)) {
                phi = (double)v3_luminance(b.radiance) * group_phi; /* the group's lights share b's radiance */
            } else { /* the receiver on a boundary point: its triangles one by one */
                phi = 0.0;
                for (int k = l; k >= 0; k = j->group_next[k]) {
                    RenderLightInfo bk;
                    if (light_at(j, k, &bk)) phi += triangle_light_phi(j, at, k, &bk, pv, p, nr);
                }
            }
            irr += phi, sum += phi;
            if (b.shape == j->shape) own += phi;
        }
        if (j->irradiance) j->irradiance[i] = isfinite(irr) ? (float)irr : 0.0f;
        double frac = sum > 0.0 ? fmin(own / sum, 1.0) : 0.0;
        if (j->share) j->share[i] = isfinite(frac) ? (float)frac : 0.0f;
    }
    for (int g = 0; facing_at && g < j->group_count; ++g) emitter_facing_at_destroy(facing_at[g]);
    free(facing_at);
    shared_triangles_at_destroy(at);
}

/* The mesh emitters among the entries info[0..count): one group a shape and pose (node_of: the
 * entry's sweep node, -1 static) whose triangles share their radiance and sidedness, summed through
 * its boundary when it is a surface emitter_boundary_create accepts (planar), else, from
 * FACING_MIN_TRIANGLES triangles, through its facing parts (emitter_facing.h; fewer are as cheap one
 * by one). */
#define FACING_MIN_TRIANGLES 32
typedef struct {
    int count;
    EmitterBoundary **boundary;
    EmitterFacing **facing;
    int **member; /* a curved group's lights, in the order its triangles were given (else NULL) */
    int *group_of, *first, *next;
} BoundaryGroups;

typedef struct {
    int shape, node, entry;
    float radiance[3];
    bool two_sided;
} GroupKey;

static int cmp_group_key(const void *a, const void *b)
{
    const GroupKey *x = a, *y = b;
    if (x->shape != y->shape) return x->shape < y->shape ? -1 : 1;
    if (x->node != y->node) return x->node < y->node ? -1 : 1;
    int c = memcmp(x->radiance, y->radiance, sizeof x->radiance);
    if (c) return c;
    if (x->two_sided != y->two_sided) return x->two_sided ? 1 : -1;
    return x->entry - y->entry;
}

static bool same_group(const GroupKey *x, const GroupKey *y)
{
    return x->shape == y->shape && x->node == y->node && !memcmp(x->radiance, y->radiance, sizeof x->radiance) &&
           x->two_sided == y->two_sided;
}

static void boundary_groups_free(BoundaryGroups *bg)
{
    for (int g = 0; g < bg->count; ++g)
        emitter_boundary_destroy(bg->boundary[g]), emitter_facing_destroy(bg->facing[g]), free(bg->member[g]);
    free(bg->boundary), free(bg->facing), free(bg->member), free(bg->group_of), free(bg->first), free(bg->next);
    *bg = (BoundaryGroups){0};
}

/* False (bg empty) when there is none or out of memory: every triangle then sums alone. */
static bool boundary_groups_find(const RenderLightInfo *info, const bool *ok, const int *node_of, int count,
                                 BoundaryGroups *bg)
{
    *bg = (BoundaryGroups){0};
    size_t n = count > 0 ? (size_t)count : 1;
    GroupKey *key = malloc(n * sizeof *key);
    double(*tri)[3][3] = malloc(n * sizeof *tri);
    bg->group_of = malloc(n * sizeof *bg->group_of), bg->next = malloc(n * sizeof *bg->next);
    bg->first = malloc(n * sizeof *bg->first), bg->boundary = malloc(n * sizeof *bg->boundary);
    bg->facing = malloc(n * sizeof *bg->facing), bg->member = malloc(n * sizeof *bg->member);
    if (!key || !tri || !bg->group_of || !bg->next || !bg->first || !bg->boundary || !bg->facing || !bg->member) {
        free(key), free(tri);
        boundary_groups_free(bg);
        return false;
    }
    int keys = 0;
    for (int l = 0; l < count; ++l) {
        bg->group_of[l] = bg->next[l] = -1;
        const RenderLightInfo *b = &info[l];
        if (!ok[l] || b->kind != RENDER_LIGHT_AREA || !b->is_triangle || b->shape < 0) continue;
        key[keys] = (GroupKey){b->shape, node_of[l], l, {b->radiance.x, b->radiance.y, b->radiance.z}, b->two_sided};
        ++keys;
    }
    qsort(key, (size_t)keys, sizeof *key, cmp_group_key);
    for (int q = 0; q < keys;) {
        int r = q + 1;
        while (r < keys && same_group(&key[q], &key[r])) ++r;
        for (int m = q; m < r; ++m)
            for (int v = 0; v < 3; ++v) {
                const vec3 *w = &info[key[m].entry].tri_world[v];
                tri[m - q][v][0] = w->x, tri[m - q][v][1] = w->y, tri[m - q][v][2] = w->z;
            }
        EmitterBoundary *boundary = r - q >= 2 ? emitter_boundary_create(r - q, (const double(*)[3][3])tri) : NULL;
        EmitterFacing *facing = !boundary && r - q >= FACING_MIN_TRIANGLES
                                    ? emitter_facing_create(r - q, (const double(*)[3][3])tri, key[q].two_sided)
                                    : NULL;
        int *member = facing ? malloc((size_t)(r - q) * sizeof *member) : NULL;
        if (facing && !member) emitter_facing_destroy(facing), facing = NULL;
        for (int m = q; member && m < r; ++m) member[m - q] = key[m].entry;
        if (boundary || facing) { /* entries in increasing order: the first is the group's first in the sum */
            bg->boundary[bg->count] = boundary;
            bg->facing[bg->count] = facing;
            bg->member[bg->count] = member;
            bg->first[bg->count] = key[q].entry;
            for (int m = q; m < r; ++m) {
                bg->group_of[key[m].entry] = bg->count;
                bg->next[key[m].entry] = m + 1 < r ? key[m + 1].entry : -1;
            }
            ++bg->count;
        }
        q = r;
    }
    free(key), free(tri);
    if (bg->count == 0) boundary_groups_free(bg);
    return bg->count > 0;
}

/* shade_range over the n pixels, the lights' infos found once and the triangle lights'
 * shared vertices and edges (shared_triangles.h); per pixel and light, one triangle at a time,
 * if out of memory. */
static void shade_all(ShadeJob *j, int n)
{
    int lights = renderer_light_count(j->r), moving = 0;
    for (int l = 0; l < lights; ++l) {
        RenderLightInfo b;
        moving += renderer_light_info(j->r, l, &b) && b.moving;
    }
    /* a moving light enters as its poses at the sweep's nodes, each with its radiance times the
     * node's weight: the time mean of its projected solid angle (docs/algorithms.md 1.9) */
    j->count = lights + moving * (AAF_SWEEP_NODES - 1);
    size_t count = j->count > 0 ? (size_t)j->count : 1;
    RenderLightInfo *info = malloc(count * sizeof *info);
    bool *ok = malloc(count * sizeof *ok);
    int *tri_of = malloc(count * sizeof *tri_of), tris = 0, *node_of = malloc(count * sizeof *node_of);
    double(*tri)[3][3] = malloc(count * sizeof *tri);
    if (info && ok && node_of) {
        int at = 0;
        for (int l = 0; l < lights; ++l) {
            ok[at] = renderer_light_info(j->r, l, &info[at]);
            node_of[at] = -1;
            if (!ok[at] || !info[at].moving) {
                ++at;
                continue;
            }
            for (int k = 0; k < AAF_SWEEP_NODES; ++k, ++at) {
                double w, u = aaf_sweep_node(k, &w);
                node_of[at] = k;
                ok[at] = renderer_light_info_at(j->r, l, (float)u, &info[at]);
                info[at].radiance = v3_scale(info[at].radiance, (float)w);
            }
        }
        j->info = info, j->info_ok = ok;
    } else {
        j->count = lights;
    }
    for (int l = 0; j->info && tri_of && tri && l < j->count; ++l) {
        const RenderLightInfo *b = &info[l];
        tri_of[l] = ok[l] && b->kind == RENDER_LIGHT_AREA && b->is_triangle ? tris++ : -1;
        for (int k = 0; tri_of[l] >= 0 && k < 3; ++k)
            tri[tri_of[l]][k][0] = b->tri_world[k].x, tri[tri_of[l]][k][1] = b->tri_world[k].y,
            tri[tri_of[l]][k][2] = b->tri_world[k].z;
    }
    SharedTriangles *shared = j->info && tri_of && tri ? shared_triangles_create(tris, (const double(*)[3][3])tri) : NULL;
    if (shared) j->tris = shared, j->tri_of = tri_of;
    BoundaryGroups bg = {0};
    if (j->info && boundary_groups_find(info, ok, node_of, j->count, &bg))
        j->group_of = bg.group_of, j->group_first = bg.first, j->group_next = bg.next,
        j->groups = (EmitterBoundary *const *)bg.boundary, j->facing = (EmitterFacing *const *)bg.facing,
        j->facing_member = (int *const *)bg.member,
        j->group_count = bg.count;
    int *lead = j->group_of ? malloc((size_t)(j->count > 0 ? j->count : 1) * sizeof *lead) : NULL;
    for (int l = 0; lead && l < j->count; ++l)
        if (j->group_of[l] < 0 || l == j->group_first[j->group_of[l]]) lead[j->lead_count++] = l;
    j->lead = lead;
    recon_parallel_for((size_t)n, shade_range, j);
    free(lead);
    boundary_groups_free(&bg);
    shared_triangles_destroy(shared);
    free(info), free(ok), free(tri_of), free(tri), free(node_of);
}

void fsf_irradiance_and_share(const Renderer *r, int shape, int n, const unsigned char *hit, const float *pos4,
                              const float *nrm4, float *irradiance, float *share)
{
    ShadeJob j = {.r = r, .shape = shape < 0 ? 0 : shape, .hit = hit, .pos4 = pos4, .nrm4 = nrm4, .irradiance = irradiance, .share = share};
    shade_all(&j, n);
}

bool fsf_shade_inputs_keep(FsfShadeInputs *k, int n, const unsigned char *hit, const float *pos4, const float *nrm4)
{
    size_t bytes = (size_t)n * 4 * sizeof(float);
    k->hit = malloc((size_t)n), k->pos4 = malloc(bytes), k->nrm4 = malloc(bytes);
    if (!k->hit || !k->pos4 || !k->nrm4) {
        fsf_shade_inputs_free(k);
        return false;
    }
    memcpy(k->hit, hit, (size_t)n), memcpy(k->pos4, pos4, bytes), memcpy(k->nrm4, nrm4, bytes);
    return true;
}

void fsf_shade_inputs_free(FsfShadeInputs *k)
{
    free(k->hit), free(k->pos4), free(k->nrm4);
    *k = (FsfShadeInputs){0};
}

void fsf_irradiance_and_share_since(const Renderer *r, int shape, int n, const unsigned char *hit, const float *pos4,
                                    const float *nrm4, const FsfShadeInputs *before, float *irradiance, float *share)
{
    ShadeJob j = {.r = r, .shape = shape < 0 ? 0 : shape, .hit = hit, .pos4 = pos4, .nrm4 = nrm4, .irradiance = irradiance, .share = share,
                  .before = before};
    shade_all(&j, n);
}

void fsf_light_share(const Renderer *r, int shape, int n, const unsigned char *hit, const float *pos4,
                     const float *nrm4, float *share)
{
    fsf_irradiance_and_share(r, shape, n, hit, pos4, nrm4, NULL, share);
}
