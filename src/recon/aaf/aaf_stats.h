/* Per-pixel statistics for axis-aligned filtering, accumulated from the renderer's
 * SampleRecords by a SampleSink (DESIGN.md section 2).
 *
 * Pass 1 (sparse sampling) measures, per pixel: the shadow-ray geometry (AAF-shadow Sec. 6:
 * d1, d2min, d2max from 9 light samples), the bounce-ray distances (AAF-GI Sec. 5: zmin,
 * zmax from 16 hemisphere samples), and the range of circle-of-confusion slopes (defocus).
 * The receiver's position, normal and object id (the filter's guides) are the pipeline's
 * GBuffer, shared by every method. The sink is called from the thread that owns the pixel,
 * so no locks are needed. */
#ifndef WEDGE_RECON_AAF_STATS_H
#define WEDGE_RECON_AAF_STATS_H

#include <stdbool.h>

#include "recon/aaf/aaf_pixel_params.h"
#include "recon/dist.h"
#include "recon/gbuffer.h"
#include "render/renderer.h"
#include "render/sample_record.h"

/* One light as the shadow filter sees it (from renderer_light_info, index = ShadowRayRecord
 * .light_index): its Gaussian width and, for planar lights, the plane's unit normal. */
typedef struct {
    float sigma_world;           /* sqrt(A)/2 (AAF-shadow eq. 16: A_l = (2 sigma)^2); A is the
                                  * emitter's total area (all triangles of one shape), or for a
                                  * sphere its silhouette pi r^2 = area/4; 0: not an area light */
    float normal[3];             /* planar: unit normal; sphere: 0 (use receiver -> centre) */
    float center[3];             /* sphere: centre */
    /* The emitter itself, for the exact unoccluded irradiance r(x) (aaf_unoccluded_irradiance):
     * a triangle's vertices, or a disk's / sphere's radius around center. */
    enum { AAF_EMITTER_NONE, AAF_EMITTER_TRIANGLE, AAF_EMITTER_DISK, AAF_EMITTER_SPHERE } emitter;
    float tri[3][3];
    float radius_world;
    float radiance_mean;         /* mean of the emitted radiance's r, g, b: the emitter's weight */
    bool two_sided;
} AafLightGeom;

typedef struct {
    int width, height;
    const GBuffer *g;            /* the shared guides (not owned): camera, hits, positions */
    bool collect_rays;           /* true during pass 1: ray geometry feeds the statistics */
    bool collect_coc;            /* the samples' CoC range (coc_min, coc_max): read only by the
                                  * defocus filter, so off when AAF does not filter defocus */
    const AafLightGeom *lights;  /* exact lights (not owned; NULL: estimate from light samples) */
    int light_count;
    /* r(x)'s emitters when an area light moves during the shutter: its poses over the shutter
     * with their quadrature weights (aaf_light_sweep.h; not owned). NULL: lights themselves. */
    const AafLightGeom *emitters;
    int emitter_count;

    /* per pixel accumulators */
    /* shadows: ratio r = d2/d1 along each occluded shadow ray (light->occluder over
     * light->receiver), so that d2min = rmin * d1 and d2max = rmax * d1 */
    int *shadow_rays, *occluded_rays;
    float *d1_sum;
    float *ratio_min, *ratio_max;
    float *light_p_sum;          /* 3 per pixel: sampled light points */
    float *light_pp_sum;         /* 6 per pixel: xx xy xz yy yz zz */
    /* exact lights: min sigma over the lights of the pixel's shadow rays (the most
     * conservative width, see aaf_stats.c), and the sum of the per-ray light-plane normals */
    float *sigma_min;
    float *plane_sum;            /* 3 per pixel */
    float *phong_max;            /* largest Blinn-Phong exponent seen (0: diffuse) */
    /* indirect: distance of the reflector from the receiver's tangent plane (AAF-GI Fig. 2: z) */
    float *zmin, *zmax;
    /* defocus: signed CoC slope, pixels per unit lens coordinate */
    float *coc_min, *coc_max;
} AafStats;

/* Statistics for the frame of g (which must outlive them). */
bool aaf_stats_init(AafStats *s, const GBuffer *g);
/* Fills lights[0..count) from the renderer's exact light list (count = renderer_light_count). */
void aaf_lights_from_renderer(const Renderer *r, AafLightGeom *lights, int count);
/* One light's AafLightGeom from its RenderLightInfo; shape_area: the summed area of its
 * shape's triangles (0: the light's own). */
void aaf_light_geom_from_info(const RenderLightInfo *li, double shape_area, AafLightGeom *out);
/* The summed area of each SceneDesc shape's area lights in info[0..count), indexed by shape
 * (malloc'ed; NULL when out of memory). */
double *aaf_shape_areas(const RenderLightInfo *info, int count);
void aaf_stats_free(AafStats *s);

/* The statistics' per-pixel arrays, for gathering from MPI ranks (dist.h); returns how many. */
int aaf_stats_arrays(AafStats *s, DistArray *out, int max);

/* The SampleSink callback (ctx = AafStats *). */
void aaf_stats_add(void *ctx, int px, int py, const SampleRecord *r);

/* Derived maps the parameter code consumes, owned by the caller's AafDerived. */
typedef struct {
    int width, height;
    const GBuffer *g;            /* the guides (hit, pos4, nrm4, mixed, pixel_world), not owned */
    float *d1, *d2min, *d2max, *sigma_light;
    float *zmin, *zmax, *coc_min, *coc_max;
    float *plane4;               /* per pixel unit normal of the plane shadow-filter distances
                                  * are measured in (eq. 12); NULL data: light_normal */
    float *phong_m;              /* Blinn-Phong exponent per pixel for AAF-GI eq. 18 (0: diffuse) */
    float light_normal[3];       /* the light plane's unit normal (eq. 12); zero if unknown */
    float light_center[3];       /* the light as a rectangle: centre and half-side vectors */
    float light_half_u[3], light_half_v[3];
    bool light_known;
    bool exact_lights;           /* sigma and planes come from the renderer's light list */
    const AafLightGeom *lights;  /* the emitters for r(x) (not owned; NULL: use the rectangle) */
    int light_count;
    float light_sigma_world;     /* global estimate (see aaf_stats.c) */
} AafDerived;

/* From the statistics and the guides of s->g (resolved: gbuffer_resolve_guides). */
bool aaf_derive(const AafStats *s, AafDerived *out);
void aaf_derived_free(AafDerived *d);
/* r(x) of AAF-shadow eq. 1 up to a constant factor: the irradiance each pixel would get
 * without occlusion (0 where unknown), exactly from the emitters when d->lights lists them
 * (at most AAF_EXACT_EMITTERS_MAX of them), else from the estimated light rectangle. n floats. */
#define AAF_EXACT_EMITTERS_MAX 256
void aaf_unoccluded_irradiance(const AafDerived *d, float *r);
/* Points AafPixelStats at the derived maps. */
AafPixelStats aaf_derived_pixel_stats(const AafDerived *d);

#endif
