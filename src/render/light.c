/* Light sources and their sampling (pbrt-v4 semantics; see light.h). */
#include "render/light_choose.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/vectorise.h"
#include "render/sincos_run.h"
#include "render/warp.h"

static const float LIGHT_OFFSET_REL = 1e-5f; /* as tracer.c: scales with the coordinates */

static float luminance(vec3 c)
{
    float y = v3_luminance(c);
    return y > 0.0f ? y : fmaxf(0.0f, v3_max_component(c));
}

/* Point, spot and distant lights: a single direction from each receiver. */
static bool light_is_delta(const Light *l) { return l->kind != LIGHT_AREA && l->kind != LIGHT_INFINITE; }

static vec3 param_point(const ParamSet *ps, const char *name, vec3 def)
{
    int n = 0;
    const float *f = params_floats(ps, name, &n);
    return (f && n >= 3) ? v3(f[0], f[1], f[2]) : def;
}


/* Largest emission taken without a warning: sums of a few thousand samples of it, times BSDF
 * and geometry factors, stay finite in float (FLT_MAX is 3.4e38). */
#define EMISSION_WARN_MAX 1e30f

/* emission * scale, with a warning (shown by render and info) for what would otherwise be
 * dropped, dimmed or overflow silently: negative values (clamped to 0), a negative or
 * non-finite scale (the light emits nothing), and radiance so large that sums overflow. */
static vec3 checked_emission(SceneDesc *scene, SrcLoc loc, const ParamSet *ps, const char *name, float scale)
{
    float rgb[3] = {1.0f, 1.0f, 1.0f};
    if (params_illuminant_rgb(ps, name, rgb) && (rgb[0] < 0.0f || rgb[1] < 0.0f || rgb[2] < 0.0f))
        scene_warn(scene, loc, "negative \"%s\" (%g %g %g) is clamped to 0: a light cannot remove light", name,
                   (double)rgb[0], (double)rgb[1], (double)rgb[2]);
    vec3 e = v3(fmaxf(rgb[0], 0.0f), fmaxf(rgb[1], 0.0f), fmaxf(rgb[2], 0.0f));
    if (!(scale >= 0.0f) || !isfinite(scale)) {
        scene_warn(scene, loc, "light \"scale\" %g is negative or not finite: the light emits nothing", (double)scale);
        return v3s(0.0f);
    }
    vec3 out = v3_scale(e, scale);
    float peak = fmaxf(out.x, fmaxf(out.y, out.z));
    if (!(peak <= EMISSION_WARN_MAX))
        scene_warn(scene, loc,
                   "\"%s\" times \"scale\" reaches %g, beyond what float sums of it hold: pixels that see this light "
                   "will come out infinite (set to 0 and counted in the report's nonfinite_pixels)",
                   name, (double)peak);
    return out;
}

static Light *push_light(LightSet *set, int *cap)
{
    if (set->count == *cap) {
        int c = *cap ? 2 * *cap : 16;
        Light *l = realloc(set->lights, (size_t)c * sizeof *l);
        if (!l) return NULL;
        set->lights = l, *cap = c;
    }
    Light *l = &set->lights[set->count++];
    memset(l, 0, sizeof *l);
    l->instance = -1, l->layer = l->geom = l->prim = -1;
    return l;
}

/* Position of a geometry-space point / normal of an emitter in world space at a time. */
typedef struct {
    bool instanced;
    Mat4 w, w_inv;
} EmitterXform;

static EmitterXform emitter_xform(const Tracer *tr, int instance, float time01)
{
    EmitterXform x;
    x.instanced = false; /* w and w_inv are only read when instanced */
    if (instance < 0) return x;
    x.instanced = true;
    x.w = tracer_world_from_instance(tr, instance, time01);
    if (!mat4_inverse(&x.w, &x.w_inv)) x.w_inv = mat4_identity();
    return x;
}

static vec3 ex_point(const EmitterXform *x, vec3 p) { return x->instanced ? mat4_apply_point(&x->w, p) : p; }
static vec3 ex_normal(const EmitterXform *x, vec3 n)
{
    return x->instanced ? v3_normalize(mat4_apply_normal(&x->w_inv, n)) : n;
}

/* World-space triangle of an emitter with its oriented unit normal (as tracer.c's hits). */
static void emitter_triangle(const Geom *g, int prim, const EmitterXform *x, vec3 P[3], vec3 *n_unit, float *area)
{
    const uint32_t *ix = g->index + 3 * (size_t)prim;
    const vec3 *V = (const vec3 *)g->p;
    vec3 pg[3] = {V[ix[0]], V[ix[1]], V[ix[2]]};
    vec3 n = v3_normalize(v3_cross(v3_sub(pg[1], pg[0]), v3_sub(pg[2], pg[0])));
    if (g->n) {
        vec3 s = v3_add(v3_add(g->n[ix[0]], g->n[ix[1]]), g->n[ix[2]]);
        if (v3_dot(n, s) < 0.0f) n = v3_neg(n);
    } else if (g->flip_normal) {
        n = v3_neg(n);
    }
    for (int i = 0; i < 3; ++i) P[i] = ex_point(x, pg[i]);
    *n_unit = ex_normal(x, n);
    *area = 0.5f * v3_length(v3_cross(v3_sub(P[1], P[0]), v3_sub(P[2], P[0])));
}

/* World placement of a disk or sphere: M = world_from_object. */
static Mat4 emitter_world_from_object(const Geom *g, const EmitterXform *x)
{
    return x->instanced ? mat4_mul(&x->w, &g->geom_from_object) : g->geom_from_object;
}

static float disk_area(const Geom *g, const Mat4 *m, vec3 *n_unit)
{
    vec3 ex = mat4_apply_vector(m, v3(1, 0, 0)), ey = mat4_apply_vector(m, v3(0, 1, 0));
    vec3 c = v3_cross(ex, ey);
    float stretch = v3_length(c);
    /* cross(M ex, M ey) = det(M) M^-T ez: undo the determinant's sign to get the normal */
    vec3 n = v3_normalize(c);
    if (mat4_swaps_handedness(m)) n = v3_neg(n);
    if (g->flip_normal) n = v3_neg(n);
    *n_unit = n;
    double a_obj = 0.5 * g->phimax_rad * (g->radius * g->radius - g->inner_radius * g->inner_radius);
    return (float)(a_obj * stretch);
}

/* A whole sphere, not cut by zmin, zmax or phimax. */
static bool sphere_is_full(const Geom *g)
{
    return !(g->zmin > -g->radius || g->zmax < g->radius || g->phimax_rad < 2.0 * M_PI);
}

/* Sphere centre and radius in world space (uniform scale assumed; see docs/rendering.md). */
static void sphere_world(const Geom *g, const Mat4 *m, vec3 *c, float *r)
{
    *c = mat4_apply_point(m, v3(0, 0, 0));
    double det = m->m[0][0] * (m->m[1][1] * m->m[2][2] - m->m[1][2] * m->m[2][1]) -
                 m->m[0][1] * (m->m[1][0] * m->m[2][2] - m->m[1][2] * m->m[2][0]) +
                 m->m[0][2] * (m->m[1][0] * m->m[2][1] - m->m[1][1] * m->m[2][0]);
    *r = (float)(g->radius * cbrt(fabs(det)));
}

bool lights_build(LightSet *set, SceneDesc *scene, Tracer *tr, Diag *err)
{
    *set = (LightSet){0};
    set->area_sampling_complete = true;
    set->sky_cosine_light = -1;
    set->sole_light = -1;
    int cap = 0;
    vec3 bmin = v3(tr->bounds_min[0], tr->bounds_min[1], tr->bounds_min[2]);
    vec3 bmax = v3(tr->bounds_max[0], tr->bounds_max[1], tr->bounds_max[2]);
    set->scene_center = v3_scale(v3_add(bmin, bmax), 0.5f);
    set->scene_radius = 0.5f * v3_length(v3_sub(bmax, bmin));
    if (!(set->scene_radius > 0.0f) || !isfinite(set->scene_radius)) set->scene_radius = 1.0f;

    /* Area lights: every emitting geometry of layer 0 and of moving-shape layers. */
    for (int li = 0; li < tr->layer_count; ++li) {
        Layer *layer = &tr->layers[li];
        for (int gi = 0; gi < layer->geom_count; ++gi) {
            Geom *g = &layer->geoms[gi];
            if (g->area_light < 0 || g->kind == GEOM_INSTANCE) continue;
            AreaLightDesc *ad = &scene->area_lights[g->area_light];
            vec3 L = checked_emission(scene, ad->loc, &ad->params, "L", params_float(&ad->params, "scale", 1.0f));
            bool two_sided = params_bool(&ad->params, "twosided", false);
            int n_prims = g->kind == GEOM_TRIANGLES ? g->triangle_count : 1;
            if (n_prims == 0) continue;
            g->light_first = set->count;
            EmitterXform x = emitter_xform(tr, g->owner_instance, 0.0f);
            for (int p = 0; p < n_prims; ++p) {
                Light *l = push_light(set, &cap);
                if (!l) goto oom;
                l->kind = LIGHT_AREA;
                l->L = L;
                l->two_sided = two_sided;
                l->layer = li, l->geom = gi, l->prim = p;
                l->instance = g->owner_instance;
                l->shadow_skip_mask = g->mask_bit;
                if (g->kind == GEOM_TRIANGLES) {
                    vec3 P[3], n;
                    emitter_triangle(g, p, &x, P, &n, &l->area_world);
                    /* static triangles: cache the world-space geometry for sampling */
                    l->tri_p0 = P[0], l->tri_e1 = v3_sub(P[1], P[0]), l->tri_e2 = v3_sub(P[2], P[0]);
                    l->tri_n = n;
                    l->tri_err = LIGHT_OFFSET_REL * fmax_nonneg(v3_max_abs(P[0]), fmax_nonneg(v3_max_abs(P[1]), v3_max_abs(P[2])));
                } else if (g->kind == GEOM_DISK) {
                    Mat4 m = emitter_world_from_object(g, &x);
                    vec3 n;
                    l->area_world = disk_area(g, &m, &n);
                } else {
                    Mat4 m = emitter_world_from_object(g, &x);
                    sphere_world(g, &m, &l->sphere_c, &l->sphere_r);
                    l->area_world = 4.0f * WEDGE_PI * l->sphere_r * l->sphere_r;
                    /* cone sampling reaches the cap facing the receiver alone: a cut sphere
                     * that emits inwards or both ways shows its far cap's inside too */
                    if (!sphere_is_full(g) && (two_sided || g->flip_normal)) set->area_sampling_complete = false;
                }
                set->has_area = true;
            }
        }
    }
    bool warned_unsupported = false;
    for (int i = 0; i < scene->light_count; ++i) {
        LightDesc *d = &scene->lights[i];
        const Mat4 *m = &d->world_from_light.m[0];
        float scale = params_float(&d->params, "scale", 1.0f);
        const char *type = d->type ? d->type : "";
        Light *l = NULL;
        if (!strcmp(type, "point")) {
            if (!(l = push_light(set, &cap))) goto oom;
            l->kind = LIGHT_POINT;
            l->L = checked_emission(scene, d->loc, &d->params, "I", scale);
            l->p_world = mat4_apply_point(m, param_point(&d->params, "from", v3(0, 0, 0)));
        } else if (!strcmp(type, "spot")) {
            if (!(l = push_light(set, &cap))) goto oom;
            l->kind = LIGHT_SPOT;
            l->L = checked_emission(scene, d->loc, &d->params, "I", scale);
            vec3 from = param_point(&d->params, "from", v3(0, 0, 0)), to = param_point(&d->params, "to", v3(0, 0, 1));
            l->p_world = mat4_apply_point(m, from);
            l->w_world = v3_normalize(mat4_apply_vector(m, v3_sub(to, from)));
            float cone = params_float(&d->params, "coneangle", 30.0f), delta = params_float(&d->params, "conedeltaangle", 5.0f);
            l->cos_falloff_end = cosf(cone * WEDGE_PI / 180.0f);
            l->cos_falloff_start = cosf((cone - delta) * WEDGE_PI / 180.0f);
        } else if (!strcmp(type, "distant")) {
            if (!(l = push_light(set, &cap))) goto oom;
            l->kind = LIGHT_DISTANT;
            l->L = checked_emission(scene, d->loc, &d->params, "L", scale);
            vec3 from = param_point(&d->params, "from", v3(0, 0, 0)), to = param_point(&d->params, "to", v3(0, 0, 1));
            l->w_world = v3_normalize(mat4_apply_vector(m, v3_sub(from, to)));
        } else if (!strcmp(type, "infinite")) {
            if (!(l = push_light(set, &cap))) goto oom;
            l->kind = LIGHT_INFINITE;
            const char *file = params_string(&d->params, "filename", NULL);
            if (file && *file) {
                char path[4096];
                if (file[0] == '/' || !d->base_dir || !*d->base_dir)
                    snprintf(path, sizeof path, "%s", file);
                else
                    snprintf(path, sizeof path, "%s/%s", d->base_dir, file);
                l->env = calloc(1, sizeof *l->env);
                if (!l->env) goto oom;
                if (!envmap_load(l->env, path, scale, err)) {
                    /* report at the light's statement (the message names the file) */
                    if (err->exit_code != WEDGE_EXIT_RUNTIME) {
                        char inner[sizeof err->message];
                        const char *what = strstr(err->message, "error: ");
                        snprintf(inner, sizeof inner, "%s", what ? what + 7 : err->message);
                        size_t len = strlen(inner);
                        while (len && inner[len - 1] == '\n') inner[--len] = '\0';
                        if (strstr(inner, path))
                            diag_set(err, WEDGE_EXIT_INPUT, d->loc, "%s", inner);
                        else
                            diag_set(err, WEDGE_EXIT_INPUT, d->loc, "environment map '%s': %s", path, inner);
                    }
                    lights_free(set);
                    return false;
                }
                envmap_set_transform(l->env, m);
                l->L = envmap_mean_radiance(l->env);
            } else {
                l->L = checked_emission(scene, d->loc, &d->params, "L", scale);
            }
        } else {
            if (!warned_unsupported) scene_warn(scene, d->loc, "light type '%s' is not supported; it is skipped", type);
            warned_unsupported = true;
        }
    }

    set->cdf = malloc((size_t)(set->count + 1) * sizeof(float));
    set->infinite = malloc((size_t)(set->count > 0 ? set->count : 1) * sizeof(int));
    if (!set->cdf || !set->infinite) goto oom;
    double acc = 0.0, r2 = (double)set->scene_radius * set->scene_radius;
    double *phi = malloc((size_t)(set->count > 0 ? set->count : 1) * sizeof *phi);
    if (!phi) goto oom;
    int delta_count = 0;
    for (int i = 0; i < set->count; ++i) {
        const Light *l = &set->lights[i];
        double y = luminance(l->L);
        phi[i] = 0.0;
        switch (l->kind) {
        case LIGHT_AREA: phi[i] = y * l->area_world * M_PI * (l->two_sided ? 2.0 : 1.0); break;
        case LIGHT_POINT: phi[i] = 4.0 * M_PI * y; break;
        case LIGHT_SPOT: phi[i] = 2.0 * M_PI * y * (1.0 - 0.5 * (l->cos_falloff_start + l->cos_falloff_end)); break;
        case LIGHT_DISTANT: phi[i] = M_PI * r2 * y; break;
        case LIGHT_INFINITE: phi[i] = 4.0 * M_PI * M_PI * r2 * y; break;
        }
        if (!(phi[i] > 0.0) || !isfinite(phi[i])) phi[i] = 0.0;
        if (light_is_delta(l) && phi[i] > 0.0) ++delta_count;
    }
    set->has_delta = delta_count > 0;
    bool every = delta_count <= LIGHTS_DELTA_EVERY_MAX;
    set->cdf[0] = 0.0f;
    for (int i = 0; i < set->count; ++i) {
        const Light *l = &set->lights[i];
        if (l->kind == LIGHT_INFINITE) set->infinite[set->infinite_count++] = i;
        if (every && light_is_delta(l) && phi[i] > 0.0) {
            set->delta_every[set->delta_every_count++] = i;
            phi[i] = 0.0;
        }
        acc += phi[i];
        set->cdf[i + 1] = (float)acc;
    }
    int pickable = 0, sole = -1;
    for (int i = 0; i < set->count; ++i)
        if (set->cdf[i + 1] > set->cdf[i]) ++pickable, sole = i;
    if (pickable == 1 && set->infinite_count == 1 && light_is_constant_sky(&set->lights[sole]))
        set->sky_cosine_light = sole;
    free(phi);
    set->power_total = (float)acc;
    lights_bound_emitters(set, tr);
    set->choice = malloc((size_t)(set->count > 0 ? set->count : 1) * sizeof *set->choice);
    if (!set->choice) goto oom;
    for (int i = 0; i < set->count; ++i) {
        LightChoice *c = &set->choice[i];
        c->pmf = lights_pmf(set, i);
        if (!lights_mesh_run(set, tr, i, &c->mesh_first, &c->mesh_end)) c->mesh_first = c->mesh_end = 0;
        c->static_triangle = light_is_static_triangle(set, tr, i);
        const Light *a = &set->lights[i], *b = &set->lights[c->mesh_first];
        c->batches_with_run = c->static_triangle && c->mesh_end > c->mesh_first && a->L.x == b->L.x &&
                              a->L.y == b->L.y && a->L.z == b->L.z && a->shadow_skip_mask == b->shadow_skip_mask &&
                              a->two_sided == b->two_sided;
    }
    lights_find_sole_mesh(set);
    return true;
oom:
    diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory building lights");
    lights_free(set);
    return false;
}

void lights_free(LightSet *set)
{
    for (int i = 0; set->lights && i < set->count; ++i) {
        if (set->lights[i].env) {
            envmap_free(set->lights[i].env);
            free(set->lights[i].env);
        }
    }
    free(set->lights);
    free(set->cdf);
    free(set->infinite);
    free(set->choice);
    *set = (LightSet){0};
}

/* The light every pick target in [0, power_total) lands on, if there is one: the first i
 * with cdf[i + 1] > target is the same s for every such target when cdf[i] <= 0 for every
 * i <= s and cdf[i] >= power_total for every i > s (the search's predicate, cdf[i + 1] >
 * target, is then false below s and true from s on), and lights_cdf_cell's skip of empty
 * lights stops at s, whose width cdf[s + 1] - cdf[s] is > 0. */
static void lights_find_sole_light(LightSet *set)
{
    set->sole_light = -1;
    if (!(set->power_total > 0.0f) || set->count <= 0) return;
    int s = 0;
    while (s < set->count && set->cdf[s + 1] <= 0.0f) ++s;
    if (s == set->count) return;
    for (int i = 0; i <= s; ++i)
        if (!(set->cdf[i] <= 0.0f)) return;
    for (int i = s + 1; i <= set->count; ++i)
        if (!(set->cdf[i] >= set->power_total)) return;
    set->sole_light = s;
}

void lights_find_sole_mesh(LightSet *set)
{
    lights_find_sole_light(set);
    set->sole_mesh_first = set->sole_mesh_end = 0;
    int first = 0, end = 0;
    for (int i = 0; i < set->count; ++i) {
        if (!(set->cdf[i + 1] > set->cdf[i])) continue; /* no power: never picked */
        const LightChoice *c = &set->choice[i];
        if (!(c->pmf > 0.0f) || c->mesh_end <= 0) return;
        if (end == 0) first = c->mesh_first, end = c->mesh_end;
        if (c->mesh_first != first || c->mesh_end != end) return;
    }
    for (int i = first; i < end; ++i)
        if (!(set->cdf[i + 1] > set->cdf[i]) || !(set->choice[i].pmf > 0.0f)) return;
    set->sole_mesh_first = first, set->sole_mesh_end = end;
}

int lights_pick(const LightSet *set, float u, float *pmf)
{
    if (!(set->power_total > 0.0f)) return -1;
    int lo = lights_cdf_cell(set, u * set->power_total);
    *pmf = (set->cdf[lo + 1] - set->cdf[lo]) / set->power_total;
    return *pmf > 0.0f ? lo : -1;
}

float lights_pmf(const LightSet *set, int light)
{
    if (light < 0 || light >= set->count || !(set->power_total > 0.0f)) return 0.0f;
    return (set->cdf[light + 1] - set->cdf[light]) / set->power_total;
}

/* Finishes an area sample: direction, distance and the solid-angle pdf from an area pdf. */
static bool finish_area_sample(const Light *l, vec3 p_ref, vec3 p, vec3 n, float pdf_area, float err_light,
                               LightSample *ls)
{
    vec3 d = v3_sub(p, p_ref);
    float dist2 = v3_length2(d);
    if (!(dist2 > 0.0f) || !(pdf_area > 0.0f)) return false;
    float dist = sqrtf(dist2);
    vec3 wi = v3_scale(d, 1.0f / dist);
    float cos_l = -v3_dot(n, wi);
    if (!l->two_sided && cos_l <= 0.0f) return false;
    if (fabsf(cos_l) < 1e-7f) return false;
    ls->wi = wi;
    ls->dist = dist;
    ls->p_light = p;
    ls->n_light = n;
    ls->err_light = err_light;
    ls->Li = l->L;
    ls->pdf = pdf_area * dist2 / fabsf(cos_l);
    ls->delta = false;
    return isfinite(ls->pdf);
}

/* Cone sampling of a sphere seen from outside (pbrt-v4 Sphere::Sample with a reference point). */
static bool sample_sphere(const Light *l, const Geom *g, const Mat4 *m, vec3 c, float r, vec3 p_ref, vec2 u,
                          LightSample *ls)
{
    float err = LIGHT_OFFSET_REL * (v3_max_abs(c) + r);
    vec3 to_c = v3_sub(c, p_ref);
    float dc2 = v3_length2(to_c);
    if (dc2 <= r * r * 1.0001f) {
        /* inside (or on) the sphere: uniform area sampling */
        vec3 nn = warp_uniform_sphere(u);
        vec3 p = v3_madd(c, nn, r);
        if (g->flip_normal) nn = v3_neg(nn);
        return finish_area_sample(l, p_ref, p, nn, 1.0f / (4.0f * WEDGE_PI * r * r), err, ls);
    }
    float dc = sqrtf(dc2);
    float sin_max = r / dc, sin2_max = sin_max * sin_max;
    float cos_max = sqrtf(fmaxf(0.0f, 1.0f - sin2_max));
    float one_minus_cos_max = 1.0f - cos_max;
    float cos_t = (cos_max - 1.0f) * u.x + 1.0f;
    float sin2_t = 1.0f - cos_t * cos_t;
    if (sin2_max < 0.00068523f) { /* small cone: Taylor expansion keeps precision */
        sin2_t = sin2_max * u.x;
        cos_t = sqrtf(1.0f - sin2_t);
        one_minus_cos_max = sin2_max / 2.0f;
    }
    /* angle alpha from the centre to the sampled point, as seen from the centre */
    float cos_a = sin2_t / sin_max + cos_t * sqrtf(fmaxf(0.0f, 1.0f - sin2_t / sin2_max));
    float sin_a = sqrtf(fmaxf(0.0f, 1.0f - cos_a * cos_a));
    float phi = 2.0f * WEDGE_PI * u.y;
    vec3 wc = v3_scale(to_c, 1.0f / dc), t1, t2;
    v3_basis(wc, &t1, &t2);
    /* outward normal at the point: -(sin_a cos phi t1 + sin_a sin phi t2 + cos_a wc) */
    vec3 nn = v3_neg(v3_add(v3_add(v3_scale(t1, sin_a * cosf(phi)), v3_scale(t2, sin_a * sinf(phi))), v3_scale(wc, cos_a)));
    vec3 p = v3_madd(c, nn, r);
    if (!sphere_is_full(g)) {
        /* partial sphere: points of the full cap that are not on the surface carry no light */
        Mat4 inv;
        if (mat4_inverse(m, &inv)) {
            vec3 po = mat4_apply_point(&inv, p);
            double phi = atan2(po.y, po.x);
            if (phi < 0.0) phi += 2.0 * M_PI;
            if (po.z < g->zmin || po.z > g->zmax || phi > g->phimax_rad) return false;
        }
    }
    vec3 n_emit = g->flip_normal ? v3_neg(nn) : nn;
    vec3 d = v3_sub(p, p_ref);
    float dist = v3_length(d);
    if (!(dist > 0.0f)) return false;
    vec3 wi = v3_scale(d, 1.0f / dist);
    if (!l->two_sided && v3_dot(n_emit, wi) >= 0.0f) return false;
    ls->wi = wi;
    ls->dist = dist;
    ls->p_light = p;
    ls->n_light = n_emit;
    ls->err_light = err;
    ls->Li = l->L;
    ls->pdf = 1.0f / (2.0f * WEDGE_PI * one_minus_cos_max);
    ls->delta = false;
    return isfinite(ls->pdf) && ls->pdf > 0.0f;
}

float light_delta_offset(const Light *l) { return LIGHT_OFFSET_REL * v3_max_abs(l->p_world); }

/* pbrt-v4's SmoothStep falloff of a spot light at cos_t (light_sample's case LIGHT_SPOT),
 * as selects rather than branches, for the vectorised loop below: the same value in every
 * case (t is computed in all of them and used only where the branchy form computes it).
 * The selects are bitwise on the values' bits: with ?: GCC moved the division and the
 * polynomial into the branch that uses them (it may not run a division the source would
 * skip, which could raise a floating-point exception) and then could not vectorise the
 * loop ("control flow in loop"); in this form every lane computes s, as the source says. */
static inline uint32_t float_bits(float x)
{
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

static inline float bits_float(uint32_t b)
{
    float x;
    memcpy(&x, &b, sizeof x);
    return x;
}

static inline float spot_falloff(float cos_t, float lo, float hi)
{
    float t = (cos_t - lo) / (hi - lo);
    float s = t * t * (3.0f - 2.0f * t);
    uint32_t full = -(uint32_t)((cos_t >= hi) | (hi <= lo)); /* all ones where the value is 1 */
    uint32_t dark = -(uint32_t)(cos_t <= lo);                 /* all ones where it is 0 */
    uint32_t b = (float_bits(s) & ~full) | (float_bits(1.0f) & full);
    return bits_float(b & ~dark);
}

/* light_sample_point_batch's loop; `spot` is a constant where it is inlined. */
static inline void point_light_loop(const Light *l, bool spot, int count, const float *restrict px,
                                    const float *restrict py, const float *restrict pz, float *restrict wx,
                                    float *restrict wy, float *restrict wz, float *restrict dist_out,
                                    float *restrict lr, float *restrict lg, float *restrict lb, int *restrict ok)
{
    float cx = l->p_world.x, cy = l->p_world.y, cz = l->p_world.z, ix = l->L.x, iy = l->L.y, iz = l->L.z;
    float ax = l->w_world.x, ay = l->w_world.y, az = l->w_world.z, lo = l->cos_falloff_end, hi = l->cos_falloff_start;
    for (int k = 0; k < count; ++k) {
        float dx = cx - px[k], dy = cy - py[k], dz = cz - pz[k];
        float dist2 = dx * dx + dy * dy + dz * dz;
        float dist = sqrtf(dist2), inv = 1.0f / dist;
        float x = dx * inv, y = dy * inv, z = dz * inv;
        float sx = ix, sy = iy, sz = iz;
        if (spot) {
            float s = spot_falloff(-(x * ax + y * ay + z * az), lo, hi);
            sx = ix * s, sy = iy * s, sz = iz * s;
        }
        float inv2 = 1.0f / dist2;
        float r = sx * inv2, g = sy * inv2, b = sz * inv2;
        wx[k] = x, wy[k] = y, wz[k] = z, dist_out[k] = dist;
        lr[k] = r, lg[k] = g, lb[k] = b;
        ok[k] = (dist2 > 0.0f) & ((r > 0.0f) | (g > 0.0f) | (b > 0.0f));
    }
}

static WEDGE_VECTORISED void point_light_batch(const Light *l, int count, const float *const p[3],
                                               const LightSampleBatch *out)
{
    if (l->kind == LIGHT_SPOT)
        point_light_loop(l, true, count, p[0], p[1], p[2], out->wi[0], out->wi[1], out->wi[2], out->dist, out->Li[0],
                         out->Li[1], out->Li[2], out->ok);
    else
        point_light_loop(l, false, count, p[0], p[1], p[2], out->wi[0], out->wi[1], out->wi[2], out->dist, out->Li[0],
                         out->Li[1], out->Li[2], out->ok);
}

void light_sample_point_batch(const Light *l, int count, const float *const p[3], const LightSampleBatch *out)
{
    point_light_batch(l, count, p, out);
}

bool light_is_static_triangle(const LightSet *set, const Tracer *tr, int li)
{
    const Light *l = &set->lights[li];
    return l->kind == LIGHT_AREA && l->instance < 0 && tr->layers[l->layer].geoms[l->geom].kind == GEOM_TRIANGLES &&
           l->area_world > 0.0f;
}

/* light_sample's static-triangle case and finish_area_sample for one receiver (px, py, pz)
 * and position sample (u0, u1) on the triangle p0 + b1 e1 + b2 e2 (normal n, 1 / area
 * pdf_area): the same operations in the same order, per coordinate and returned by value,
 * so that the loops below vectorise. */
typedef struct {
    float wx, wy, wz, dist, lx, ly, lz, pdf;
    int ok;
} TriangleLane;

static inline __attribute__((always_inline)) TriangleLane triangle_light_lane(vec3 p0, vec3 e1, vec3 e2, vec3 n,
                                                                              float pdf_area, int two_sided, float px,
                                                                              float py, float pz, float u0, float u1)
{
    float su = sqrtf(u0);
    float b0 = 1.0f - su, b1 = u1 * su, b2 = 1.0f - b0 - b1; /* warp_triangle */
    float qx = p0.x + (e1.x * b1 + e2.x * b2), qy = p0.y + (e1.y * b1 + e2.y * b2), qz = p0.z + (e1.z * b1 + e2.z * b2);
    float dx = qx - px, dy = qy - py, dz = qz - pz;
    float dist2 = dx * dx + dy * dy + dz * dz;
    float dist = sqrtf(dist2), inv = 1.0f / dist;
    float x = dx * inv, y = dy * inv, z = dz * inv;
    float cos_l = -(n.x * x + n.y * y + n.z * z);
    float pdf = pdf_area * dist2 / fabsf(cos_l);
    int facing = two_sided | !(cos_l <= 0.0f);
    int ok = (dist2 > 0.0f) & (pdf_area > 0.0f) & facing & !(fabsf(cos_l) < 1e-7f) & (fabsf(pdf) < INFINITY);
    return (TriangleLane){x, y, z, dist, qx, qy, qz, pdf, ok};
}

static inline __attribute__((always_inline)) void triangle_lane_store(TriangleLane t, int k, float *restrict wx,
                                                                      float *restrict wy, float *restrict wz,
                                                                      float *restrict dist, float *restrict lx,
                                                                      float *restrict ly, float *restrict lz,
                                                                      float *restrict pdf, int *restrict ok)
{
    wx[k] = t.wx, wy[k] = t.wy, wz[k] = t.wz, dist[k] = t.dist;
    lx[k] = t.lx, ly[k] = t.ly, lz[k] = t.lz, pdf[k] = t.pdf, ok[k] = t.ok;
}

static inline void triangle_light_loop(const Light *l, int count, const float *restrict px, const float *restrict py,
                                       const float *restrict pz, const float *restrict u0, const float *restrict u1,
                                       float *restrict wx, float *restrict wy, float *restrict wz,
                                       float *restrict dist_out, float *restrict lx, float *restrict ly,
                                       float *restrict lz, float *restrict pdf_out, int *restrict ok)
{
    vec3 p0 = l->tri_p0, e1 = l->tri_e1, e2 = l->tri_e2, n = l->tri_n;
    float pdf_area = 1.0f / l->area_world;
    int two_sided = l->two_sided;
    for (int k = 0; k < count; ++k) {
        TriangleLane t = triangle_light_lane(p0, e1, e2, n, pdf_area, two_sided, px[k], py[k], pz[k], u0[k], u1[k]);
        /* stored here, not by triangle_lane_store: through it GCC kept this loop scalar
         * (soft_shadows 11% more CPU a sample, measured) */
        wx[k] = t.wx, wy[k] = t.wy, wz[k] = t.wz, dist_out[k] = t.dist;
        lx[k] = t.lx, ly[k] = t.ly, lz[k] = t.lz, pdf_out[k] = t.pdf, ok[k] = t.ok;
    }
}

static WEDGE_VECTORISED void triangle_light_batch(const Light *l, int count, const float *const p[3],
                                                  const float *const u[2], const TriangleSampleBatch *out)
{
    triangle_light_loop(l, count, p[0], p[1], p[2], u[0], u[1], out->wi[0], out->wi[1], out->wi[2], out->dist,
                        out->p_light[0], out->p_light[1], out->p_light[2], out->pdf, out->ok);
}

void light_sample_triangle_batch(const Light *l, int count, const float *const p[3], const float *const u[2],
                                 const TriangleSampleBatch *out)
{
    triangle_light_batch(l, count, p, u, out);
}

/* light_sample_triangles_batch's loop: each lane's triangle loaded by its index as floats
 * (LIGHT_F_...: gathers where the vector width has them), the lane arithmetic
 * triangle_light_batch's; two_sided is the lanes' common sidedness. */
static inline void triangles_light_loop(const Light *lights, int two_sided, const int *restrict tri, int count,
                                        const float *restrict px, const float *restrict py, const float *restrict pz,
                                        const float *restrict u0, const float *restrict u1, float *restrict wx,
                                        float *restrict wy, float *restrict wz, float *restrict dist_out,
                                        float *restrict lx, float *restrict ly, float *restrict lz,
                                        float *restrict pdf_out, int *restrict ok)
{
    const float *restrict f = (const float *)lights;
    for (int k = 0; k < count; ++k) {
        int i = tri[k] * LIGHT_FLOATS; /* an index, not a pointer: GCC gathers through the one, not the other */
        vec3 p0 = {f[i + LIGHT_F_TRI_P0], f[i + LIGHT_F_TRI_P0 + 1], f[i + LIGHT_F_TRI_P0 + 2]};
        vec3 e1 = {f[i + LIGHT_F_TRI_E1], f[i + LIGHT_F_TRI_E1 + 1], f[i + LIGHT_F_TRI_E1 + 2]};
        vec3 e2 = {f[i + LIGHT_F_TRI_E2], f[i + LIGHT_F_TRI_E2 + 1], f[i + LIGHT_F_TRI_E2 + 2]};
        vec3 n = {f[i + LIGHT_F_TRI_N], f[i + LIGHT_F_TRI_N + 1], f[i + LIGHT_F_TRI_N + 2]};
        TriangleLane t = triangle_light_lane(p0, e1, e2, n, 1.0f / f[i + LIGHT_F_AREA], two_sided, px[k], py[k],
                                             pz[k], u0[k], u1[k]);
        wx[k] = t.wx, wy[k] = t.wy, wz[k] = t.wz, dist_out[k] = t.dist;
        lx[k] = t.lx, ly[k] = t.ly, lz[k] = t.lz, pdf_out[k] = t.pdf, ok[k] = t.ok;
    }
}

static WEDGE_VECTORISED void triangles_light_batch(const Light *lights, int two_sided, const int *tri, int count,
                                                   const float *const p[3], const float *const u[2],
                                                   const TriangleSampleBatch *out)
{
    triangles_light_loop(lights, two_sided, tri, count, p[0], p[1], p[2], u[0], u[1], out->wi[0], out->wi[1],
                         out->wi[2], out->dist, out->p_light[0], out->p_light[1], out->p_light[2], out->pdf, out->ok);
}

void light_sample_triangles_batch(const Light *lights, const int *tri, int count, const float *const p[3],
                                  const float *const u[2], const TriangleSampleBatch *out)
{
    if (count > 0) triangles_light_batch(lights, lights[tri[0]].two_sided, tri, count, p, u, out);
}

/* warp_uniform_sphere for a run of samples, as light_sample's constant sky takes it: z, r
 * and phi in a loop GCC vectorises (fmaxf(0, m) as a select: m = 1 - z z is never -0, and
 * a NaN gives 0 either way), the sine and cosine of phi by sincos_run (the same bits as
 * warp_uniform_sphere's sincos_one), then the products, in chunks on the stack. */
enum { SKY_CHUNK = 64 };
static WEDGE_VECTORISED void sky_directions(int count, const float *restrict ux, const float *restrict uy,
                                            float *restrict wx, float *restrict wy, float *restrict wz)
{
    for (int k = 0; k < count; ++k) {
        float z = 1.0f - 2.0f * ux[k];
        float m = 1.0f - z * z;
        wx[k] = sqrtf(m > 0.0f ? m : 0.0f); /* r, until the loop below */
        wy[k] = 2.0f * WEDGE_PI * uy[k];    /* phi, until the loop below */
        wz[k] = z;
    }
    for (int k0 = 0; k0 < count; k0 += SKY_CHUNK) {
        int m = count - k0 < SKY_CHUNK ? count - k0 : SKY_CHUNK;
        float sin_phi[SKY_CHUNK], cos_phi[SKY_CHUNK];
        sincos_run(m, wy + k0, sin_phi, cos_phi);
        for (int i = 0; i < m; ++i) {
            float r = wx[k0 + i];
            wx[k0 + i] = r * cos_phi[i];
            wy[k0 + i] = r * sin_phi[i];
        }
    }
}

void light_sample_sky_batch(int count, const float *const u[2], float *const wi[3])
{
    sky_directions(count, u[0], u[1], wi[0], wi[1], wi[2]);
}

/* A light at infinity (distant, sky) as a point beyond the scene along ls->wi from p_ref, facing
 * back: what the shadow ray and the record use for its position and normal. */
static void far_end(const LightSet *set, vec3 p_ref, LightSample *ls)
{
    ls->p_light = v3_madd(p_ref, ls->wi, 2.0f * set->scene_radius);
    ls->n_light = v3_neg(ls->wi);
}

bool light_sky_cosine(const LightSet *set, vec3 n, vec3 p_ref, LightSample *ls)
{
    vec3 wi = warp_cosine_about(n, ls->wi);
    float pdf = warp_cosine_about_pdf(n, wi);
    if (!(pdf > 0.0f)) return false;
    ls->wi = wi;
    ls->pdf = pdf;
    far_end(set, p_ref, ls);
    return true;
}

/* Computed in every lane and kept by a select (a product in one arm of a select would stop
 * the vectoriser: it could trap where the scalar code never computes it). */
static WEDGE_VECTORISED void sky_cosine_lanes(int count, const float *restrict nx_, const float *restrict ny_,
                                             const float *restrict nz_, const int *restrict lambert,
                                             float *restrict wx_, float *restrict wy_, float *restrict wz_,
                                             float *restrict pdf_, int *restrict ok)
{
    for (int k = 0; k < count; ++k) {
        float nx = nx_[k], ny = ny_[k], nz = nz_[k], ux = wx_[k], uy = wy_[k], uz = wz_[k];
        /* warp_cosine_about */
        float sx = nx + ux, sy = ny + uy, sz = nz + uz;
        float inv = 1.0f / sqrtf(sx * sx + sy * sy + sz * sz);
        float wx = sx * inv, wy = sy * inv, wz = sz * inv;
        /* warp_cosine_about_pdf */
        float c = nx * wx + ny * wy + nz * wz, pdf = c * 0.318309886f;
        int lam = lambert[k] != 0, above = c > 0.0f;
        int keep = lam & above;
        wx_[k] = keep ? wx : ux;
        wy_[k] = keep ? wy : uy;
        wz_[k] = keep ? wz : uz;
        pdf_[k] = keep ? pdf : pdf_[k];
        ok[k] &= (lam ^ 1) | above;
    }
}

void light_sky_cosine_batch(int count, const float *const n[3], const int *lambert, float *const wi[3], float *pdf,
                            int *ok)
{
    sky_cosine_lanes(count, n[0], n[1], n[2], lambert, wi[0], wi[1], wi[2], pdf, ok);
}

bool light_sample(const LightSet *set, const Tracer *tr, int li, vec3 p_ref, float time01, vec2 u, LightSample *ls)
{
    const Light *l = &set->lights[li];
    switch (l->kind) {
    case LIGHT_AREA: {
        const Geom *g = &tr->layers[l->layer].geoms[l->geom];
        if (g->kind == GEOM_TRIANGLES && l->instance < 0) {
            if (!(l->area_world > 0.0f)) return false;
            vec2 b = warp_triangle(u);
            /* p = b0 p0 + b1 p1 + b2 p2 = p0 + b1 e1 + b2 e2 */
            vec3 p = v3_add(l->tri_p0, v3_add(v3_scale(l->tri_e1, b.y), v3_scale(l->tri_e2, 1.0f - b.x - b.y)));
            return finish_area_sample(l, p_ref, p, l->tri_n, 1.0f / l->area_world, l->tri_err, ls);
        }
        /* a static whole sphere's centre and radius were found once (lights_build) */
        if (g->kind == GEOM_SPHERE && l->instance < 0 && sphere_is_full(g))
            return sample_sphere(l, g, NULL, l->sphere_c, l->sphere_r, p_ref, u, ls);
        EmitterXform x = emitter_xform(tr, l->instance, time01);
        if (g->kind == GEOM_TRIANGLES) {
            vec3 P[3], n;
            float area;
            emitter_triangle(g, l->prim, &x, P, &n, &area);
            if (!(area > 0.0f)) return false;
            vec2 b = warp_triangle(u);
            vec3 p = v3_add(v3_add(v3_scale(P[0], b.x), v3_scale(P[1], b.y)), v3_scale(P[2], 1.0f - b.x - b.y));
            float err = LIGHT_OFFSET_REL * fmax_nonneg(v3_max_abs(P[0]), fmax_nonneg(v3_max_abs(P[1]), v3_max_abs(P[2])));
            return finish_area_sample(l, p_ref, p, n, 1.0f / area, err, ls);
        }
        Mat4 m = emitter_world_from_object(g, &x);
        if (g->kind == GEOM_SPHERE) {
            vec3 c;
            float r;
            sphere_world(g, &m, &c, &r);
            return sample_sphere(l, g, &m, c, r, p_ref, u, ls);
        }
        /* disk: uniform in area (radius by the square-root map, angle up to phimax) */
        vec3 n;
        float area = disk_area(g, &m, &n);
        if (!(area > 0.0f)) return false;
        double r = sqrt(g->inner_radius * g->inner_radius + u.x * (g->radius * g->radius - g->inner_radius * g->inner_radius));
        double phi = u.y * g->phimax_rad;
        vec3 p = mat4_apply_point(&m, v3((float)(r * cos(phi)), (float)(r * sin(phi)), (float)g->height));
        float err = LIGHT_OFFSET_REL * (v3_max_abs(p) + (float)g->radius);
        return finish_area_sample(l, p_ref, p, n, 1.0f / area, err, ls);
    }
    case LIGHT_POINT:
    case LIGHT_SPOT: {
        vec3 d = v3_sub(l->p_world, p_ref);
        float dist2 = v3_length2(d);
        if (!(dist2 > 0.0f)) return false;
        float dist = sqrtf(dist2);
        ls->wi = v3_scale(d, 1.0f / dist);
        ls->dist = dist;
        ls->p_light = l->p_world;
        ls->n_light = v3s(0.0f);
        ls->err_light = light_delta_offset(l);
        vec3 I = l->L;
        if (l->kind == LIGHT_SPOT) {
            float cos_t = -v3_dot(ls->wi, l->w_world);
            float lo = l->cos_falloff_end, hi = l->cos_falloff_start;
            I = v3_scale(I, spot_falloff(cos_t, lo, hi));
        }
        ls->Li = v3_scale(I, 1.0f / dist2);
        ls->pdf = 1.0f;
        ls->delta = true;
        return v3_any_positive(ls->Li);
    }
    case LIGHT_DISTANT:
        ls->wi = l->w_world;
        ls->dist = INFINITY;
        far_end(set, p_ref, ls);
        ls->err_light = 0.0f;
        ls->Li = l->L;
        ls->pdf = 1.0f;
        ls->delta = true;
        return v3_any_positive(ls->Li);
    case LIGHT_INFINITE:
        if (l->env) {
            if (!envmap_sample(l->env, u, &ls->wi, &ls->Li, &ls->pdf)) return false;
        } else {
            ls->wi = warp_uniform_sphere(u);
            ls->Li = l->L;
            ls->pdf = LIGHT_SKY_PDF;
        }
        ls->dist = INFINITY;
        far_end(set, p_ref, ls);
        ls->err_light = 0.0f;
        ls->delta = false;
        return v3_any_positive(ls->Li);
    }
    return false;
}

vec3 area_light_L(const LightSet *set, int li, const SurfaceHit *h, vec3 w)
{
    if (li < 0 || li >= set->count) return v3s(0.0f);
    const Light *l = &set->lights[li];
    if (!l->two_sided && v3_dot(h->ng, w) <= 0.0f) return v3s(0.0f); /* one-sided: emits along ng */
    return l->L;
}

float area_light_pdf(const LightSet *set, const Tracer *tr, int li, vec3 p_ref, const SurfaceHit *h, float time01)
{
    if (li < 0 || li >= set->count) return 0.0f;
    const Light *l = &set->lights[li];
    const Geom *g = &tr->layers[l->layer].geoms[l->geom];
    vec3 d = v3_sub(h->p, p_ref);
    float dist2 = v3_length2(d);
    if (!(dist2 > 0.0f)) return 0.0f;
    vec3 wi = v3_scale(d, 1.0f / sqrtf(dist2));
    float area;
    if (g->kind == GEOM_TRIANGLES && l->instance < 0) {
        area = l->area_world;
    } else if (g->kind == GEOM_TRIANGLES) {
        EmitterXform x = emitter_xform(tr, l->instance, time01);
        vec3 P[3], n;
        emitter_triangle(g, l->prim, &x, P, &n, &area);
    } else if (g->kind == GEOM_SPHERE) {
        /* a static sphere's centre and radius were found once (lights_build) */
        vec3 c = l->sphere_c;
        float r = l->sphere_r;
        if (l->instance >= 0) {
            EmitterXform x = emitter_xform(tr, l->instance, time01);
            Mat4 m = emitter_world_from_object(g, &x);
            sphere_world(g, &m, &c, &r);
        }
        float dc2 = v3_length2(v3_sub(c, p_ref));
        if (dc2 > r * r * 1.0001f) {
            /* cone sampling only reaches the cap facing p_ref (matters for partial spheres) */
            if (v3_dot(v3_sub(h->p, c), v3_sub(p_ref, h->p)) < 0.0f) return 0.0f;
            float sin2_max = r * r / dc2;
            float one_minus_cos_max = sin2_max < 0.00068523f ? sin2_max / 2.0f : 1.0f - sqrtf(fmaxf(0.0f, 1.0f - sin2_max));
            return 1.0f / (2.0f * WEDGE_PI * one_minus_cos_max);
        }
        area = 4.0f * WEDGE_PI * r * r;
    } else {
        EmitterXform x = emitter_xform(tr, l->instance, time01);
        Mat4 m = emitter_world_from_object(g, &x);
        vec3 n;
        area = disk_area(g, &m, &n);
    }
    float cos_l = fabsf(v3_dot(h->ng, wi));
    if (!(area > 0.0f) || !(cos_l > 0.0f)) return 0.0f;
    float pdf = dist2 / (cos_l * area);
    return isfinite(pdf) ? pdf : 0.0f;
}

