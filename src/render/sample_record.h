/* What the integrator knows about one camera sample, handed to the reconstruction stage.
 *
 * The renderer fills one SampleRecord per camera sample and passes it to a SampleSink
 * (DESIGN.md section 2); a render that has no sink and whose users read the radiance alone
 * (render_reads.h) fills a RadianceRecord instead. Calls for one pixel never overlap: a pass
 * runs in rounds (slices of every pixel's sample indices) separated by thread joins, and
 * within a round a pixel belongs to one thread, so a sink may keep per-pixel statistics
 * without locks. The raw ray geometry (shadow and bounce rays) is filled only when
 * RenderOptions.record_ray_geometry is set: plain Monte Carlo does not pay for it. */
#ifndef WEDGE_RENDER_SAMPLE_RECORD_H
#define WEDGE_RENDER_SAMPLE_RECORD_H

#include <stdbool.h>
#include <stddef.h>

#include "core/vec.h"

/* One shadow ray from the first hit (the receiver) towards a point on an area light.
 * Distances are world units along the ray. */
typedef struct {
    float d_light_world;    /* receiver -> light sample point */
    float d_occluder_world; /* receiver -> first occluder, or +INFINITY when unoccluded */
    vec3 light_p_world;     /* the light sample point */
    int light_index;        /* which light (index into the renderer's light list) */
} ShadowRayRecord;

/* The BSDF-sampled bounce ray leaving the first hit. */
typedef struct {
    float d_hit_world;      /* receiver -> reflector hit, or +INFINITY when it escaped */
    vec3 dir_world;         /* unit direction */
} BounceRayRecord;

enum { SAMPLE_RECORD_MAX_SHADOW = 1, SAMPLE_RECORD_MAX_BOUNCE = 1 };

/* The radiance of one sample (linear rgb), what every user of a render reads of it. */
typedef struct {
    vec3 L;                       /* = emission + direct + indirect */
    vec3 emission;                /* emission seen directly by the camera ray (incl. infinite lights) */
    vec3 direct;                  /* direct light reflected at the first hit (MIS light + BSDF) */
    vec3 indirect;                /* everything reflected at the first hit that bounced at least once */
} SampleRadiance;

/* What a render whose users read the radiance alone (render_reads.h) keeps of a sample
 * instead of its SampleRecord: 52 bytes instead of 244, the records of a wave 13 KB instead
 * of 62 (integrate_wave_radiance). */
typedef struct {
    SampleRadiance radiance;
    float filter_weight;          /* SampleRecord.filter_weight */
} RadianceRecord;

typedef struct {
    /* the sample's position in the extra dimensions */
    float px_raster, py_raster;   /* film position, pixels (pixel (x, y) covers [x, x+1); a pixel
                                   * filter wider than the box puts it up to its radius outside) */
    float filter_weight;          /* pixel filter weight (1 for box, triangle, gaussian; pixel_filter.h) */
    float lens_u, lens_v;         /* unit-disk lens coordinates in [-1, 1]^2 (0 for a pinhole) */
    float time;                   /* normalised shutter time in [0, 1] (shutter open when static) */

    /* radiance (linear rgb): the fields of SampleRadiance, by name (rec->L) or as one
     * (rec->radiance, which the integrator writes for either kind of record) */
    union {
        SampleRadiance radiance;
        struct {
            vec3 L, emission, direct, indirect;
        };
    };
    vec3 unfiltered;              /* the part of direct + indirect the filters must not blur
                                   * (already included there): all of it at a dielectric first hit,
                                   * and whatever arrived through a delta lobe of the first hit (a
                                   * smooth mirror, a smooth coat's reflection); subtract it before
                                   * filtering and add it back after */
    vec3 unfiltered_direct;       /* the same for a part of `direct` known to be direct (not in
                                   * `unfiltered`): a point, spot or distant light's light in a
                                   * scene with area lights, whose hard shadows the soft-shadow
                                   * filters must not blur; unfiltered and unfiltered_direct stay
                                   * +0 when the render's users declared that none of them reads
                                   * the first-hit fields (render/render_reads.h) */

    /* first-hit surface (valid when hit); albedo .. object_id, and motion_px and the ray
     * geometry entries unless asked for, are left unset when the render's users declared that
     * none of them reads them (render/render_reads.h) */
    bool hit;
    vec3 albedo;                  /* reflectance at the first hit for demodulation: Lambert
                                   * reflectance, or albedo_diffuse + albedo_glossy (each channel
                                   * at most 1) for a glossy material */
    vec3 albedo_diffuse;          /* the diffuse (Lambert) part: reflectance, coateddiffuse's base
                                   * as seen through the coat; 0 for conductors and dielectrics */
    vec3 albedo_glossy;           /* the glossy / specular part for the viewing direction
                                   * (glossy_albedo); 0 for Lambert */
    float phong_exponent;         /* equivalent Blinn-Phong exponent of the glossy lobe (002 eq. 18);
                                   * 0 when there is no glossy lobe (Lambert) */
    bool unfilterable;            /* the first hit is a dielectric or made of delta lobes only:
                                   * its light is in `unfiltered`, pass it through */
    vec3 p_world;                 /* first hit position */
    vec3 n_shading;               /* unit shading normal, facing the camera ray's origin side */
    float depth_cam;              /* camera-space z of the first hit (world units), +INFINITY on a miss */
    int object_id;                /* per top-level shape or per instance; -1 on a miss */
    float motion_px[2];           /* screen velocity of the first hit, raster pixels per unit
                                   * shutter time (the film moves from shutter open to close):
                                   * the hit's object-space point carried by its animated
                                   * transform and seen by the (possibly moving) camera at
                                   * shutter open and close; 0 on a miss, without motion, or
                                   * unless RenderOptions.record_motion asks for it */

    /* raw ray geometry (only with RenderOptions.record_ray_geometry) */
    int shadow_count;             /* shadow rays to area lights recorded from the first hit */
    ShadowRayRecord shadow[SAMPLE_RECORD_MAX_SHADOW];
    int bounce_count;             /* bounce rays recorded from the first hit */
    BounceRayRecord bounce[SAMPLE_RECORD_MAX_BOUNCE];

    /* the direct light split by lobe; last, so that the fields above keep their offsets (placed
     * after unfiltered_direct, in record_reset's cleared run, the wave took 3% more
     * instructions on a Lambert scene under AAF) */
    vec3 direct_glossy;           /* the glossy lobes' part of `direct` that is in neither
                                   * `unfiltered` nor `unfiltered_direct`: a light sample's and a BSDF sample's direct light
                                   * at a glossy first hit with the BSDF value cut to its glossy
                                   * lobes (glossy_f - glossy_f_diffuse), MIS weights unchanged;
                                   * direct - unfiltered parts - direct_glossy is the diffuse lobe's
                                   * (visibility-weighted irradiance x albedo_diffuse). +0 at a
                                   * Lambert hit, all of it at a conductor; the filters pass it
                                   * through (recon/gbuffer.h) */
} SampleRecord;

_Static_assert(offsetof(SampleRecord, L) == offsetof(SampleRecord, radiance) + offsetof(SampleRadiance, L) &&
                   offsetof(SampleRecord, emission) == offsetof(SampleRecord, radiance) + offsetof(SampleRadiance, emission) &&
                   offsetof(SampleRecord, direct) == offsetof(SampleRecord, radiance) + offsetof(SampleRadiance, direct) &&
                   offsetof(SampleRecord, indirect) == offsetof(SampleRecord, radiance) + offsetof(SampleRadiance, indirect),
               "SampleRecord's radiance fields by name are its SampleRadiance");

/* Consumer hook: add() is called once per camera sample; calls for the same pixel (px, py)
 * never run concurrently and come in increasing sample order. */
typedef struct {
    void (*add)(void *ctx, int px, int py, const SampleRecord *r);
    void *ctx;
} SampleSink;

#endif
