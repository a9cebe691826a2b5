/* Path integrator with next-event estimation and MIS (see integrator.h).
 *
 * Sampler dimensions, in this fixed order per camera sample (strata line up across the
 * samples of a pixel): film position (2D); lens (2D, only with a lens); time (1D, only with
 * motion); then per path vertex: light choice (1D; among the lights not in
 * LightSet.delta_every, which every vertex lights), light position (2D), BSDF lobe choice
 * (1D), BSDF direction (2D). Every vertex takes all of them, whatever its material (a delta
 * BSDF draws the light dimensions and does not use them; a Lambert vertex reserves the lobe
 * choice's index without drawing it), so the strata of a dimension belong to the same
 * decision in every sample.
 *
 * Materials: Lambert (material.h) and the glossy BSDFs of bsdf_glossy.h, evaluated in the
 * local frame (t1, t2, ns). Delta lobes (smooth conductor / dielectric, the smooth coat of
 * coateddiffuse) are reached only by BSDF sampling, and what they see is weighted 1 (no
 * MIS: light sampling cannot produce their directions). A Lambert receiver samples a constant
 * sky that is the pick's only light by cosine about its normal (sky_by_cosine), and a Lambert
 * last vertex takes its lights by light sampling alone (weight 1, no BSDF ray:
 * lambert_light_only) in a scene without infinite lights, or beyond the first hit under such
 * a sky. */
#include "render/integrator.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/vectorise.h"
#include "render/lambert_bounce.h"
#include "render/light_choose.h"
#include "render/shadow_rays.h"
#include "render/warp.h"

/* The wave is compiled twice, for whole records (integrate_wave) and for the radiance alone
 * (integrate_wave_radiance): wave_integrate and every stage function it calls once are forced
 * inline into both, so that each copy is specialised for its output and inlines what the one
 * copy of the base build inlined (GCC inlines a large static function that has one caller,
 * not one with two: left to it, a sample took 2-4% more instructions; docs/benchmarks.md,
 * "Issue 22, twenty-first round"). */
#define WAVE_STAGE static inline __attribute__((always_inline))

/* All three components finite, without a test and branch per component: x * 0 is 0 for a
 * finite x and NaN for an infinite or NaN one, and a sum with a NaN term is NaN, which is
 * the one value unequal to itself. (Exact: no rounding can make a NaN of zeros or the
 * converse.) */
static inline bool finite3(vec3 v)
{
    float z = v.x * 0.0f + v.y * 0.0f + v.z * 0.0f;
    return z == z;
}

/* v3_max_component(v) <= 0 without its two fmaxf library calls: fmaxf skips NaN operands,
 * so the maximum is <= 0 exactly when no component is > 0 and not all of them are NaN. */
static inline bool max_component_nonpositive(vec3 v)
{
    if (v.x > 0.0f || v.y > 0.0f || v.z > 0.0f) return false;
    return !(isnan(v.x) && isnan(v.y) && isnan(v.z));
}

/* Replaces a non-finite contribution by zero and counts it. */
static vec3 guard3(vec3 v, IntegratorStats *st)
{
    if (finite3(v)) return v;
    ++st->guarded_events;
    return v3s(0.0f);
}

typedef struct {
    SurfaceHit hit;
    vec3 wo;      /* unit, towards where the path came from */
    vec3 n;       /* Lambert: shading normal flipped to wo's side (the lobe's axis);
                   * glossy: the shading normal as is (dielectrics need inside / outside) */
    vec3 t1, t2;  /* glossy: tangents completing the local frame (t1, t2, n); a Lambert
                   * vertex leaves them unset (its bounce is sampled in lanes, which make
                   * their own: wave_lambert_bounces) */
    bool glossy;
    vec3 albedo;  /* Lambert reflectance */
    float cos_o;  /* Lambert: v3_dot(n, wo) */
    GlossyBsdf bsdf;
    vec3 wo_l;    /* glossy: wo in the local frame */
} Vertex;

static vec3 to_local(const Vertex *v, vec3 w) { return v3(v3_dot(v->t1, w), v3_dot(v->t2, w), v3_dot(v->n, w)); }

static vec3 from_local(const Vertex *v, vec3 l)
{
    return v3_normalize(v3_add(v3_add(v3_scale(v->t1, l.x), v3_scale(v->t2, l.y)), v3_scale(v->n, l.z)));
}

/* A glossy vertex takes its tangents here, for every f; a Lambert one needs them only to
 * sample its bounce, which wave_lambert_bounces does for the stage's Lambert vertices in
 * lanes, tangents included. */
static inline __attribute__((always_inline)) void make_vertex(const IntegratorScene *sc, const SurfaceHit *h, vec3 wo,
                                                               Vertex *v)
{
    const MaterialTable *mt = sc->materials;
    v->hit = *h;
    v->wo = wo;
    /* mix materials pick one of their two materials per hit (deterministic hash of p, wo) */
    int m = h->geom->material;
    const Material *mat = material_get(mt, m);
    if (mat->kind == MATERIAL_MIX) {
        m = material_resolve(mt, m, h->uv, h->p, wo);
        mat = material_get(mt, m);
    }
    /* The glossy BSDF, or the Lambert albedo (a Lambert hit is the common case). */
    v->glossy = mat->kind == MATERIAL_GLOSSY;
    if (v->glossy) {
        v->bsdf = material_glossy_bsdf(mt, mat, h->uv, h->p);
        v->n = h->ns;
        v3_basis(v->n, &v->t1, &v->t2);
        v->wo_l = to_local(v, wo);
        v->albedo = v3s(0.0f);
    } else {
        /* an untextured diffuse material's albedo is its reflectance, without the call; a
         * 2D checkerboard of two constants' is found inline (material_checker_albedo); any
         * other textured one's is material_albedo's, without its look-up of mat (mat is
         * diffuse: material_resolve leaves a diffuse or a glossy material) */
        if (mat->checker) v->albedo = material_checker_albedo(mat, h->uv);
        else v->albedo = material_textured(mt, mat) ? material_diffuse_albedo(mt, mat, h->uv, h->p) : mat->reflectance;
        float cos_ns = v3_dot(h->ns, wo);
        bool flip = cos_ns < 0.0f;
        v->n = flip ? v3_neg(h->ns) : h->ns;
        /* v3_dot(v->n, wo) bit for bit: negating every term of a sum negates a nonzero sum
         * exactly (round to nearest is symmetric), and a flipped sum is < 0 */
        v->cos_o = flip ? -cos_ns : cos_ns;
    }
}

/* f(wo, wi) (no cosine), the |cosine| of wi at the shading normal, and the solid-angle
 * pdf with which BSDF sampling would pick wi (non-delta lobes only). */
static vec3 vertex_f(const Vertex *v, vec3 wi, float *cos_abs, float *pdf)
{
    if (v->glossy) {
        vec3 wi_l = to_local(v, wi);
        *cos_abs = fabsf(wi_l.z);
        *pdf = glossy_pdf(&v->bsdf, v->wo_l, wi_l);
        return glossy_f(&v->bsdf, v->wo_l, wi_l);
    }
    float cos_i = v3_dot(v->n, wi), cos_o = v3_dot(v->n, v->wo);
    *cos_abs = fabsf(cos_i);
    *pdf = bsdf_diffuse_pdf(cos_o, cos_i);
    return bsdf_diffuse_f(v->albedo, cos_o, cos_i);
}

typedef struct {
    vec3 wi;      /* world, unit */
    vec3 weight;  /* f |cos| / pdf */
    float pdf;    /* solid angle (the lobe probability for delta lobes) */
    bool delta;
} VertexSample;

/* BSDF sampling at a glossy vertex: a lobe chosen with u_lobe and sampled with u
 * (bsdf_glossy.h). False when nothing was sampled. (A Lambert vertex's bounce is sampled in
 * lanes: wave_lambert_bounces.) */
WAVE_STAGE bool glossy_vertex_sample(const Vertex *v, float u_lobe, vec2 u, VertexSample *vs)
{
    GlossySample gs;
    if (!glossy_sample(&v->bsdf, v->wo_l, u_lobe, u, &gs)) return false;
    vs->wi = from_local(v, gs.wi);
    vs->pdf = gs.pdf;
    vs->delta = gs.delta;
    vs->weight = v3_scale(gs.f, fabsf(gs.wi.z) / gs.pdf);
    return true;
}

/* The light a path vertex's dimensions choose (the dimensions themselves are the wave's
 * arrays, Wave.dim_*: wave_vertex_dims writes them there run by run). */
typedef struct {
    /* the light its pick and light dimensions choose (lights_pick, then
     * lights_pick_in_mesh, made by wave_triangle_light_samples): its index (-1: none),
     * probability, and the position sample as that leaves it */
    int light_index;
    float light_pmf;
    vec2 light_uv;
} VertexDims;

/* Scalar dimensions per vertex: pick (1), light (2), lobe (1), BSDF (2). Only glossy BSDFs
 * choose a lobe: its index is reserved (the later dimensions keep theirs) and its value
 * drawn when needed (sampler_1d_at). */
enum { VERTEX_DIMS = 6 };

/* The first scalar dimension of path vertex `depth` (1: the first hit), after the camera's:
 * film (2), lens (2, with a lens), time (1, with motion). */
static int vertex_dim0(const IntegratorScene *sc, int depth)
{
    return 2 + (sc->sample_lens ? 2 : 0) + (sc->sample_time ? 1 : 0) + VERTEX_DIMS * (depth - 1);
}

/* Next-event estimation: one sample of a light picked by power, MIS-weighted against the
 * BSDF (Veach 1997, eq. 9.13 with beta = 2), plus every delta light of LightSet.delta_every
 * (those are not in the pick), in two halves around the shadow rays, which are traced in a
 * batch with the wave's other shadow rays. What the first half leaves for the second: */
typedef struct {
    LightSample ls;
    int light;        /* index of the sampled light */
    float pmf;        /* probability of having picked it */
    vec3 f;           /* BSDF value for ls.wi */
    float cos_i;      /* |cos| of ls.wi at the shading normal */
    float pdf_bsdf;   /* BSDF sampling's solid-angle density of ls.wi */
    bool is_area;
} LightPending;

/* The shadow ray from vertex v to light sample ls: it leaves the receiver and stops short
 * of the light's surface (both ends pushed off their surfaces). False (counted) when the
 * two ends coincide. */
static bool shadow_ray_to(const Vertex *v, const LightSample *ls, float time01, IntegratorStats *st, TracerRay *ray)
{
    vec3 o, dir;
    float tmax;
    if (!shadow_ray_make(&v->hit, ls, &o, &dir, &tmax)) {
        ++st->guarded_events;
        return false;
    }
    ++st->rays_shadow;
    *ray = (TracerRay){o, dir, tmax, time01, 0u};
    return true;
}

/* A shadow ray computed ahead for shadow_ray_to (wave_*_light_samples): origin,
 * direction and length, or `redo` where shadow_ray_to must compute it itself. */
typedef struct {
    vec3 o, dir;
    float len;
    bool redo;
} ShadowRayAhead;

/* shadow_ray_to's outcome for a ray computed ahead (not `redo`: a finite distance). */
static bool shadow_ray_ahead(const ShadowRayAhead *a, float time01, IntegratorStats *st, TracerRay *ray)
{
    if (!(a->len > 0.0f)) {
        ++st->guarded_events;
        return false;
    }
    ++st->rays_shadow;
    *ray = (TracerRay){a->o, a->dir, a->len, time01, 0u};
    return true;
}

/* What light_prepare_at does once lp->ls holds light `light`'s sample (light_sample
 * returned true), perhaps with its shadow ray (ahead; NULL: computed here). */
static bool light_prepare_sampled(const IntegratorScene *sc, const Vertex *v, float time01, int light, float pmf,
                                  const ShadowRayAhead *ahead, IntegratorStats *st, TracerRay *shadow,
                                  LightPending *lp)
{
    lp->light = light;
    lp->pmf = pmf;
    const LightSample *ls = &lp->ls;
    lp->f = vertex_f(v, ls->wi, &lp->cos_i, &lp->pdf_bsdf);
    lp->is_area = sc->lights->lights[light].kind == LIGHT_AREA;
    /* A receiver facing away from the light, or a light sending nothing this way (a spot
     * light's cone), traces no shadow ray (and records none). */
    if (max_component_nonpositive(lp->f) || max_component_nonpositive(ls->Li)) return false;
    bool traced = ahead && !ahead->redo ? shadow_ray_ahead(ahead, time01, st, shadow)
                                        : shadow_ray_to(v, ls, time01, st, shadow);
    if (!traced) return false;
    shadow->skip_mask = sc->lights->lights[light].shadow_skip_mask;
    return true;
}

/* Whether vertex v samples light l by cosine about its normal instead of the light's own way:
 * the scene's constant sky, when it is the pick's only light (LightSet.sky_cosine_light), at
 * a Lambert receiver. There the sky's light sample has the density of the receiver's BSDF
 * sample, whose value f cos / pdf is the albedo in every direction, so only visibility
 * varies; a uniform sample spends half its samples below the horizon and weighs the rest by
 * the cosine. MIS needs only the density each technique has at a direction, which sky_pdf_at
 * gives (docs/algorithms.md, "A constant sky sampled by cosine at a Lambert receiver"). */
static inline bool sky_by_cosine(const LightSet *set, const Vertex *v, int l)
{
    return !v->glossy && l == set->sky_cosine_light;
}

/* Whether vertex v at `depth` takes the constant sky l (sky_by_cosine) from its BSDF-sampled
 * ray alone, with MIS weight 1 and no light sample or shadow ray of its own: a Lambert
 * vertex before the last, whose cosine-sampled bounce ray is traced anyway to carry the path
 * on and is a sample of the sky with the very density the light sample would have. Weights
 * 0 (light) and 1 (BSDF) sum to 1 wherever the integrand is not 0, since the cosine sample
 * covers the receiver's whole hemisphere (Veach 1997, ch. 9). The last vertex takes the sky
 * by light sampling alone (lambert_light_only), so every Lambert vertex takes one cosine
 * sample of the sky. Only in a frame no method filters (IntegratorScene.sky_bounce_alone):
 * there the two samples of MIS cost more CPU than their lower noise saves, while a filter
 * that takes the indirect light's noise out leaves the first hit's direct noise, which the
 * second sample halves (docs/algorithms.md, "One cosine sample of the sky a vertex"). */
static inline bool sky_by_bsdf_alone(const IntegratorScene *sc, const Vertex *v, int l, int depth)
{
    return sc->sky_bounce_alone && depth < sc->max_depth && sky_by_cosine(sc->lights, v, l);
}

/* The density of the sample that infinite light l takes at vertex v, for direction wi. */
static inline float sky_pdf_at(const LightSet *set, int l, const Vertex *v, vec3 wi)
{
    return sky_by_cosine(set, v, l) ? warp_cosine_about_pdf(v->n, wi) : infinite_light_pdf(set, l, wi);
}

/* A point on light `light` (chosen with probability pmf) and its shadow ray. False when the
 * sample contributes nothing without one (the estimate is then 0). */
static bool light_prepare_at(const IntegratorScene *sc, const Vertex *v, float time01, int light, vec2 u_light,
                             float pmf, IntegratorStats *st, TracerRay *shadow, LightPending *lp)
{
    if (!light_sample(sc->lights, sc->tracer, light, v->hit.p, time01, u_light, &lp->ls)) return false;
    if (sky_by_cosine(sc->lights, v, light) && !light_sky_cosine(sc->lights, v->n, v->hit.p, &lp->ls))
        return false;
    return light_prepare_sampled(sc, v, time01, light, pmf, NULL, st, shadow, lp);
}

/* Second half, once the shadow ray is traced: the MIS-weighted estimate. */
static vec3 light_finish(const LightPending *lp, bool occluded, IntegratorStats *st)
{
    if (occluded) return v3s(0.0f);
    float denom = lp->pmf * lp->ls.pdf;
    if (!(denom > 0.0f)) {
        ++st->guarded_events;
        return v3s(0.0f);
    }
    float w = lp->ls.delta ? 1.0f : mis_power(denom, lp->pdf_bsdf);
    return guard3(v3_scale(v3_mul(lp->f, lp->ls.Li), lp->cos_i * w / denom), st);
}

/* The part of light_finish's (unoccluded, non-zero) estimate that BSDF value f_part (a share
 * of lp->f) carries: the same MIS weight and densities, lp->f replaced by f_part. */
static vec3 light_finish_part(const LightPending *lp, vec3 f_part)
{
    float denom = lp->pmf * lp->ls.pdf;
    float w = lp->ls.delta ? 1.0f : mis_power(denom, lp->pdf_bsdf);
    return v3_scale(v3_mul(f_part, lp->ls.Li), lp->cos_i * w / denom);
}

/* The glossy lobes' share of f, the value of a glossy vertex's whole BSDF for world direction
 * wi: f less the diffuse lobe's (glossy_f_diffuse), each channel at least 0. */
static vec3 glossy_share(const Vertex *v, vec3 wi, vec3 f)
{
    vec3 fd = glossy_f_diffuse(&v->bsdf, v->wo_l, to_local(v, wi));
    return v3(fmaxf(f.x - fd.x, 0.0f), fmaxf(f.y - fd.y, 0.0f), fmaxf(f.z - fd.z, 0.0f));
}

/* Emission reached by a BSDF-sampled ray, MIS-weighted against light sampling (weight 1
 * after a delta lobe or from a delta-only vertex, which light sampling never serves). */
WAVE_STAGE vec3 bsdf_ray_emission(const IntegratorScene *sc, const Vertex *from, int depth, float pdf_bsdf, bool no_mis,
                                  const SurfaceHit *h, vec3 wi, float time01, bool hit)
{
    vec3 p_from = from->hit.p;
    const LightSet *L = sc->lights;
    vec3 sum = v3s(0.0f);
    if (!hit) {
        for (int k = 0; k < L->infinite_count; ++k) {
            int li = L->infinite[k];
            /* the light's density is looked up only where MIS weighs it (under the sky from
             * the bounce ray alone, every escaping ray of a Lambert vertex before the last: no
             * cosine density a ray) */
            float w = 1.0f;
            if (!no_mis && !sky_by_bsdf_alone(sc, from, li, depth)) {
                /* the light's pick probability as lights_choose has it (LightChoice.pmf is
                 * lights_pmf's value), without the call */
                float pdf_light = L->choice[li].pmf * sky_pdf_at(L, li, from, wi);
                w = mis_power(pdf_bsdf, pdf_light);
            }
            sum = v3_add(sum, v3_scale(infinite_light_L(L, li, wi), w));
        }
        return sum;
    }
    if (h->light < 0) return sum;
    vec3 Le = area_light_L(L, h->light, h, v3_neg(wi));
    if (max_component_nonpositive(Le)) return sum;
    if (no_mis) return Le;
    float pdf_light = lights_pmf(L, h->light) * area_light_pdf(L, sc->tracer, h->light, p_from, h, time01);
    return v3_scale(Le, mis_power(pdf_bsdf, pdf_light));
}

/* fminf(a, 1) inline, for every a (NaN gives 1, as fminf): a library call otherwise. */
static inline float min1(float a) { return a < 1.0f ? a : 1.0f; }

/* The first hit's reflectance split for the filters' demodulation (sample_record.h). */
static void record_first_hit_material(const Vertex *v, SampleRecord *rec)
{
    /* the split in locals, summed from them: read back from the record, the sum waited on
     * its own stores */
    vec3 diffuse, glossy;
    if (v->glossy) {
        GlossyAlbedo a = glossy_albedo(&v->bsdf, v->wo_l);
        diffuse = a.diffuse;
        glossy = a.glossy;
        rec->phong_exponent = glossy_phong_exponent(&v->bsdf);
        rec->unfilterable = !glossy_is_filterable(&v->bsdf) || glossy_is_delta(&v->bsdf);
    } else {
        diffuse = v->albedo;
        glossy = v3s(0.0f);
        rec->phong_exponent = 0.0f;
        rec->unfilterable = false;
    }
    rec->albedo_diffuse = diffuse;
    rec->albedo_glossy = glossy;
    vec3 sum = v3_add(diffuse, glossy);
    rec->albedo = v3(min1(sum.x), min1(sum.y), min1(sum.z));
}

/* Scene time of shutter fraction shutter_u -> fraction between the two transform poses
 * (what Embree's time is). */
static float shutter_time01(const IntegratorScene *sc, float shutter_u)
{
    float t_scene = sc->shutter_open + shutter_u * (sc->shutter_close - sc->shutter_open);
    float span = sc->xform_time_end - sc->xform_time_start;
    float time01 = span > 0.0f ? (t_scene - sc->xform_time_start) / span : 0.0f;
    return clamp01f(time01);
}

float integrator_fixed_time01(const IntegratorScene *sc) { return shutter_time01(sc, 0.0f); }
float integrator_shutter_time01(const IntegratorScene *sc, float shutter_u) { return shutter_time01(sc, shutter_u); }

/* The record of a sample that has seen nothing yet. Field by field rather than
 * `*rec = (SampleRecord){0}`: the compiler turns that into a `rep stos` over the whole
 * record, whose start-up cost was a visible part of a sample; these are a few vector
 * stores. The ray geometry arrays are cleared too. Fields that are always written later
 * are left alone: the lens and time (wave_camera_sample) and the first hit's fields
 * (wave_first_hit, on a hit and on a miss), so the record is still filled completely, but
 * for the fields a radiance-only render's users declared they do not read (render_reads.h). */
static inline void record_reset(SampleRecord *rec, bool radiance_only)
{
    /* L .. unfiltered_direct are one run of 18 floats: one fixed-size clear (a few vector
     * stores) instead of 18 scalar ones. +0.0f is all zero bits. */
    _Static_assert(offsetof(SampleRecord, unfiltered_direct) == offsetof(SampleRecord, L) + 5 * sizeof(vec3),
                   "the radiance fields are one run");
    memset((char *)rec + offsetof(SampleRecord, L), 0, 6 * sizeof(vec3));
    rec->direct_glossy = v3s(0.0f);
    rec->hit = false;
    rec->shadow_count = rec->bounce_count = 0;
    /* a render whose users read the radiance alone (render_reads.h) leaves the motion and
     * the ray geometry entries unset unless asked for them (then they are written anyway) */
    if (radiance_only) return;
    rec->motion_px[0] = rec->motion_px[1] = 0.0f;
    rec->shadow[0] = (ShadowRayRecord){0};
    rec->bounce[0] = (BounceRayRecord){0};
}

/* The first hit's screen velocity (SampleRecord.motion_px, for LR): its point in its
 * instance's space, placed by the instance's transform and projected by the camera at shutter
 * open and at shutter close. The chord over the shutter: exact for linear motion, the mean
 * velocity for rotation. Points behind the camera at either end get 0. */
static void first_hit_motion(const IntegratorScene *sc, const SurfaceHit *h, float time01, float motion_px[2])
{
    motion_px[0] = motion_px[1] = 0.0f;
    if (!sc->sample_time) return;
    bool instance_moving = h->instance >= 0 && sc->tracer->instances[h->instance].moving;
    /* A static point seen by a static camera projects to the same pixel at both ends: 0,
     * exactly what the two projections below would give, without them (most hits). */
    if (!instance_moving && !sc->camera->moving) return;
    float t0 = shutter_time01(sc, 0.0f), t1 = shutter_time01(sc, 1.0f);
    vec3 p0 = h->p, p1 = h->p;
    if (instance_moving) {
        Mat4 wfi = tracer_world_from_instance(sc->tracer, h->instance, time01), ifw;
        if (!mat4_inverse(&wfi, &ifw)) return;
        vec3 p_inst = mat4_apply_point(&ifw, h->p);
        Mat4 w0 = tracer_world_from_instance(sc->tracer, h->instance, t0);
        Mat4 w1 = tracer_world_from_instance(sc->tracer, h->instance, t1);
        p0 = mat4_apply_point(&w0, p_inst);
        p1 = mat4_apply_point(&w1, p_inst);
    }
    float x0, y0, x1, y1;
    if (!camera_project(sc->camera, p0, t0, &x0, &y0) || !camera_project(sc->camera, p1, t1, &x1, &y1)) return;
    float mx = x1 - x0, my = y1 - y0;
    if (isfinite(mx) && isfinite(my)) motion_px[0] = mx, motion_px[1] = my;
}

/* ---- the wave ----
 *
 * A wave is the camera samples of a few whole pixels (at most WAVE_SAMPLES), integrated
 * together stage by stage: all camera rays are generated and traced as one batch, every
 * first hit is shaded, then per path vertex all shadow rays and all bounce rays go to
 * Embree as batches (tracer_*_batch), and the results are folded in path by path. Each
 * path does exactly the floating-point operations, in the same order, of a path traced on
 * its own; only the order between paths changes, so images do not depend on the wave. */

/* One path of the wave between stages. */
typedef struct {
    int pixel;         /* index into the wave's pixels */
    int sample_index;  /* the pixel sampler's sample index */
    float time01;
    bool alive;        /* has a vertex to continue from */
    Vertex v;
    VertexDims u;      /* the light the current vertex's dimensions choose */
    vec3 beta;         /* path throughput up to v */
    bool unfiltered;   /* light from here on passes the filters unfiltered */
    /* the current vertex's light sample and bounce, between tracing and folding in */
    bool light_pending, light_recorded, unfiltered_light;
    bool light_valued; /* the light's estimate is its group's lane (lambert_triangle_nee), not lp */
    int shadow_ray;    /* index into the occlusion or the recorded batch */
    LightPending lp;
    int tri_group, tri_lane; /* its picked static triangle's or constant sky's samples
                              * (WaveTriangleSamples), or -1 */
    bool bounce;       /* a bounce was sampled (vs, beta_next) */
    int hit_slot;      /* its ray's entry in the closest-hit batch (a last ray that cannot
                        * reach an emitter, lights_ray_may_reach_emitter, leaves bounce false) */
    VertexSample vs;
    vec3 beta_next;
} WavePath;

/* The wave's camera samples as arrays, one lane per path (camera_generate_rays' input; its
 * rays go to the wave's camera arrays). */
typedef struct {
    float px[WAVE_SAMPLES], py[WAVE_SAMPLES], lens_u[WAVE_SAMPLES], lens_v[WAVE_SAMPLES];
} CameraBatch;

/* Each path's current vertex, one lane per path, written beside its Vertex
 * (receiver_to_lanes), for the delta lights and the Lambert bounces: position, geometric
 * normal and offset (every live vertex), a Lambert vertex's lobe axis n, cos_o, albedo and
 * the path's throughput beta, and whether the path is alive at a Lambert vertex (lambert: 0
 * for the others, whose other lanes are stale). */
typedef struct {
    float p[3][WAVE_SAMPLES], ng[3][WAVE_SAMPLES], err[WAVE_SAMPLES];
    float n[3][WAVE_SAMPLES], cos_o[WAVE_SAMPLES], albedo[3][WAVE_SAMPLES], beta[3][WAVE_SAMPLES];
    int lambert[WAVE_SAMPLES];
} WaveReceivers;

/* The Lambert vertices' bounces of a stage, one lane per path (lambert_bounce.h; lanes of
 * other paths hold values nothing reads). */
typedef struct {
    float wi[3][WAVE_SAMPLES], pdf[WAVE_SAMPLES], beta_next[3][WAVE_SAMPLES], o[3][WAVE_SAMPLES];
    int sampled[WAVE_SAMPLES], guarded[WAVE_SAMPLES], bounce[WAVE_SAMPLES];
} WaveLambertBounces;

/* Triangle lights batched per stage; paths that pick others sample them one by one.
 * GROUP_SLOTS: wave_triangle_light_samples' memory of each key's group (a power of two). */
enum { WAVE_TRIANGLE_GROUPS = 8, GROUP_SLOTS = 16 };

/* Occlusion rays of one stage: per path, the picked light's and one per delta light lit at
 * every vertex. */
enum { WAVE_OCC_RAYS = WAVE_SAMPLES * (1 + LIGHTS_DELTA_EVERY_MAX) };

struct Wave {
    WavePath path[WAVE_SAMPLES];
    /* rays of one stage and what they found */
    TracerRay ray_occ[WAVE_OCC_RAYS], ray_rec[WAVE_SAMPLES], ray_hit[WAVE_SAMPLES];
    bool occluded[WAVE_OCC_RAYS], rec_found[WAVE_SAMPLES], hit_found[WAVE_SAMPLES];
    SurfaceHit rec_hit[WAVE_SAMPLES], hit[WAVE_SAMPLES];
    /* one pixel sampler, set up for sampler_pixel (-1: none), and a run of its samples */
    PixelSampler sampler;
    int sampler_pixel;
    SamplerRun run;
    /* each pixel's paths: path[path_first[k] .. path_first[k] + path_count[k]) */
    int path_first[WAVE_SAMPLES], path_count[WAVE_SAMPLES];
    /* one run's values of one dimension */
    float run_1d[SAMPLER_RUN_MAX];
    vec2 run_2d[SAMPLER_RUN_MAX], run_2d_b[SAMPLER_RUN_MAX];
    /* the current vertex's dimensions per path (wave_vertex_dims), in the order drawn:
     * light choice (1D), position on the light (2D), BSDF direction (2D) and its
     * warp_cosine_hemisphere (Lambert's direction in the local frame); the lobe choice (1D)
     * is drawn by a glossy vertex alone, at vertex_dim0 + 3 */
    float dim_pick[WAVE_SAMPLES];
    vec2 dim_light[WAVE_SAMPLES], dim_bsdf[WAVE_SAMPLES];
    float dim_cosine[3][WAVE_SAMPLES];
    CameraBatch camera;
    /* the wave's camera rays, per path, as arrays: camera_generate_rays writes them and
     * tracer_intersect_arrays reads them, with no TracerRay between (16-byte aligned: Embree's
     * streams read cam_d and cam_time01 in place) */
    _Alignas(16) float cam_o[3][WAVE_SAMPLES], cam_d[3][WAVE_SAMPLES], cam_time01[WAVE_SAMPLES];
    WaveReceivers rx;
    WaveLambertBounces lb;
    /* the delta lights lit at every vertex, entry k for LightSet.delta_every[k] */
    WaveDeltaSamples delta[LIGHTS_DELTA_EVERY_MAX];
    /* the delta rays of the occlusion batch (ray_occ) made path by path: ray delta_fix_ray[i]
     * answers light delta_fix_light[i]'s lane delta_fix_path[i] */
    int delta_fix_ray[WAVE_OCC_RAYS], delta_fix_light[WAVE_OCC_RAYS], delta_fix_path[WAVE_OCC_RAYS];
    int delta_fixes;
    bool delta_redo; /* some Lambert receiver's delta ray is left to wave_vertex_rays */
    /* per path, the sum of its unoccluded delta lights' values, in the lights' order */
    float delta_sum[3][WAVE_SAMPLES];
    WaveTriangleSamples tri[WAVE_TRIANGLE_GROUPS];
    int tri_groups;
    /* a stage's last rays queued for the emitter-box test (wave_emitter_box_test): per
     * queued ray its origin, direction, path and answer */
    float box_o[3][WAVE_SAMPLES], box_d[3][WAVE_SAMPLES];
    int box_path[WAVE_SAMPLES], box_may[WAVE_SAMPLES];
};

/* Zeroed: lanes of paths that never had a vertex hold zeros, not whatever malloc left, for
 * the loops that compute every lane (wave_delta_light_samples). */
Wave *wave_create(void) { return calloc(1, sizeof(Wave)); }
void wave_free(Wave *w) { free(w); }

/* The sampler of pixel k of the wave. Its values are a pure function of (pixel, sample,
 * dimension) and its cache is per pixel, so it is set up again only when the pixel changes
 * (the stages visit the paths in pixel order). */
static PixelSampler *wave_pixel_sampler(Wave *w, const WaveSampling *ws, const WavePixel *pixels, int k)
{
    if (w->sampler_pixel != k) {
        const WavePixel *px = &pixels[k];
        sampler_continue_pixel(&w->sampler, ws->kind, ws->seed, px->px, px->py, ws->pass, px->spp_before, px->spp_set);
        w->sampler_pixel = k;
    }
    return &w->sampler;
}

/* The same at the start of sample `sample_index`. */
static PixelSampler *wave_sampler(Wave *w, const WaveSampling *ws, const WavePixel *pixels, int k, int sample_index)
{
    PixelSampler *s = wave_pixel_sampler(w, ws, pixels, k);
    sampler_start_sample(s, sample_index);
    return s;
}

/* Whether a vertex at `depth` reads its light choice and position dimensions: lights_pick
 * reads u only when some light can be picked (the delta lights of LightSet.delta_every never
 * are), and none is where the pick's only light is a constant sky that every vertex at that
 * depth, all of them Lambert, takes from its bounce ray alone (sky_by_bsdf_alone). */
static inline bool vertex_uses_light_dims(const IntegratorScene *sc, int depth)
{
    bool sky_alone_everywhere = sc->materials_lambert_only && sc->sky_bounce_alone && depth < sc->max_depth &&
                                sc->lights->sky_cosine_light >= 0;
    return sc->lights->power_total > 0.0f && !sky_alone_everywhere;
}

/* Whether a Lambert vertex at `depth` takes its lights' light by light sampling alone (MIS
 * weight 1, no BSDF-sampled ray): the last vertex, whose BSDF ray would only look for
 * emission, unless the filters record where the first hit's bounce ends. MIS's weights need
 * only sum to 1 wherever the integrand is not 0 (Veach 1997, ch. 9), so weights 1 and 0 (the
 * BSDF sample not drawn) are unbiased where light sampling reaches every point of every
 * emitter the vertex sees: the pick by power gives every emitter a probability (its power is
 * > 0) and the triangle, disk and sphere samplers of light.c cover what the receiver can see
 * of it (LightSet.area_sampling_complete). With infinite lights only where the sky is sampled
 * by cosine over the receiver's whole hemisphere (sky_by_cosine) and the vertex is not the
 * first hit: there the BSDF sample is as good a sample of the sky as the light's, and giving
 * it up costs more noise at the pixel's own surface than it saves (docs/algorithms.md,
 * "Light sampling alone at a Lambert last vertex" and "A constant sky sampled by cosine at a
 * Lambert receiver"). */
static inline bool lambert_light_only(const IntegratorScene *sc, int depth)
{
    const LightSet *L = sc->lights;
    bool infinite_ok = L->infinite_count == 0 || (L->sky_cosine_light >= 0 && depth >= 2);
    return depth == sc->max_depth && infinite_ok && L->area_sampling_complete &&
           !(depth == 1 && sc->record_ray_geometry && sc->record_bounce_geometry);
}

/* Whether vertex `depth` samples its BSDF: to carry the path on, or, at the last vertex,
 * to look for emission that MIS weighs against the light sample (area or infinite lights
 * only: no BSDF-sampled ray can find a point, spot or distant light). */
static inline bool vertex_uses_bsdf_dims(const IntegratorScene *sc, int depth)
{
    if (sc->materials_lambert_only && lambert_light_only(sc, depth)) return false;
    return depth < sc->max_depth || sc->lights->has_area || sc->lights->infinite_count > 0;
}

/* Whether a Lambert vertex at `depth` samples a direction (in lanes: wave_lambert_bounces). */
static inline bool lambert_uses_bsdf(const IntegratorScene *sc, int depth)
{
    return vertex_uses_bsdf_dims(sc, depth) && !lambert_light_only(sc, depth);
}

/* The dimensions of vertex `depth` for paths path[j0 .. j0 + run->count), the samples of
 * w->run, drawn dimension by dimension (sampler_run_*: the values sampler_1d / sampler_2d
 * give each sample on its own). Dimensions the vertex will not read are not drawn (their
 * indices stay reserved, so every other dimension keeps its value): on a scene lit only by
 * delta lights at maxdepth 1 (defocus.pbrt) that is every vertex dimension. */
static void wave_vertex_dims(const IntegratorScene *sc, Wave *w, int j0, int depth)
{
    PixelSampler *s = &w->sampler;
    const SamplerRun *run = &w->run;
    int d0 = vertex_dim0(sc, depth);
    bool light_dims = vertex_uses_light_dims(sc, depth), bsdf_dims = vertex_uses_bsdf_dims(sc, depth);
    /* straight into the wave's arrays at the run's paths (no copy into each path) */
    if (light_dims) {
        sampler_run_1d(s, run, d0, w->dim_pick + j0);
        sampler_run_2d(s, run, d0 + 1, w->dim_light + j0);
    }
    if (bsdf_dims) {
        sampler_run_2d(s, run, d0 + 4, w->dim_bsdf + j0);
        warp_cosine_hemisphere_run(run->count, w->dim_bsdf + j0, w->dim_cosine[0] + j0, w->dim_cosine[1] + j0,
                                   w->dim_cosine[2] + j0);
    }
}

/* Where a wave's samples go: whole records (recs), or their radiance alone (rads,
 * radiance_only: integrate_wave_radiance). A constant in each of the wave's two copies
 * (WAVE_STAGE), so every test of it below is decided at compile time. */
typedef struct {
    SampleRecord *recs;
    RadianceRecord *rads;
    bool radiance_only;
} WaveOut;

static inline SampleRecord *wave_out_record(WaveOut out, int j) { return out.radiance_only ? NULL : &out.recs[j]; }
static inline SampleRadiance *wave_out_radiance(WaveOut out, int j)
{
    return out.radiance_only ? &out.rads[j].radiance : &out.recs[j].radiance;
}

/* The record's sample position of one camera sample from its film and shutter dimensions
 * and its point on the lens (the unit disk), and its path's time; the camera ray through it
 * comes later, in a batch. */
static inline void wave_camera_sample(const IntegratorScene *sc, vec2 u_film01, vec2 lens, float shutter_u,
                                      const WavePixel *px, WavePath *p, WaveOut out, int j, float *px_raster,
                                      float *py_raster)
{
    SampleRecord *rec = wave_out_record(out, j);
    float *filter_weight;
    if (!out.radiance_only) {
        record_reset(rec, sc->skip_first_hit_fields && !sc->record_motion && !sc->record_ray_geometry);
        filter_weight = &rec->filter_weight;
    } else {
        /* the radiance alone: its fields start at +0 (all zero bits) */
        memset(&out.rads[j].radiance, 0, sizeof out.rads[j].radiance);
        filter_weight = &out.rads[j].filter_weight;
    }
    /* filter importance sampling (pixel_filter.h): the radiance fields are weighted by the
     * renderer once the record is complete (pixel_filter_weigh_record) */
    vec2 u_film = pixel_filter_sample(sc->pixel_filter, u_film01, filter_weight);
    *px_raster = (float)px->px + u_film.x;
    *py_raster = (float)px->py + u_film.y;
    if (!sc->sample_time) shutter_u = 0.0f;
    if (!out.radiance_only) {
        rec->px_raster = *px_raster, rec->py_raster = *py_raster;
        rec->lens_u = lens.x, rec->lens_v = lens.y;
        rec->time = shutter_u;
    }
    p->time01 = sc->sample_time ? shutter_time01(sc, shutter_u) : sc->time01_fixed;
}

/* Whether the first vertex's dimensions are drawn after the camera rays are traced, per
 * pixel with a first hit, as every later vertex's are (wave_integrate), rather than with the
 * camera's: where camera rays can leave the scene into a sky (an infinite light), a pixel
 * whose rays all miss then draws none; elsewhere nearly every pixel has a hit and the second
 * pass over the pixels' samplers would cost what it saves (docs/design.md 12.35). The
 * dimensions' values do not depend on when they are drawn. */
static inline bool first_dims_after_trace(const IntegratorScene *sc) { return sc->lights->infinite_count > 0; }

/* The camera samples of pixel k's samples first .. first + count - 1 (count <=
 * SAMPLER_RUN_MAX), paths j0 .., into the wave's camera batch, with their first vertex's
 * dimensions unless those come later (first_dims_after_trace). The rays themselves are
 * made for the whole wave at once (wave_integrate: camera_generate_rays), not per pixel: at 16
 * samples a pixel the batch's set-up cost as much as its 16 rays (issue 22's flatness). Each
 * ray is computed on its own, lane by lane, so the batch's length does not change its bits. */
WAVE_STAGE void wave_camera_samples(const IntegratorScene *sc, Wave *w, const WaveSampling *ws,
                                    const WavePixel *pixels, int k, int first, int count, int j0, WaveOut out)
{
    PixelSampler *s = wave_pixel_sampler(w, ws, pixels, k);
    sampler_run_begin(s, &w->run, first, count);
    vec2 *film = w->run_2d, *lens = w->run_2d_b;
    float *shutter = w->run_1d;
    sampler_run_2d(s, &w->run, 0, film);
    if (sc->sample_lens) sampler_run_2d(s, &w->run, 2, lens);
    if (sc->sample_time) sampler_run_1d(s, &w->run, sc->sample_lens ? 4 : 2, shutter);
    CameraBatch *cb = &w->camera;
    float *lens_u = cb->lens_u + j0, *lens_v = cb->lens_v + j0;
    if (sc->sample_lens) warp_disk_concentric_run(count, lens, lens_u, lens_v);
    else
        for (int i = 0; i < count; ++i) lens_u[i] = lens_v[i] = 0.0f;
    for (int i = 0; i < count; ++i) {
        WavePath *p = &w->path[j0 + i];
        p->pixel = k;
        p->sample_index = first + i;
        wave_camera_sample(sc, film[i], v2(lens_u[i], lens_v[i]), sc->sample_time ? shutter[i] : 0.0f, &pixels[k],
                           p, out, j0 + i, &cb->px[j0 + i], &cb->py[j0 + i]);
        w->cam_time01[j0 + i] = p->time01;
    }
    if (!first_dims_after_trace(sc)) wave_vertex_dims(sc, w, j0, 1);
}

/* Without infinite lights, and unless the filters record where it ends (the bounce
 * geometry: record_ray_geometry alone records only the shadow rays), a path's last ray
 * that misses the emitters' box finds no emission: its estimate is 0 without tracing it,
 * exactly as wave_vertex_fold computes it for a miss (light_bounds.c). Whether the stage at
 * `depth` asks that of its closest-hit rays (all of them are then last rays): */
static inline bool emitter_box_test(const IntegratorScene *sc, int depth)
{
    return depth == sc->max_depth && sc->lights->infinite_count == 0 &&
           !(depth == 1 && sc->record_ray_geometry && sc->record_bounce_geometry) && sc->lights->emitters_bounded;
}

/* Without area lights a surface emits nothing, so a path's last ray adds light only where it
 * escapes to the infinite lights (bsdf_ray_emission is +0 at any hit): whether it hits,
 * not where, is all the stage at `depth` needs of its closest-hit rays (all of them last
 * rays), unless the filters record where the first hit's bounce ends. Such rays are traced
 * as occlusion rays (any hit: the same answer as a closest hit's found, which Embree gives
 * for the same ray and geometry; no hit is shaded). */
static inline bool last_rays_escape_only(const IntegratorScene *sc, int depth)
{
    return depth == sc->max_depth && !sc->lights->has_area &&
           !(depth == 1 && sc->record_ray_geometry && sc->record_bounce_geometry);
}

/* Path p's lanes of the receivers (WaveReceivers), lane j, from its current vertex: written
 * whenever the path gets a vertex or ends (after wave_first_hit and wave_vertex_fold). */
static inline void receiver_to_lanes(WaveReceivers *rx, int j, const WavePath *p)
{
    rx->lambert[j] = p->alive && !p->v.glossy;
    if (!p->alive) return;
    const Vertex *v = &p->v;
    rx->p[0][j] = v->hit.p.x, rx->p[1][j] = v->hit.p.y, rx->p[2][j] = v->hit.p.z;
    rx->ng[0][j] = v->hit.ng.x, rx->ng[1][j] = v->hit.ng.y, rx->ng[2][j] = v->hit.ng.z;
    rx->err[j] = v->hit.err;
    if (v->glossy) return;
    rx->n[0][j] = v->n.x, rx->n[1][j] = v->n.y, rx->n[2][j] = v->n.z;
    rx->cos_o[j] = v->cos_o;
    rx->albedo[0][j] = v->albedo.x, rx->albedo[1][j] = v->albedo.y, rx->albedo[2][j] = v->albedo.z;
    rx->beta[0][j] = p->beta.x, rx->beta[1][j] = p->beta.y, rx->beta[2][j] = p->beta.z;
}

/* The bounces of the stage's Lambert vertices (lambert_uses_bsdf), lanes [0, n): their
 * directions from the BSDF dimensions' cosine-weighted directions (wave_vertex_dims), their
 * throughputs and their rays' origins. wave_vertex_rays reads a Lambert path's lane. */
static void wave_lambert_bounces(Wave *w, int n)
{
    const WaveReceivers *rx = &w->rx;
    WaveLambertBounces *b = &w->lb;
    LambertBounceIn in = {{rx->p[0], rx->p[1], rx->p[2]},
                          {rx->ng[0], rx->ng[1], rx->ng[2]},
                          rx->err,
                          {rx->n[0], rx->n[1], rx->n[2]},
                          rx->cos_o,
                          {rx->albedo[0], rx->albedo[1], rx->albedo[2]},
                          {rx->beta[0], rx->beta[1], rx->beta[2]},
                          {w->dim_cosine[0], w->dim_cosine[1], w->dim_cosine[2]},
                          rx->lambert};
    LambertBounceOut out = {{b->wi[0], b->wi[1], b->wi[2]},
                            b->pdf,
                            {b->beta_next[0], b->beta_next[1], b->beta_next[2]},
                            {b->o[0], b->o[1], b->o[2]},
                            b->sampled,
                            b->guarded,
                            b->bounce};
    lambert_bounce_lanes(n, &in, &out);
}

/* What the camera ray found: emission seen directly, the first hit's record fields (rec:
 * NULL for the radiance alone), and the path's first vertex. Out of line until the
 * twenty-first round (its call cost about 20 instructions a sample; the fourteenth round had
 * found it dearer inline, in the base build alone, which still holds: +0.4%). */
WAVE_STAGE void wave_first_hit(const IntegratorScene *sc, WavePath *p, vec3 d_world, bool found, const SurfaceHit *h,
                               SampleRecord *rec, SampleRadiance *R, IntegratorStats *st)
{
    p->alive = false;
    if (!found) {
        /* what record_reset leaves to this function: a miss's first-hit fields, unless
         * nothing reads them (render_reads.h) */
        if (rec && !sc->skip_first_hit_fields) {
            const vec3 zero = v3s(0.0f);
            rec->albedo = rec->albedo_diffuse = rec->albedo_glossy = zero;
            rec->phong_exponent = 0.0f;
            rec->unfilterable = false;
            rec->p_world = rec->n_shading = zero;
            rec->depth_cam = INFINITY;
            rec->object_id = -1;
        }
        /* without infinite lights the emission and L stay record_reset's +0 (the sum below
         * would be +0 and pass its guard) */
        if (sc->lights->infinite_count == 0) return;
        /* camera rays see infinite lights directly (no MIS: nothing else samples them) */
        vec3 env = v3s(0.0f);
        for (int k = 0; k < sc->lights->infinite_count; ++k)
            env = v3_add(env, infinite_light_L(sc->lights, sc->lights->infinite[k], d_world));
        R->emission = guard3(env, st); /* L follows at the wave's end */
        return;
    }
    Vertex *v = &p->v;
    make_vertex(sc, h, v3_neg(d_world), v);
    if (rec) rec->hit = true;
    /* fields only the G-buffer, the methods and the AOVs read: skipped when none of them
     * runs (render_reads.h; about 3% of a --filter none sample on soft_shadows) */
    if (rec && !sc->skip_first_hit_fields) {
        record_first_hit_material(v, rec);
        rec->p_world = h->p;
        /* towards the camera, any material (a Lambert vertex's n is already that) */
        rec->n_shading = v->glossy ? (v3_dot(h->ns, v->wo) < 0.0f ? v3_neg(h->ns) : h->ns) : v->n;
        rec->object_id = h->object_id;
        rec->depth_cam = camera_depth(sc->camera, h->p, p->time01);
    }
    if (rec && sc->record_motion) first_hit_motion(sc, h, p->time01, rec->motion_px);
    if (h->light >= 0) R->emission = guard3(area_light_L(sc->lights, h->light, h, v->wo), st);
    p->beta = v3s(1.0f);
    /* Light the filters must pass through unfiltered (sample_record.h): everything at a
     * dielectric first hit, and whatever arrives through a delta lobe of the first hit. */
    p->unfiltered = v->glossy && !glossy_is_filterable(&v->bsdf);
    p->alive = true;
}

/* A BSDF made of delta lobes only cannot be reached by a light sample: its vertex takes none. */
static inline bool vertex_lit(const Vertex *v) { return !(v->glossy && glossy_is_delta(&v->bsdf)); }


/* A Lambert receiver's response to one delta light in lane k of the loops below: what
 * light_prepare_sampled and its caller compute path by path (bsdf_diffuse_f: albedo / pi
 * where wi is on wo's side of n, else 0; the shadow ray sent where f and Li have a positive
 * channel, kept where its length is > 0), the same operations in the same order, branches
 * as selects: the value f Li |cos| (written whether or not the ray is kept) and whether the
 * ray is kept; *guarded: sent but of no length. on: the lane is a live Lambert receiver
 * with a sample of the light. */
static inline int lambert_delta_lane(const WaveReceivers *restrict rx, int k, int on, float wx, float wy, float wz,
                                     float lr, float lg, float lb, float len, WaveDeltaSamples *restrict ds,
                                     int *guarded)
{
    /* f on the lit side, albedo / pi, and !max_component_nonpositive of it and of Li */
    float fx = rx->albedo[0][k] * 0.318309886f, fy = rx->albedo[1][k] * 0.318309886f,
          fz = rx->albedo[2][k] * 0.318309886f;
    int f_sends = (fx > 0.0f) | (fy > 0.0f) | (fz > 0.0f) | (isnan(fx) & isnan(fy) & isnan(fz));
    int li_sends = (lr > 0.0f) | (lg > 0.0f) | (lb > 0.0f) | (isnan(lr) & isnan(lg) & isnan(lb));
    /* the side test of bsdf_diffuse_f (cos_o: v3_dot(n, wo), make_vertex's) */
    float cos_i = rx->n[0][k] * wx + rx->n[1][k] * wy + rx->n[2][k] * wz;
    int same_side = !(rx->cos_o[k] * cos_i <= 0.0f);
    float cos_abs = fabsf(cos_i);
    fx = same_side ? fx : 0.0f, fy = same_side ? fy : 0.0f, fz = same_side ? fz : 0.0f;
    ds->value[0][k] = fx * lr * cos_abs, ds->value[1][k] = fy * lg * cos_abs, ds->value[2][k] = fz * lb * cos_abs;
    int sends = on & same_side & f_sends & li_sends;
    int len_ok = len > 0.0f;
    *guarded = sends & !len_ok;
    return sends & len_ok;
}

/* The Lambert receivers' shares of a point or spot light (WaveDeltaSamples) over lanes
 * [0, count), from its samples and point_shadow_rays' rays: a ray left to shadow_ray_to
 * (redo) is wave_vertex_rays' to make. Adds the kept rays and the guarded events to
 * counts[0] and counts[1], and the Lambert lanes left to wave_vertex_rays to counts[2]. */
static WEDGE_VECTORISED void point_lambert_lanes(int count, const WaveReceivers *restrict rx,
                                                 WaveDeltaSamples *restrict ds, int counts[3])
{
    int rays = 0, guarded_all = 0, redone = 0;
    for (int k = 0; k < count; ++k) {
        int sampled = rx->lambert[k] & (ds->ok[k] != 0);
        int guarded;
        int kept = lambert_delta_lane(rx, k, sampled & !ds->redo[k], ds->wi[0][k], ds->wi[1][k], ds->wi[2][k],
                                      ds->Li[0][k], ds->Li[1][k], ds->Li[2][k], ds->len[k], ds, &guarded);
        ds->kept[k] = kept;
        ds->occluded[k] = false;
        rays += kept, guarded_all += guarded, redone += sampled & (ds->redo[k] != 0);
    }
    counts[0] += rays, counts[1] += guarded_all, counts[2] += redone;
}

/* A distant light's shadow rays from every lane [0, count) (surface_offset towards wi, along
 * wi, unbounded) and the Lambert receivers' shares of it (point_lambert_lanes' counts[0]
 * and [1]). sends: v3_any_positive(Li), without which light_sample gives no sample. */
static WEDGE_VECTORISED void distant_lambert_lanes(int count, const WaveReceivers *restrict rx, vec3 wi, vec3 Li,
                                                   int sends, WaveDeltaSamples *restrict ds, int counts[3])
{
    int rays = 0, guarded_all = 0;
    for (int k = 0; k < count; ++k) {
        float gx = rx->ng[0][k], gy = rx->ng[1][k], gz = rx->ng[2][k];
        float side = gx * wi.x + gy * wi.y + gz * wi.z >= 0.0f ? rx->err[k] : -rx->err[k];
        ds->o[0][k] = rx->p[0][k] + gx * side, ds->o[1][k] = rx->p[1][k] + gy * side,
        ds->o[2][k] = rx->p[2][k] + gz * side;
        ds->dir[0][k] = wi.x, ds->dir[1][k] = wi.y, ds->dir[2][k] = wi.z;
        ds->len[k] = INFINITY;
        int guarded;
        int kept = lambert_delta_lane(rx, k, rx->lambert[k] & sends, wi.x, wi.y, wi.z, Li.x, Li.y, Li.z, INFINITY, ds,
                                      &guarded);
        ds->kept[k] = kept;
        ds->occluded[k] = false;
        rays += kept, guarded_all += guarded;
    }
    counts[0] += rays, counts[1] += guarded_all;
}

/* Per lane [0, count), the sum of the unoccluded kept values of lights [0, lights), in the
 * lights' order (wave_vertex_fold's l_delta, which skipped the others): a lane not kept or
 * occluded adds +0, which leaves the sum as it is (a sum begun at +0 is never -0). */
static WEDGE_VECTORISED void delta_lanes_sum(int count, int lights, const WaveDeltaSamples *restrict ds,
                                             float (*restrict sum)[WAVE_SAMPLES])
{
    for (int k = 0; k < count; ++k) sum[0][k] = sum[1][k] = sum[2][k] = 0.0f;
    for (int l = 0; l < lights; ++l) {
        const float *restrict vx = ds[l].value[0], *restrict vy = ds[l].value[1], *restrict vz = ds[l].value[2];
        const int *restrict kept = ds[l].kept;
        /* the answers' bytes as unsigned char: GCC 12 vectorises no load of a bool array */
        const unsigned char *restrict occluded = (const unsigned char *)ds[l].occluded;
        float *restrict sx = sum[0], *restrict sy = sum[1], *restrict sz = sum[2];
        for (int k = 0; k < count; ++k) {
            float x = vx[k], y = vy[k], z = vz[k]; /* loaded in every lane, then selected */
            int on = kept[k] & (occluded[k] ^ 1);
            sx[k] += on ? x : 0.0f;
            sy[k] += on ? y : 0.0f;
            sz[k] += on ? z : 0.0f;
        }
    }
}


/* light_prepare_lambert_triangle and light_finish (unoccluded) for every lane of g, as one
 * loop GCC vectorises: bsdf_diffuse_f and bsdf_diffuse_pdf, the shadow ray's send and guard
 * tests, and the MIS-weighted estimate (Veach 1997, eq. 9.13, beta = 2: mis_power), with
 * the same operations in the same order as the scalar functions, branches as selects.
 * The estimate is read only where the ray is sent (send), so where the receiver faces the
 * light: there f and the pdf are the lit side's, which are taken in every lane
 * (a select between a product and 0 could trap in one arm, which stops the vectoriser).
 * Li: the light's radiance L, li_sends: !max_component_nonpositive(L); bsdf_mis 1, or 0
 * where the receivers take light sampling alone (lambert_light_only: the weight is then 1). */
static WEDGE_VECTORISED void lambert_triangle_nee(vec3 Li, int li_sends, float bsdf_mis, WaveTriangleSamples *restrict g)
{
    for (int k = 0; k < g->count; ++k) {
        float nx = g->n[0][k], ny = g->n[1][k], nz = g->n[2][k];
        /* f on the lit side */
        float cos_o = g->cos_o[k];
        float flx = g->albedo[0][k] * 0.318309886f, fly = g->albedo[1][k] * 0.318309886f,
              flz = g->albedo[2][k] * 0.318309886f;
        int f_nonpositive = !((flx > 0.0f) | (fly > 0.0f) | (flz > 0.0f)) & !(isnan(flx) & isnan(fly) & isnan(flz));
        /* the side test, f and the pdf */
        float cos_i = nx * g->wi[0][k] + ny * g->wi[1][k] + nz * g->wi[2][k];
        int same_side = !(cos_o * cos_i <= 0.0f);
        float cos_abs = fabsf(cos_i);
        float pdf_bsdf = cos_abs * 0.318309886f; /* the lit side's (see above) */
        int sends = (g->ok[k] != 0) & same_side & !f_nonpositive & li_sends;
        int len_ok = g->len[k] > 0.0f;
        g->send[k] = sends & len_ok;
        g->send_guarded[k] = sends & !len_ok;
        g->traced[k] = sends & len_ok & g->lambert[k] & !g->redo[k];
        /* light_finish: denom, mis_power(denom, pdf_bsdf), the scaled value and its guard3 */
        float denom = g->pmf[k] * g->pdf[k];
        float pdf_mis = pdf_bsdf * bsdf_mis; /* 0: light sampling alone (lambert_light_only) */
        float a = denom * denom, b = pdf_mis * pdf_mis;
        int a_inf = a == INFINITY; /* isinf of a square (never -inf) */
        int mis_trivial = a_inf | (a + b > 0.0f ? 0 : 1);
        float q = a / (a + b); /* computed in every lane, kept where mis_power divides */
        float w = mis_trivial ? (a_inf ? 1.0f : 0.0f) : q;
        float scale = cos_abs * w / denom;
        float vx = flx * Li.x * scale, vy = fly * Li.y * scale, vz = flz * Li.z * scale;
        float z = vx * 0.0f + vy * 0.0f + vz * 0.0f; /* finite3 */
        g->nee[0][k] = vx, g->nee[1][k] = vy, g->nee[2][k] = vz;
        g->nee_guarded[k] = (denom > 0.0f ? 0 : 1) | (z == z ? 0 : 1);
    }
}

/* The picks of the stage's live, lit paths (what light_prepare would find), and the samples
 * of the picked static triangle lights, per light in one vectorised loop each (up to
 * WAVE_TRIANGLE_GROUPS lights; a path that picks another samples it on its own). */
WAVE_STAGE void wave_triangle_light_samples(const IntegratorScene *sc, Wave *w, int n, int depth)
{
    const LightSet *L = sc->lights;
    float bsdf_mis = lambert_light_only(sc, depth) ? 0.0f : 1.0f;
    w->tri_groups = 0;
    /* Nothing to pick (wave_vertex_dims drew no pick): wave_vertex_rays then reads neither
     * the pick nor tri_group, so the pass over the paths is skipped. */
    if (!vertex_uses_light_dims(sc, depth)) return;
    /* One emitting mesh lights the scene: every lane's choice in vectorised loops first
     * (lights_choose_sole_mesh_batch, bit for bit lights_choose's), where one at a time the
     * choice's chain of dependent loads was the longest per-path cost */
    int pick_index[WAVE_SAMPLES], pick_regular[WAVE_SAMPLES];
    float pick_ux[WAVE_SAMPLES], pick_pmf[WAVE_SAMPLES];
    bool sole_mesh = L->sole_mesh_end > 0;
    if (sole_mesh)
        lights_choose_sole_mesh_batch(L, n, w->dim_pick, w->dim_light, pick_index, pick_ux, pick_pmf, pick_regular);
    /* The groups' keys, and the group a key last went to by its low bits (-1: none): which of
     * a quad's two triangles a path picks is a coin flip, on which a search from the first
     * group stopping at the match branched, mispredicted half the time; the remembered group
     * is checked (the same answer: each key has at most one group) and nearly always right */
    int group_light[WAVE_TRIANGLE_GROUPS], group_mesh[WAVE_TRIANGLE_GROUPS], last_group[GROUP_SLOTS];
    for (int q = 0; q < GROUP_SLOTS; ++q) last_group[q] = -1;
    for (int j = 0; j < n; ++j) {
        WavePath *p = &w->path[j];
        p->tri_group = -1;
        if (!p->alive || !vertex_lit(&p->v)) continue;
        VertexDims *u = &p->u;
        float pmf = 0.0f;
        bool static_triangle = false;
        u->light_uv = w->dim_light[j];
        if (sole_mesh && pick_regular[j]) {
            u->light_index = pick_index[j];
            u->light_uv.x = pick_ux[j];
            pmf = pick_pmf[j];
            static_triangle = L->choice[pick_index[j]].static_triangle;
        } else {
            u->light_index = lights_choose(L, w->dim_pick[j], &u->light_uv, &pmf, &static_triangle);
        }
        u->light_pmf = pmf;
        if (u->light_index < 0) continue;
        /* the sky from the bounce ray alone: no light sample here (light_prepare finds none) */
        if (sky_by_bsdf_alone(sc, &p->v, u->light_index, depth)) {
            u->light_index = -1;
            continue;
        }
        /* a static triangle, or else a constant sky (the group's kind, below) */
        if (!static_triangle && !light_is_constant_sky(&L->lights[u->light_index])) continue;
        /* the triangles of a large emitting mesh share a group (keyed by its run's first
         * light), where they share what the group reads of its light (radiance, shadow mask):
         * with each triangle a light of its own a mesh of hundreds scattered the wave's lanes
         * over more groups than it keeps, and they took the scalar path. A mesh of a few
         * triangles (a quad's two) keeps a group a triangle, whose loops take the triangle's
         * vertices as constants (vectorised; the mesh's lanes load their own) */
        int key = u->light_index;
        bool mesh = false;
        if (static_triangle) {
            const LightChoice *c = &L->choice[u->light_index];
            mesh = c->mesh_end - c->mesh_first > WAVE_TRIANGLE_GROUPS / 2 && c->batches_with_run;
            if (mesh) key = c->mesh_first;
        }
        int slot = key & (GROUP_SLOTS - 1), g = last_group[slot];
        if (!(g >= 0 && group_light[g] == key && group_mesh[g] == (int)mesh)) {
            g = 0;
            while (g < w->tri_groups && !(group_light[g] == key && group_mesh[g] == (int)mesh)) ++g;
            if (g == w->tri_groups) {
                if (g == WAVE_TRIANGLE_GROUPS) continue;
                w->tri[g].light = key, w->tri[g].count = 0, w->tri[g].sky = !static_triangle, w->tri[g].mesh = mesh;
                group_light[g] = key, group_mesh[g] = mesh;
                ++w->tri_groups;
            }
            last_group[slot] = g;
        }
        WaveTriangleSamples *t = &w->tri[g];
        int k = t->count++;
        t->tri[k] = u->light_index;
        const SurfaceHit *h = &p->v.hit;
        t->p[0][k] = h->p.x, t->p[1][k] = h->p.y, t->p[2][k] = h->p.z;
        t->ng[0][k] = h->ng.x, t->ng[1][k] = h->ng.y, t->ng[2][k] = h->ng.z;
        t->err[k] = h->err;
        t->u[0][k] = u->light_uv.x, t->u[1][k] = u->light_uv.y;
        const Vertex *v = &p->v;
        t->n[0][k] = v->n.x, t->n[1][k] = v->n.y, t->n[2][k] = v->n.z;
        t->cos_o[k] = v->cos_o;
        t->lambert[k] = !v->glossy;
        t->time01[k] = p->time01;
        t->albedo[0][k] = v->albedo.x, t->albedo[1][k] = v->albedo.y, t->albedo[2][k] = v->albedo.z;
        t->pmf[k] = pmf;
        p->tri_group = g, p->tri_lane = k;
    }
    for (int g = 0; g < w->tri_groups; ++g) {
        WaveTriangleSamples *t = &w->tri[g];
        const Light *l = &L->lights[t->light];
        const float *pos[3] = {t->p[0], t->p[1], t->p[2]}, *uv[2] = {t->u[0], t->u[1]};
        if (t->sky) {
            /* light_sample's constant sky: the same pdf and outcome in every lane */
            float *wi[3] = {t->wi[0], t->wi[1], t->wi[2]};
            light_sample_sky_batch(t->count, uv, wi);
            int sends = v3_any_positive(l->L);
            for (int k = 0; k < t->count; ++k) t->pdf[k] = LIGHT_SKY_PDF, t->ok[k] = sends;
            /* a Lambert receiver's by cosine (sky_by_cosine) */
            const float *n[3] = {t->n[0], t->n[1], t->n[2]};
            if (t->light == L->sky_cosine_light) light_sky_cosine_batch(t->count, n, t->lambert, wi, t->pdf, t->ok);
            t->rays_ahead = true;
            sky_shadow_rays(t);
            lambert_triangle_nee(l->L, !max_component_nonpositive(l->L), bsdf_mis, t);
            continue;
        }
        TriangleSampleBatch out = {{t->wi[0], t->wi[1], t->wi[2]}, t->dist, {t->pl[0], t->pl[1], t->pl[2]}, t->pdf, t->ok};
        if (t->mesh) {
            light_sample_triangles_batch(L->lights, t->tri, t->count, pos, uv, &out);
            t->rays_ahead = true;
            mesh_shadow_rays(L->lights, t);
            lambert_triangle_nee(l->L, !max_component_nonpositive(l->L), bsdf_mis, t);
            continue;
        }
        light_sample_triangle_batch(l, t->count, pos, uv, &out);
        t->rays_ahead = light_triangle_rays_ahead(l);
        if (t->rays_ahead) {
            triangle_shadow_rays(l->tri_n, l->tri_err, t);
            lambert_triangle_nee(l->L, !max_component_nonpositive(l->L), bsdf_mis, t);
        } else {
            for (int k = 0; k < t->count; ++k) t->redo[k] = 1; /* no offset at the light: shadow_ray_to */
        }
    }
}

/* The shadow rays of the groups' Lambert receivers (WaveTriangleSamples.traced), traced
 * from the lanes where triangle_shadow_rays or sky_shadow_rays made them, in the lanes'
 * order: an occlusion answer is an any-hit question about one ray, which its place in the
 * batch does not change (docs/design.md 12.18). recorded: the triangle groups' rays are
 * recorded for the filters (wave_vertex_rays put them in the recorded batch), a sky's are
 * not. */
static void wave_triangle_occlusion(const IntegratorScene *sc, Wave *w, bool recorded)
{
    for (int g = 0; g < w->tri_groups; ++g) {
        WaveTriangleSamples *t = &w->tri[g];
        if (!t->rays_ahead || (recorded && !t->sky)) continue;
        TracerRayArrays a = {{t->o[0], t->o[1], t->o[2]},
                             {t->dir[0], t->dir[1], t->dir[2]},
                             t->len,
                             t->time01,
                             t->traced,
                             sc->lights->lights[t->light].shadow_skip_mask};
        /* a sky's rays are cosine-distributed from scattered receivers: incoherent (Embree's
         * packets, tracer.c packets_of_16); a triangle light's converge on it */
        tracer_occluded_arrays(sc->tracer, &a, t->count, !t->sky, t->occluded);
    }
}

/* The delta lights lit at every vertex (LightSet.delta_every) at the stage's n paths, light
 * by light in vectorised loops over every path's lane (WaveDeltaSamples): a point or spot
 * light's samples (light_sample_point_batch: the same values light_sample gives path by
 * path) and shadow rays, a distant light's shadow rays, and the Lambert receivers' kept rays
 * and values, with their counters. What the loops leave to wave_vertex_rays (glossy
 * receivers, rays to redo) it does path by path; w->delta_redo says whether a Lambert
 * receiver has such a ray. */
WAVE_STAGE void wave_delta_light_samples(const IntegratorScene *sc, Wave *w, int n, IntegratorStats *st)
{
    const LightSet *L = sc->lights;
    const WaveReceivers *rx = &w->rx;
    const float *pos[3] = {rx->p[0], rx->p[1], rx->p[2]};
    int counts[3] = {0, 0, 0};
    for (int k = 0; k < L->delta_every_count; ++k) {
        const Light *light = &L->lights[L->delta_every[k]];
        WaveDeltaSamples *ds = &w->delta[k];
        int kept_before = counts[0];
        if (light->kind == LIGHT_POINT || light->kind == LIGHT_SPOT) {
            LightSampleBatch out = {{ds->wi[0], ds->wi[1], ds->wi[2]}, ds->dist, {ds->Li[0], ds->Li[1], ds->Li[2]}, ds->ok};
            light_sample_point_batch(light, n, pos, &out);
            ds->err_light = light_delta_offset(light);
            point_shadow_rays(n, rx->p, rx->ng, rx->err, light->p_world, ds);
            point_lambert_lanes(n, rx, ds, counts);
        } else if (light->kind == LIGHT_DISTANT) {
            distant_lambert_lanes(n, rx, light->w_world, light->L, v3_any_positive(light->L), ds, counts);
        } else {
            /* another kind: every receiver path by path */
            for (int j = 0; j < n; ++j) ds->kept[j] = 0;
            counts[2] += 1;
        }
        ds->kept_count = counts[0] - kept_before;
    }
    if (sc->delta_lights_by_path) {
        /* the reference: no lane kept, every receiver's rays made by wave_vertex_rays */
        for (int k = 0; k < L->delta_every_count; ++k) {
            for (int j = 0; j < n; ++j) w->delta[k].kept[j] = 0;
            w->delta[k].kept_count = 0;
        }
        counts[0] = counts[1] = 0, counts[2] = 1;
    }
    st->rays_shadow += (long long)counts[0];
    st->guarded_events += (long long)counts[1];
    w->delta_redo = counts[2] > 0;
    w->delta_fixes = 0;
}

/* The delta lights' rays kept in the lanes (WaveDeltaSamples.kept), traced from them light by
 * light, then the answers of the rays wave_vertex_rays made path by path copied into their
 * lanes, which are then kept: every lane's answer where wave_vertex_fold reads it. An
 * occlusion answer does not depend on the ray's place in a batch (docs/design.md 12.18). */
static void wave_delta_occlusion(const IntegratorScene *sc, Wave *w, int n)
{
    const LightSet *L = sc->lights;
    for (int k = 0; k < L->delta_every_count; ++k) {
        WaveDeltaSamples *ds = &w->delta[k];
        const Light *light = &L->lights[L->delta_every[k]];
        if (ds->kept_count == 0) continue; /* (a light of another kind keeps none) */
        TracerRayArrays a = {{ds->o[0], ds->o[1], ds->o[2]}, {ds->dir[0], ds->dir[1], ds->dir[2]}, ds->len,
                             w->cam_time01, ds->kept, light->shadow_skip_mask};
        tracer_occluded_arrays(sc->tracer, &a, n, true, ds->occluded);
    }
    for (int i = 0; i < w->delta_fixes; ++i) {
        WaveDeltaSamples *ds = &w->delta[w->delta_fix_light[i]];
        int j = w->delta_fix_path[i];
        ds->kept[j] = 1;
        ds->occluded[j] = w->occluded[w->delta_fix_ray[i]];
    }
}

/* First half of next-event estimation for path p: a point on the light its dimensions
 * picked (wave_triangle_light_samples, which also sampled a static triangle) and the
 * shadow ray, into p->lp. */
WAVE_STAGE bool light_prepare(const IntegratorScene *sc, const Wave *w, WavePath *p, IntegratorStats *st,
                              TracerRay *shadow)
{
    const VertexDims *u = &p->u;
    if (u->light_index < 0) return false;
    if (p->tri_group < 0)
        return light_prepare_at(sc, &p->v, p->time01, u->light_index, u->light_uv, u->light_pmf, st, shadow, &p->lp);
    const WaveTriangleSamples *g = &w->tri[p->tri_group];
    int k = p->tri_lane;
    if (!g->ok[k]) return false;
    const Light *l = &sc->lights->lights[u->light_index];
    if (g->sky) {
        /* light_sample's constant sky at the receiver */
        vec3 wi = v3(g->wi[0][k], g->wi[1][k], g->wi[2][k]);
        p->lp.ls = (LightSample){wi,   INFINITY, v3_madd(p->v.hit.p, wi, 2.0f * sc->lights->scene_radius),
                                 v3_neg(wi), 0.0f, l->L, g->pdf[k], false};
    } else {
        p->lp.ls = (LightSample){v3(g->wi[0][k], g->wi[1][k], g->wi[2][k]), g->dist[k],
                                 v3(g->pl[0][k], g->pl[1][k], g->pl[2][k]), l->tri_n, l->tri_err, l->L, g->pdf[k], false};
    }
    ShadowRayAhead ahead = {v3(g->o[0][k], g->o[1][k], g->o[2][k]), v3(g->dir[0][k], g->dir[1][k], g->dir[2][k]),
                            g->len[k], g->redo[k] != 0};
    return light_prepare_sampled(sc, &p->v, p->time01, u->light_index, u->light_pmf, &ahead, st, shadow, &p->lp);
}

/* light_prepare for a Lambert receiver of a picked static triangle whose shadow ray was
 * computed ahead (not `redo`) and is recorded for the filters (the others are traced from the
 * lanes: wave_triangle_occlusion), from its lane of the group, where lambert_triangle_nee
 * found whether it is sent and its estimate: *shadow is written whether or not the sample
 * is kept, so that whether the receiver faces the light and the light faces it (one-sided
 * emitters; on a receiver beside the light a coin toss) is not a branch. The same tests
 * and counters as light_prepare_sampled; wave_vertex_fold reads the lane (light_valued). */
static inline int light_send_lambert_triangle(const IntegratorScene *sc, const Wave *w, const WavePath *p,
                                              IntegratorStats *st, TracerRay *shadow)
{
    const WaveTriangleSamples *g = &w->tri[p->tri_group];
    int k = p->tri_lane;
    /* field by field into the batch's slot: a TracerRay built on the stack and copied was
     * read back as 16-byte words over narrower stores, a stalled store forward per ray */
    shadow->o = v3(g->o[0][k], g->o[1][k], g->o[2][k]);
    shadow->d = v3(g->dir[0][k], g->dir[1][k], g->dir[2][k]);
    shadow->tmax = g->len[k];
    shadow->time01 = p->time01;
    shadow->skip_mask = sc->lights->lights[g->light].shadow_skip_mask;
    st->guarded_events += g->send_guarded[k];
    st->rays_shadow += g->send[k];
    return g->send[k];
}

/* The rules of a stage at one depth, the same for every path: found once a stage and handed
 * to wave_vertex_rays (each is a few loads through sc and sc->lights, which the per-path
 * loop cannot hoist past its stores). */
typedef struct {
    bool light_only; /* lambert_light_only */
    bool picks;      /* vertex_uses_light_dims */
    bool bsdf_dims;  /* vertex_uses_bsdf_dims */
    bool box_test;   /* emitter_box_test */
} StageRules;

static inline StageRules stage_rules(const IntegratorScene *sc, int depth)
{
    return (StageRules){lambert_light_only(sc, depth), vertex_uses_light_dims(sc, depth),
                        vertex_uses_bsdf_dims(sc, depth), emitter_box_test(sc, depth)};
}

/* Stage one of a vertex: its light sample's shadow ray and its BSDF-sampled bounce ray
 * (independent of each other), queued for the batches. Inlined into its one caller: the
 * call's eleven arguments and large frame cost about 100 instructions per indirect sample. */
static inline __attribute__((always_inline)) void wave_vertex_rays(const IntegratorScene *sc, Wave *w,
                                                                   const WaveSampling *ws, const WavePixel *pixels,
                                                                   int j, int depth, StageRules rules,
                                                                   SampleRecord *rec, IntegratorStats *st, int *n_occ,
                                                                   int *n_rec, int *n_hit)
{
    WavePath *p = &w->path[j];
    const Vertex *v = &p->v;
    const LightSet *L = sc->lights;
    TracerRay shadow;
    bool lit = vertex_lit(v);
    bool light_only = rules.light_only;
    p->light_recorded = false;
    /* with nothing to pick, the vertex takes no picked light's sample (its pick and
     * tri_group were not set: wave_triangle_light_samples) */
    bool picks = rules.picks;
    bool valued = picks && lit && !v->glossy && p->tri_group >= 0 && !w->tri[p->tri_group].redo[p->tri_lane];
    p->light_valued = valued;
    if (valued) {
        /* A recorded ray (the first hit's to an area light, for the filters:
         * rec->shadow_count is 0 there) is written to the slot it would take and the count
         * moves by the outcome; any other is traced from its group's lanes
         * (wave_triangle_occlusion), a sky's always (it is no area light). */
        bool record = depth == 1 && sc->record_ray_geometry && !w->tri[p->tri_group].sky;
        if (record) {
            p->shadow_ray = *n_rec;
            int kept = light_send_lambert_triangle(sc, w, p, st, &w->ray_rec[p->shadow_ray]);
            *n_rec += kept;
            p->light_pending = kept;
            p->light_recorded = kept;
        } else {
            const WaveTriangleSamples *g = &w->tri[p->tri_group];
            int lane = p->tri_lane;
            st->guarded_events += g->send_guarded[lane];
            st->rays_shadow += g->send[lane];
            p->light_pending = g->send[lane];
        }
    } else {
        p->light_pending = picks && lit && light_prepare(sc, w, p, st, &shadow);
        /* light sampling alone: mis_power(denom, 0) is 1 */
        if (light_only && !v->glossy) p->lp.pdf_bsdf = 0.0f;
    }
    if (p->light_pending && !valued) {
        /* the first hit's shadow rays to area lights are recorded for the filters, with the
         * distance to their occluder: traced for the closest hit instead of any hit */
        bool record = depth == 1 && sc->record_ray_geometry && p->lp.is_area && rec->shadow_count < SAMPLE_RECORD_MAX_SHADOW;
        p->light_recorded = record;
        if (record) {
            p->shadow_ray = (*n_rec)++;
            w->ray_rec[p->shadow_ray] = shadow;
        } else {
            p->shadow_ray = (*n_occ)++;
            w->ray_occ[p->shadow_ray] = shadow;
        }
    }
    /* Delta lights lit at every vertex: probability 1, no MIS (BSDF sampling never finds
     * them); the light dimensions go unused (a point has no area). A Lambert receiver's are
     * its lanes' (wave_delta_light_samples), unless a ray of its is left to shadow_ray_to
     * (redo) or the light is of another kind; the others are made here, their rays queued in
     * the occlusion batch and their values and answers put in their lanes
     * (wave_delta_occlusion). */
    bool by_path = lit && (v->glossy || w->delta_redo);
    for (int k = 0; by_path && k < L->delta_every_count; ++k) {
        LightPending lp;
        int li = L->delta_every[k];
        const Light *light = &L->lights[li];
        WaveDeltaSamples *ds = &w->delta[k];
        bool point = light->kind == LIGHT_POINT || light->kind == LIGHT_SPOT;
        bool lane = !v->glossy && (light->kind == LIGHT_DISTANT || (point && !ds->redo[j]));
        if (lane && !sc->delta_lights_by_path) continue; /* the lane's */
        bool prepared;
        if (point) {
            /* sampled for the whole stage by wave_delta_light_samples */
            if (!ds->ok[j]) continue;
            lp.ls = (LightSample){v3(ds->wi[0][j], ds->wi[1][j], ds->wi[2][j]), ds->dist[j], light->p_world, v3s(0.0f),
                                  ds->err_light, v3(ds->Li[0][j], ds->Li[1][j], ds->Li[2][j]), 1.0f, true};
            ShadowRayAhead ahead = {v3(ds->o[0][j], ds->o[1][j], ds->o[2][j]),
                                    v3(ds->dir[0][j], ds->dir[1][j], ds->dir[2][j]), ds->len[j], ds->redo[j] != 0};
            prepared = light_prepare_sampled(sc, v, p->time01, li, 1.0f, &ahead, st, &w->ray_occ[*n_occ], &lp);
        } else {
            prepared = light_prepare_at(sc, v, p->time01, li, v2(0.5f, 0.5f), 1.0f, st, &w->ray_occ[*n_occ], &lp);
        }
        if (!prepared) continue;
        vec3 value = v3_scale(v3_mul(lp.f, lp.ls.Li), lp.cos_i);
        ds->value[0][j] = value.x, ds->value[1][j] = value.y, ds->value[2][j] = value.z;
        int f = w->delta_fixes++;
        w->delta_fix_ray[f] = (*n_occ)++, w->delta_fix_light[f] = k, w->delta_fix_path[f] = j;
    }
    p->unfiltered_light = p->unfiltered;
    p->bounce = false;

    if (!rules.bsdf_dims || (light_only && !v->glossy)) return;
    bool box_test = rules.box_test; /* glossy last rays (Lambert ones: lambert_light_only) */
    vec3 o;
    if (v->glossy) {
        float u_lobe = sampler_1d_at(wave_sampler(w, ws, pixels, p->pixel, p->sample_index), vertex_dim0(sc, depth) + 3);
        if (!glossy_vertex_sample(v, u_lobe, w->dim_bsdf[j], &p->vs)) return;
        p->beta_next = guard3(v3_mul(p->beta, p->vs.weight), st);
        if (max_component_nonpositive(p->beta_next)) return;
        if (depth == 1 && p->vs.delta) p->unfiltered = true;
        o = surface_offset(&v->hit, p->vs.wi);
    } else {
        /* the lane wave_lambert_bounces sampled (what the path reads of vs: wi, pdf, delta) */
        const WaveLambertBounces *b = &w->lb;
        if (!b->sampled[j]) return;
        st->guarded_events += b->guarded[j];
        if (!b->bounce[j]) return;
        p->vs.wi = v3(b->wi[0][j], b->wi[1][j], b->wi[2][j]);
        p->vs.pdf = b->pdf[j];
        p->vs.delta = false;
        p->beta_next = v3(b->beta_next[0][j], b->beta_next[1][j], b->beta_next[2][j]);
        o = v3(b->o[0][j], b->o[1][j], b->o[2][j]);
    }
    if (box_test) {
        /* a glossy last ray: sampled, weighed and guarded as ever, and queued for the test,
         * which writes its ray if it keeps it */
        p->bounce = true;
        int k = (*n_hit)++;
        w->box_o[0][k] = o.x, w->box_o[1][k] = o.y, w->box_o[2][k] = o.z;
        w->box_d[0][k] = p->vs.wi.x, w->box_d[1][k] = p->vs.wi.y, w->box_d[2][k] = p->vs.wi.z;
        w->box_path[k] = j;
        return;
    }
    p->bounce = true;
    /* The last ray of a path only finds emitters for MIS of direct light; the others carry
     * the path on (reported apart: a maxdepth 1 scene traces no bounce ray). */
    if (depth < sc->max_depth) ++st->rays_indirect;
    else ++st->rays_bsdf;
    p->hit_slot = (*n_hit)++;
    /* field by field into the batch's slot (as light_send_lambert_triangle's shadow rays) */
    TracerRay *ray = &w->ray_hit[p->hit_slot];
    ray->o = o;
    ray->d = p->vs.wi;
    ray->tmax = INFINITY;
    ray->time01 = p->time01;
    ray->skip_mask = 0u;
}

/* The box test for the stage's n_hit queued last rays at once (lights_rays_may_reach_emitter,
 * one vectorised loop, instead of a call per ray), then, for the rays it keeps, in the
 * paths' order, their ray at slot [0, count). Returns count. The queued rays were sampled,
 * weighed and guarded, with bounce set: glossy ones, and Lambert ones only where light
 * sampling alone does not hold (lambert_light_only: LightSet.area_sampling_complete false).
 * A dropped ray's path loses bounce, which wave_vertex_fold ends as a traced ray that found
 * nothing (no emission, no infinite light: nothing added). */
static int wave_emitter_box_test(const IntegratorScene *sc, Wave *w, int n_hit, IntegratorStats *st)
{
    const float *o[3] = {w->box_o[0], w->box_o[1], w->box_o[2]}, *d[3] = {w->box_d[0], w->box_d[1], w->box_d[2]};
    lights_rays_may_reach_emitter(sc->lights, n_hit, o, d, w->box_may);
    int count = 0;
    for (int k = 0; k < n_hit; ++k) {
        WavePath *p = &w->path[w->box_path[k]];
        if (!w->box_may[k]) {
            p->bounce = false;
            continue;
        }
        vec3 wi = v3(d[0][k], d[1][k], d[2][k]);
        w->ray_hit[count] = (TracerRay){v3(o[0][k], o[1][k], o[2][k]), wi, INFINITY, p->time01, 0u};
        p->hit_slot = count++;
    }
    st->rays_bsdf += count;
    st->rays_bsdf_skipped += n_hit - count;
    return count;
}

/* Path j's unoccluded delta-light values summed one by one: delta_lanes_sum's reference
 * (IntegratorScene.delta_lights_by_path). */
static vec3 delta_sum_by_path(const Wave *w, int lights, int j)
{
    vec3 sum = v3s(0.0f);
    for (int k = 0; k < lights; ++k) {
        const WaveDeltaSamples *ds = &w->delta[k];
        if (ds->kept[j] && !ds->occluded[j]) sum = v3_add(sum, v3(ds->value[0][j], ds->value[1][j], ds->value[2][j]));
    }
    return sum;
}

/* The sum of path p's unoccluded delta-light values, each guarded (guard3). Its caller adds
 * them unguarded and comes here only when that sum is not finite: a non-finite value makes
 * the sum non-finite (inf and NaN absorb finite terms), and a sum of finite values equals
 * the guarded sum, so the result and the count of guarded events are the same either way
 * (one finite test a vertex instead of one per value). */
static vec3 delta_sum_guarded(const Wave *w, int lights, int j, IntegratorStats *st)
{
    vec3 sum = v3s(0.0f);
    for (int k = 0; k < lights; ++k) {
        const WaveDeltaSamples *ds = &w->delta[k];
        if (ds->kept[j] && !ds->occluded[j])
            sum = v3_add(sum, guard3(v3(ds->value[0][j], ds->value[1][j], ds->value[2][j]), st));
    }
    return sum;
}

/* The glossy lobes' part of a glossy first hit's unoccluded light sample (its estimate
 * non-zero), added to SampleRecord.direct_glossy. Out of line, as record_glossy_bsdf: a
 * Lambert hit never calls them, and inline they cost every sample of a filtered frame. */
static __attribute__((noinline)) void record_glossy_light(const WavePath *p, SampleRecord *rec)
{
    vec3 part = light_finish_part(&p->lp, glossy_share(&p->v, p->lp.ls.wi, p->lp.f));
    rec->direct_glossy = v3_add(rec->direct_glossy, v3_mul(p->beta, part));
}

/* The glossy lobes' part of a glossy first hit's BSDF sample that found emission e (MIS
 * weighted): the sample's weight f |cos| / pdf less the diffuse lobe's f_d |cos| / pdf, times e. */
static __attribute__((noinline)) void record_glossy_bsdf(const WavePath *p, vec3 e, SampleRecord *rec, IntegratorStats *st)
{
    const Vertex *v = &p->v;
    vec3 wl = to_local(v, p->vs.wi);
    vec3 wd = v3_scale(glossy_f_diffuse(&v->bsdf, v->wo_l, wl), fabsf(wl.z) / p->vs.pdf);
    vec3 wg = v3(fmaxf(p->vs.weight.x - wd.x, 0.0f), fmaxf(p->vs.weight.y - wd.y, 0.0f), fmaxf(p->vs.weight.z - wd.z, 0.0f));
    rec->direct_glossy = v3_add(rec->direct_glossy, guard3(v3_mul(v3_mul(p->beta, wg), e), st));
}

/* Stage two of a vertex, after the batches: its light and the emission its bounce ray
 * found, added to the radiance R (and to the record rec, NULL for the radiance alone), and
 * the next vertex (or the end of the path). */
WAVE_STAGE void wave_vertex_fold(const IntegratorScene *sc, Wave *w, int j, int depth, SampleRecord *rec,
                                 SampleRadiance *R, IntegratorStats *st)
{
    WavePath *p = &w->path[j];
    vec3 *bucket = depth == 1 ? &R->direct : &R->indirect;
    vec3 l_light = v3s(0.0f);
    if (p->light_pending) {
        bool occluded;
        /* a Lambert receiver's triangle sample: its group's lane (lambert_triangle_nee) */
        const WaveTriangleSamples *g = p->light_valued ? &w->tri[p->tri_group] : NULL;
        int lane = p->tri_lane;
        if (p->light_recorded) {
            int k = p->shadow_ray;
            occluded = w->rec_found[k];
            ShadowRayRecord *r = &rec->shadow[rec->shadow_count++];
            r->d_light_world = g ? g->dist[lane] : p->lp.ls.dist;
            r->d_occluder_world = occluded ? w->rec_hit[k].t : INFINITY;
            r->light_p_world = g ? v3(g->pl[0][lane], g->pl[1][lane], g->pl[2][lane]) : p->lp.ls.p_light;
            r->light_index = g ? g->tri[lane] : p->lp.light;
        } else {
            occluded = g ? g->occluded[lane] : w->occluded[p->shadow_ray];
        }
        if (!g) {
            l_light = light_finish(&p->lp, occluded, st);
        } else if (!occluded) {
            /* light_finish's value, or its guarded event and 0 */
            if (g->nee_guarded[lane]) ++st->guarded_events;
            else l_light = v3(g->nee[0][lane], g->nee[1][lane], g->nee[2][lane]);
        }
    }
    vec3 l_delta = v3s(0.0f);
    int lights = sc->lights->delta_every_count;
    if (lights > 0) {
        l_delta = sc->delta_lights_by_path ? delta_sum_by_path(w, lights, j)
                                           : v3(w->delta_sum[0][j], w->delta_sum[1][j], w->delta_sum[2][j]);
        if (!finite3(l_delta)) l_delta = delta_sum_guarded(w, lights, j, st);
    }
    vec3 ld = v3_mul(p->beta, l_light), ld_delta = v3_mul(p->beta, l_delta);
    *bucket = v3_add(*bucket, v3_add(ld, ld_delta));
    /* A point, spot or distant light casts hard shadows: in a scene with area lights, whose
     * direct light the soft-shadow filters take, its share of the direct light must not be
     * blurred with theirs (on motion_defocus_soft, a sphere light beside a distant light,
     * AAF's shadows had 30x Monte Carlo's error at 64 spp, static and pinhole). Without
     * area lights no filter takes direct light and nothing needs to be set apart. */
    if (sc->skip_first_hit_fields) {
        /* only the methods read the unfiltered parts (render_reads.h) */
    } else if (p->unfiltered_light) {
        rec->unfiltered = v3_add(rec->unfiltered, v3_add(ld, ld_delta));
    } else if (depth == 1) {
        if (sc->lights->has_area) {
            if (p->light_pending && !p->light_valued && p->lp.ls.delta) rec->unfiltered_direct = v3_add(rec->unfiltered_direct, ld);
            rec->unfiltered_direct = v3_add(rec->unfiltered_direct, ld_delta);
        }
        /* the light sample's glossy lobes' part (SampleRecord.direct_glossy): a glossy
         * receiver's only (a valued triangle sample's receiver is Lambert), a delta light's
         * being in unfiltered_direct already where a filter takes direct light. Finite: f_g is
         * at most f, so each channel is at most l_light's (finite, guarded); the BSDF part is
         * guarded below, so direct_glossy needs no guard of its own at the wave's end */
        if (p->v.glossy && p->light_pending && !p->light_valued && !p->lp.ls.delta && !max_component_nonpositive(l_light))
            record_glossy_light(p, rec);
    }
    p->alive = false;
    /* no bounce: none sampled, or a last ray the emitter-box test dropped, which would have
     * found nothing (wave_emitter_box_test) and so added nothing below */
    if (!p->bounce) return;

    bool hit = w->hit_found[p->hit_slot];
    const SurfaceHit *nh = hit ? &w->hit[p->hit_slot] : NULL;
    vec3 wi = p->vs.wi;
    if (depth == 1 && sc->record_ray_geometry && sc->record_bounce_geometry && rec->bounce_count < SAMPLE_RECORD_MAX_BOUNCE) {
        BounceRayRecord *b = &rec->bounce[rec->bounce_count++];
        b->d_hit_world = hit ? nh->t : INFINITY;
        b->dir_world = wi;
    }
    /* A ray that found nothing, without infinite lights: bsdf_ray_emission is +0, so le is a zero
     * (beta_next is finite, guarded above) and adding it changes no sum (a sum begun at +0
     * is never -0). Nothing to add, no guard, and such a path ends here either way. */
    if (!hit && sc->lights->infinite_count == 0) return;
    /* A hit of a last ray traced for its answer alone (last_rays_escape_only): no emitter
     * there, so nothing to add (as above), no SurfaceHit, and the path ends. */
    if (hit && last_rays_escape_only(sc, depth)) return;
    const Vertex *v = &p->v;
    bool no_mis = p->vs.delta || (v->glossy && glossy_is_delta(&v->bsdf));
    vec3 e = bsdf_ray_emission(sc, v, depth, p->vs.pdf, no_mis, hit ? nh : NULL, wi, p->time01, hit);
    vec3 le = guard3(v3_mul(p->beta_next, e), st);
    *bucket = v3_add(*bucket, le);
    if (p->unfiltered && !sc->skip_first_hit_fields) rec->unfiltered = v3_add(rec->unfiltered, le);
    /* the BSDF sample's glossy lobes' part (SampleRecord.direct_glossy): its weight f |cos| / pdf
     * less the diffuse lobe's f_d |cos| / pdf, times the same MIS-weighted emission */
    if (depth == 1 && v->glossy && !p->unfiltered && !sc->skip_first_hit_fields && !max_component_nonpositive(le))
        record_glossy_bsdf(p, e, rec, st);
    if (!hit || depth == sc->max_depth) return;
    p->beta = p->beta_next;
    make_vertex(sc, nh, v3_neg(wi), &p->v);
    p->alive = true;
}

/* The wave, for either kind of output (WaveOut; one copy of it each, WAVE_STAGE). A
 * radiance-only wave runs on a scene that asks for nothing else (integrate_wave_radiance), so
 * every record field it would skip is skipped by that scene's flags as well. */
WAVE_STAGE int wave_integrate(const IntegratorScene *sc, Wave *w, const WaveSampling *ws, const WavePixel *pixels,
                              int pixel_count, WaveOut out, IntegratorStats *st)
{
    _Static_assert(SAMPLE_RECORD_MAX_SHADOW == 1 && SAMPLE_RECORD_MAX_BOUNCE == 1,
                   "record_reset clears one entry of each");
    w->sampler_pixel = -1;
    /* camera samples, and the first vertex's dimensions, pixel by pixel; then the rays */
    int n = 0;
    for (int k = 0; k < pixel_count; ++k) {
        int count = pixels[k].count < WAVE_SAMPLES - n ? pixels[k].count : WAVE_SAMPLES - n;
        w->path_first[k] = n;
        w->path_count[k] = count > 0 ? count : 0;
        for (int i = 0; i < count; i += SAMPLER_RUN_MAX) {
            int m = count - i < SAMPLER_RUN_MAX ? count - i : SAMPLER_RUN_MAX;
            wave_camera_samples(sc, w, ws, pixels, k, pixels[k].index_first + i, m, n + i, out);
        }
        n += w->path_count[k];
    }
    float *cam_o[3] = {w->cam_o[0], w->cam_o[1], w->cam_o[2]}, *cam_d[3] = {w->cam_d[0], w->cam_d[1], w->cam_d[2]};
    camera_generate_rays(sc->camera, n, w->camera.px, w->camera.py, w->camera.lens_u, w->camera.lens_v, w->cam_time01,
                         cam_o, cam_d);
    st->rays_primary += n;
    TracerRayArrays camera_rays = {{w->cam_o[0], w->cam_o[1], w->cam_o[2]},
                                   {w->cam_d[0], w->cam_d[1], w->cam_d[2]},
                                   NULL, /* INFINITY */
                                   w->cam_time01,
                                   NULL,
                                   0u};
    tracer_intersect_arrays(sc->tracer, &camera_rays, n, true, true, w->hit, w->hit_found);
    bool any_alive = false;
    /* the receivers' lanes are read by the delta lights' stage and by the Lambert bounces,
     * which every vertex before the last samples (lambert_uses_bsdf) */
    bool delta_lanes = sc->lights->delta_every_count > 0;
    bool rx_lanes = delta_lanes || sc->max_depth > 1 || lambert_uses_bsdf(sc, 1);
    for (int j = 0; j < n; ++j) {
        wave_first_hit(sc, &w->path[j], v3(w->cam_d[0][j], w->cam_d[1][j], w->cam_d[2][j]), w->hit_found[j], &w->hit[j],
                       wave_out_record(out, j), wave_out_radiance(out, j), st);
        if (rx_lanes) receiver_to_lanes(&w->rx, j, &w->path[j]);
        any_alive |= w->path[j].alive;
    }

    /* path vertices: shadow and bounce rays in batches, then folded in path by path */
    for (int depth = 1; depth <= sc->max_depth && any_alive; ++depth) {
        /* the vertex's dimensions, per pixel with a path still going (the first vertex's
         * came with the camera rays, unless first_dims_after_trace); a pixel with none draws
         * nothing (the values are a pure function of pixel, sample and dimension, so when
         * they are drawn changes none of them) */
        bool any_dims = vertex_uses_light_dims(sc, depth) || vertex_uses_bsdf_dims(sc, depth);
        bool draw_here = depth > 1 || first_dims_after_trace(sc);
        for (int k = 0; k < pixel_count && draw_here && any_dims; ++k) {
            int j0 = w->path_first[k], count = w->path_count[k];
            bool alive = false;
            for (int j = j0; j < j0 + count; ++j) alive |= w->path[j].alive;
            if (!alive) continue;
            PixelSampler *s = wave_pixel_sampler(w, ws, pixels, k);
            for (int i = 0; i < count; i += SAMPLER_RUN_MAX) {
                sampler_run_begin(s, &w->run, pixels[k].index_first + i, count - i);
                wave_vertex_dims(sc, w, j0 + i, depth);
            }
        }
        int n_occ = 0, n_rec = 0, n_hit = 0;
        int delta_lights = sc->lights->delta_every_count;
        if (delta_lights > 0) wave_delta_light_samples(sc, w, n, st);
        wave_triangle_light_samples(sc, w, n, depth);
        if (lambert_uses_bsdf(sc, depth)) wave_lambert_bounces(w, n);
        StageRules rules = stage_rules(sc, depth);
        for (int j = 0; j < n; ++j)
            if (w->path[j].alive)
                wave_vertex_rays(sc, w, ws, pixels, j, depth, rules, wave_out_record(out, j), st, &n_occ, &n_rec,
                                 &n_hit);
        if (rules.box_test) n_hit = wave_emitter_box_test(sc, w, n_hit, st);
        tracer_occluded_batch(sc->tracer, w->ray_occ, n_occ, true, w->occluded);
        if (delta_lights > 0) {
            wave_delta_occlusion(sc, w, n);
            delta_lanes_sum(n, delta_lights, w->delta, w->delta_sum);
        }
        wave_triangle_occlusion(sc, w, depth == 1 && sc->record_ray_geometry);
        tracer_intersect_batch(sc->tracer, w->ray_rec, n_rec, false, true, w->rec_hit, w->rec_found);
        if (last_rays_escape_only(sc, depth))
            tracer_occluded_batch(sc->tracer, w->ray_hit, n_hit, false, w->hit_found);
        else
            tracer_intersect_batch(sc->tracer, w->ray_hit, n_hit, depth < sc->max_depth, false, w->hit, w->hit_found);
        any_alive = false;
        for (int j = 0; j < n; ++j) {
            WavePath *p = &w->path[j];
            if (!p->alive) continue;
            wave_vertex_fold(sc, w, j, depth, wave_out_record(out, j), wave_out_radiance(out, j), st);
            if (rx_lanes) receiver_to_lanes(&w->rx, j, p);
            any_alive |= p->alive;
        }
    }
    for (int j = 0; j < n; ++j) {
        SampleRecord *rec = wave_out_record(out, j);
        SampleRadiance *R = wave_out_radiance(out, j);
        /* guard3 of each sum, tested at once: a non-finite component makes the total
         * non-finite, and when the total is finite so is every term (an overflowing total
         * of finite terms only sends them to the test one by one). A miss's sums are
         * record_reset's +0 (no vertex folded into them): it passes, and its L is its
         * emission (+0 plus a value that is never -0, being +0 or a guarded sum begun at
         * +0), as before, when a miss set L itself and skipped this. */
        vec3 all = v3_add(R->direct, R->indirect);
        if (rec && !sc->skip_first_hit_fields) all = v3_add(all, v3_add(rec->unfiltered, rec->unfiltered_direct));
        if (!finite3(all)) {
            R->direct = guard3(R->direct, st);
            R->indirect = guard3(R->indirect, st);
            if (rec) {
                rec->unfiltered = guard3(rec->unfiltered, st);
                rec->unfiltered_direct = guard3(rec->unfiltered_direct, st);
            }
        }
        R->L = v3_add(R->emission, v3_add(R->direct, R->indirect));
    }
    return n;
}

int integrate_wave(const IntegratorScene *sc, Wave *w, const WaveSampling *ws, const WavePixel *pixels, int pixel_count,
                   SampleRecord *recs, IntegratorStats *st)
{
    return wave_integrate(sc, w, ws, pixels, pixel_count, (WaveOut){recs, NULL, false}, st);
}

int integrate_wave_radiance(const IntegratorScene *sc, Wave *w, const WaveSampling *ws, const WavePixel *pixels,
                            int pixel_count, RadianceRecord *rads, IntegratorStats *st)
{
    /* what the records' users asked for is what this wave keeps: the radiance alone */
    IntegratorScene radiance_only = *sc;
    radiance_only.skip_first_hit_fields = true;
    radiance_only.record_motion = radiance_only.record_ray_geometry = false;
    return wave_integrate(&radiance_only, w, ws, pixels, pixel_count, (WaveOut){NULL, rads, true}, st);
}
