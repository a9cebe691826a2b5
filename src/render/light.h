/* Light sources: diffuse area lights (one Light per emitting triangle, sphere or disk),
 * point, spot, distant, constant infinite and image infinite lights (pbrt-v4 semantics; the
 * image one importance sampled through envmap.h), and the light selection distribution
 * (proportional to an estimate of emitted power) over the lights a path vertex picks one of;
 * a few point, spot and distant lights are instead lit at every vertex (delta_every). */
#ifndef WEDGE_RENDER_LIGHT_H
#define WEDGE_RENDER_LIGHT_H

#include <stdbool.h>
#include <stddef.h>

#include "core/diag.h"
#include "core/vec.h"
#include "render/envmap.h"
#include "render/tracer.h"
#include "render/warp.h"
#include "scene/scene_desc.h"

typedef enum { LIGHT_AREA, LIGHT_POINT, LIGHT_SPOT, LIGHT_DISTANT, LIGHT_INFINITE } LightKind;

typedef struct {
    LightKind kind;
    vec3 L;                 /* radiance (area, distant: radiance x solid angle = irradiance
                             * scale, infinite) or intensity (point, spot), times "scale" */
    bool two_sided;         /* area lights */
    int layer, geom, prim;  /* area lights: the emitting geometry */
    int instance;           /* area light on a moving shape: its instance, else -1 */
    unsigned shadow_skip_mask; /* area lights: the emitter's Geom.mask_bit, which its own
                                * shadow rays need not test (0: test it) */
    vec3 p_world;           /* point, spot */
    vec3 w_world;           /* spot: unit axis; distant: unit direction towards the light */
    float cos_falloff_end, cos_falloff_start; /* spot */
    float area_world;       /* area lights, at shutter open */
    vec3 tri_p0, tri_e1, tri_e2, tri_n; /* static triangle lights: world vertex 0, edges, normal */
    float tri_err;          /* static triangle lights: surface offset */
    vec3 sphere_c;          /* static sphere lights: world centre and radius (sphere_world) */
    float sphere_r;
    Envmap *env;            /* infinite light with "filename": the image (owned); else NULL */
} Light;

/* A Light's static-triangle fields as float offsets from the Light's start, for loops over
 * lanes that each read their own light lights[i] (a mesh's triangles): as
 * ((const float *)lights)[i * LIGHT_FLOATS + LIGHT_F_...] the load is a gather GCC 12
 * vectorises, which it does not for a field of an indexed struct. */
enum {
    LIGHT_FLOATS = sizeof(Light) / sizeof(float),
    LIGHT_F_TRI_P0 = offsetof(Light, tri_p0) / sizeof(float),
    LIGHT_F_TRI_E1 = offsetof(Light, tri_e1) / sizeof(float),
    LIGHT_F_TRI_E2 = offsetof(Light, tri_e2) / sizeof(float),
    LIGHT_F_TRI_N = offsetof(Light, tri_n) / sizeof(float),
    LIGHT_F_TRI_ERR = offsetof(Light, tri_err) / sizeof(float),
    LIGHT_F_AREA = offsetof(Light, area_world) / sizeof(float),
};
_Static_assert(sizeof(Light) % sizeof(float) == 0, "a Light is a whole number of floats");

/* Point, spot and distant lights of a scene that has at most this many are lit at every
 * path vertex (a shadow ray each) instead of entering the one-light pick: picking one of
 * them per sample adds a two-valued noise (light or nothing, scaled by 1/pmf) that
 * nothing filters, since their hard shadows pass the filters unfiltered. More of them
 * than this join the pick, where one shadow ray per vertex keeps the cost bounded. */
enum { LIGHTS_DELTA_EVERY_MAX = 8 };

/* Per light, what the per-sample choice (lights_choose, light_choose.h) needs, fixed when the set is built:
 * its probability lights_pmf, the run [mesh_first, mesh_end) of the emitting mesh whose
 * triangle lights_pick_in_mesh re-picks (0, 0: it keeps the light as picked), and
 * light_is_static_triangle. Read per sample instead of a chain of loads through the
 * tracer's layer and geometry and a division. */
typedef struct {
    float pmf;
    int mesh_first, mesh_end;
    bool static_triangle;
    /* a static triangle of a run whose radiance, shadow mask and sidedness are its run's first light's:
     * the wave batches it with the run's other triangles (wave_triangle_light_samples) */
    bool batches_with_run;
} LightChoice;

typedef struct {
    Light *lights;
    int count;
    float *cdf;             /* count + 1 entries: selection by power (lights in
                             * delta_every have none: they are never picked) */
    float power_total;
    int delta_every[LIGHTS_DELTA_EVERY_MAX]; /* indices of the delta lights lit at every vertex */
    int delta_every_count;
    int *infinite;          /* indices of infinite lights (seen by escaping rays) */
    int infinite_count;
    bool has_area, has_delta;
    /* light_sample reaches every point of every area light that a receiver outside it can see
     * emitting towards it (false: a cut sphere that emits inwards or both ways, whose far
     * cap's inside cone sampling misses; and in a set made by hand). Light sampling alone is
     * then unbiased (the integrator's lambert_light_only). */
    bool area_sampling_complete;
    /* the light a Lambert receiver samples by cosine about its normal (light_sky_cosine): the
     * pick's only light when that is a constant sky, the scene's only infinite light; else -1
     * (as in a set made by hand). With other lights in the pick the sky's uniform sample stays:
     * its MIS weight is small there and the cosine would add rays, not lower noise. */
    int sky_cosine_light;
    float scene_radius;     /* bounding sphere of the geometry (distant/infinite power) */
    vec3 scene_center;
    /* a padded world box around every area light (light_bounds.c); emitters_bounded is
     * false when there is none or one moves (then every ray may reach an emitter) */
    bool emitters_bounded;
    vec3 emitter_lo, emitter_hi;
    LightChoice *choice;    /* count entries (lights_build; NULL in a set made by hand) */
    /* When every light the pick can land on is a triangle of one emitting mesh (the lights
     * outside its run [sole_mesh_first, sole_mesh_end) have no power, each inside has some):
     * the run, else sole_mesh_end = 0. lights_choose then needs no pick of the light. */
    int sole_mesh_first, sole_mesh_end;
    /* When the pick can land on one light alone (cdf[i] <= 0 up to it and >= power_total
     * after it): lights_cdf_cell's answer for every target in [0, power_total), which
     * lights_choose then takes without the search (envlight's sky beside its sun); else -1. */
    int sole_light;
} LightSet;

/* A sampled point on a light as seen from a receiver. */
typedef struct {
    vec3 wi;                /* unit direction receiver -> light */
    float dist;             /* distance to the light point (INFINITY for distant/infinite) */
    vec3 p_light;           /* the point on the light (area), light position (point/spot) */
    vec3 n_light;           /* surface normal at p_light (area lights) */
    float err_light;        /* offset that keeps the shadow ray off the light's surface */
    vec3 Li;                /* incident radiance (area/infinite) or intensity / dist^2 (delta) */
    float pdf;              /* solid-angle density of wi (1 for delta lights) */
    bool delta;
} LightSample;

/* Builds the lights of a scene (area lights from tracer geometries; sets Geom.light_first).
 * Unsupported light types become warnings. */
bool lights_build(LightSet *set, SceneDesc *scene, Tracer *tr, Diag *err);
void lights_free(LightSet *set);

/* Sets sole_mesh_first / sole_mesh_end and sole_light from the set's cdf
 * and choice table (lights_build calls it; a test that edits the table calls it again). */
void lights_find_sole_mesh(LightSet *set);
/* The box around the area lights (light_bounds.c; called by lights_build). */
void lights_bound_emitters(LightSet *set, const Tracer *tr);
/* False when the ray o + t d (t >= 0, world units) cannot hit any area light: it misses
 * their box. True when it may (or when the box is unbounded). */
bool lights_ray_may_reach_emitter(const LightSet *set, vec3 o, vec3 d);
/* The same for n rays given per coordinate (o[axis][k], d[axis][k]): may[k] is 1 exactly
 * when lights_ray_may_reach_emitter says true for ray k (one vectorised loop). */
void lights_rays_may_reach_emitter(const LightSet *set, int n, const float *const o[3], const float *const d[3], int *may);

/* The light choice in two steps without lights_build's per-light table: lights_pick, then
 * lights_pick_in_mesh. The integrator makes both at once through the table (lights_choose,
 * light_choose.h) with the same bisections; test_light_mesh_pick checks the table's answers
 * against these two. */
/* Picks a light with probability proportional to power; returns -1 when there is none. */
int lights_pick(const LightSet *set, float u, float *pmf);
float lights_pmf(const LightSet *set, int light);
/* Light li picked, a triangle of an emitting mesh: re-picks the triangle within that mesh
 * from u->x (each triangle keeps its probability lights_pmf, stored in *pmf) and stretches
 * u->x back to [0, 1), so that the strata of the position sample cover the whole mesh
 * (light_mesh_pick.c). Other lights: li, nothing changed. */
int lights_pick_in_mesh(const LightSet *set, const Tracer *tr, int li, vec2 *u, float *pmf);
/* The run [*first, *end) of light li's emitting mesh in which lights_pick_in_mesh re-picks,
 * false when it keeps li as picked. */
bool lights_mesh_run(const LightSet *set, const Tracer *tr, int li, int *first, int *end);

/* Samples light l as seen from p_world at time time01. Returns false when the sample
 * carries no light (zero pdf, back side, ...). */
bool light_sample(const LightSet *set, const Tracer *tr, int l, vec3 p_world, float time01, vec2 u, LightSample *ls);

/* light_sample of a point or spot light l (LIGHT_POINT or LIGHT_SPOT) for count receivers at
 * once, arrays in and out (one per coordinate; `p` holds the receivers' x, y, z): for
 * receiver k, ok[k] is what light_sample returns and, where it is true, wi, dist and Li are
 * its sample's fields, bit for bit (the other fields are the light's own: p_light is
 * l->p_world, n_light 0, err_light light_delta_offset(l), pdf 1, delta). One vectorised
 * loop (core/vectorise.h): the square roots and divisions of the receivers overlap. */
typedef struct {
    float *wi[3], *dist, *Li[3];
    int *ok;
} LightSampleBatch;
void light_sample_point_batch(const Light *l, int count, const float *const p[3], const LightSampleBatch *out);
/* light_sample of a static triangle light l (light_is_static_triangle) for count receivers
 * p (x, y, z arrays) at the position samples u (u[0][k], u[1][k]): for receiver k, ok[k] is
 * what light_sample returns and, where it is true, wi, dist, p_light and pdf are its fields,
 * bit for bit (the others are the light's: n_light tri_n, err_light tri_err, Li L, not
 * delta). One vectorised loop (core/vectorise.h). */
typedef struct {
    float *wi[3], *dist, *p_light[3], *pdf;
    int *ok;
} TriangleSampleBatch;
void light_sample_triangle_batch(const Light *l, int count, const float *const p[3], const float *const u[2],
                                 const TriangleSampleBatch *out);
/* light_sample_triangle_batch with each receiver's own static triangle light: lane k samples
 * lights[tri[k]], bit for bit as light_sample (the lanes of one emitting mesh, whose
 * triangles are separate lights). The lanes' lights are all one-sided or all two-sided
 * (one mesh's run: LightChoice.batches_with_run). */
void light_sample_triangles_batch(const Light *lights, const int *tri, int count, const float *const p[3],
                                  const float *const u[2], const TriangleSampleBatch *out);
/* light_sample of a constant infinite light (LIGHT_INFINITE without an image:
 * light_is_constant_sky) for count position samples u (u[0][k], u[1][k]): wi[.][k] is the
 * sample's direction (warp_uniform_sphere), bit for bit, the same for every such light; the
 * other fields are the light's own (Li its L, pdf LIGHT_SKY_PDF, dist infinite, not delta,
 * the answer v3_any_positive(L)) but p_light and n_light, which follow from the receiver
 * and wi. The arithmetic is vectorised, the sine and cosine by sincos_run. */
void light_sample_sky_batch(int count, const float *const u[2], float *const wi[3]);
/* A constant sky's sample at a Lambert receiver whose shading normal (on the side it is seen
 * from) is n: light_sample's uniform direction ls->wi turned into the cosine-weighted one
 * about n (warp_cosine_about), with that density (warp_cosine_about_pdf) and the far point
 * and normal light_sample would give it from p_ref. False, ls unchanged, where the density
 * is 0 (the direction of n - n). docs/algorithms.md, "A constant sky sampled by cosine at a
 * Lambert receiver". */
bool light_sky_cosine(const LightSet *set, vec3 n, vec3 p_ref, LightSample *ls);
/* light_sky_cosine's direction, density and answer for the lanes k < count with lambert[k]
 * (normals n[.][k], uniform directions wi[.][k] in, pdf[k] and ok[k] ANDed with the answer);
 * the other lanes are left as they are. One vectorised loop, bit for bit. */
void light_sky_cosine_batch(int count, const float *const n[3], const int *lambert, float *const wi[3], float *pdf,
                            int *ok);
/* Whether light l is a constant infinite light (light_sample_sky_batch). */
static inline bool light_is_constant_sky(const Light *l) { return l->kind == LIGHT_INFINITE && !l->env; }
/* Whether the shadow rays of static triangle light l's samples can be made ahead (an offset and
 * a normal to push their far end off the light; else shadow_ray_to makes them). */
static inline bool light_triangle_rays_ahead(const Light *l) { return l->tri_err > 0.0f && v3_length2(l->tri_n) > 0.0f; }
/* Whether light_sample of light l takes the static-triangle case (light_sample_triangle_batch). */
bool light_is_static_triangle(const LightSet *set, const Tracer *tr, int l);
/* The shadow-ray offset of a point or spot light's samples (LightSample.err_light). */
float light_delta_offset(const Light *l);

/* Radiance leaving area light l at hit h towards direction w (unit, away from the surface). */
vec3 area_light_L(const LightSet *set, int l, const SurfaceHit *h, vec3 w);
/* Solid-angle pdf with which light_sample would produce the point h seen from p_ref. */
float area_light_pdf(const LightSet *set, const Tracer *tr, int l, vec3 p_ref, const SurfaceHit *h, float time01);

/* The solid-angle density of a constant sky's samples (uniform over the sphere). */
#define LIGHT_SKY_PDF (1.0f / (4.0f * WEDGE_PI))

/* Infinite light l's radiance from direction w (unit, pointing away from the scene).
 * Inline: every escaping BSDF ray of a sky-lit scene asks (docs/design.md 12.23). */
static inline vec3 infinite_light_L(const LightSet *set, int l, vec3 w)
{
    const Light *light = &set->lights[l];
    return light->env ? envmap_Le(light->env, w) : light->L;
}
/* Solid-angle density with which light_sample picks direction w on infinite light l
 * (uniform 1/(4 pi) without an image; the image's importance density with one). */
static inline float infinite_light_pdf(const LightSet *set, int l, vec3 w)
{
    const Light *light = &set->lights[l];
    return light->env ? envmap_pdf(light->env, w) : LIGHT_SKY_PDF;
}

#endif
