/* The integrator: radiance of one camera sample, split the way the filters need it
 * (emission seen directly, direct light at the first hit, indirect light), by next-event
 * estimation with multiple importance sampling against BSDF sampling (Veach 1997, power
 * heuristic; at a Lambert last vertex without infinite lights, light sampling alone) and, for
 * max_depth >= 2, BSDF-sampled bounces (direct lighting at each bounce vertex). Everything
 * after the first bounce counts as indirect. */
#ifndef WEDGE_RENDER_INTEGRATOR_H
#define WEDGE_RENDER_INTEGRATOR_H

#include <stdbool.h>

#include "core/sampler.h"
#include "render/camera.h"
#include "render/light.h"
#include "render/material.h"
#include "render/pixel_filter.h"
#include "render/sample_record.h"
#include "render/tracer.h"

typedef struct {
    const Camera *camera;
    const Tracer *tracer;
    const LightSet *lights;
    const MaterialTable *materials;
    int max_depth;             /* pbrt "maxdepth": 1 = direct only, 2 = one bounce, ... */
    bool sample_lens;          /* lens radius > 0: draw lens dimensions */
    bool sample_time;          /* something moves during the shutter: draw a time */
    float shutter_open, shutter_close;       /* scene time */
    float xform_time_start, xform_time_end;  /* TransformTimes: scene times of the two poses */
    bool record_ray_geometry;  /* fill SampleRecord shadow/bounce arrays */
    bool record_bounce_geometry; /* with record_ray_geometry: the bounce array too. Off, the
                                * first hit's last BSDF rays keep the emitter-box test (a
                                * maxdepth-1 frame whose filters read only the shadow rays) */
    bool record_motion;        /* fill SampleRecord.motion_px (LR, the blur probe; two camera
                                * projections and a matrix inverse per moving first hit) */
    bool skip_first_hit_fields; /* leave SampleRecord's first-hit fields (albedo .. object_id),
                                * its unfiltered parts (+0) and, unless recorded, its motion and
                                * ray geometry entries unset: no user reads them (render_reads.h;
                                * false: fill them) */
    bool sky_bounce_alone;     /* a Lambert vertex before the last takes a constant sky that is
                                * the pick's only light from its bounce ray alone, without a
                                * light sample (integrator.c, sky_by_bsdf_alone): set where no
                                * method filters the frame (!render_reads_first_hit) */
    bool materials_lambert_only; /* no material is glossy (material_table_lambert_only): every
                                * vertex is Lambert (false: some may not be) */
    float time01_fixed;        /* without sample_time: every ray's time (integrator_fixed_time01) */
    bool delta_lights_by_path; /* WEDGE_DELTA_BY_PATH=1 (tests): every receiver's delta lights path by
                                * path, the reference for the lanes (integrator.c, WaveDeltaSamples) */
    const PixelFilter *pixel_filter; /* NULL: the box over the pixel (the film sample as is) */
} IntegratorScene;

typedef struct {
    long long rays_primary, rays_shadow, rays_indirect, rays_bsdf;
    long long rays_bsdf_skipped; /* last rays not traced: they cannot reach an emitter (glossy
                                  * ones: a Lambert last vertex there samples no direction) */
    long long guarded_events;  /* non-finite values replaced, degenerate divisions skipped */
} IntegratorStats;

/* The pose fraction of every ray when no time is sampled (shutter fraction 0), once per
 * scene instead of per sample: store it in time01_fixed after filling the other fields. */
float integrator_fixed_time01(const IntegratorScene *sc);
/* The pose fraction (tracer time) a sample with shutter coordinate shutter_u in [0, 1] traces at. */
float integrator_shutter_time01(const IntegratorScene *sc, float shutter_u);

/* The samples of a few pixels integrated together (integrator.c, "the wave"): at most
 * WAVE_SAMPLES (a render round gives a pixel up to 319, which the renderer splits between
 * as many waves as they take). Scratch space for one thread. */
enum { WAVE_SAMPLES = 256 };
typedef struct Wave Wave;
Wave *wave_create(void); /* NULL when out of memory */
void wave_free(Wave *w);

/* How the pixels' samplers are seeded (sampler_continue_pixel). */
typedef struct {
    SamplerKind kind;
    uint64_t seed;
    int pass;
} WaveSampling;

/* One pixel's samples in a wave: sample indices index_first .. index_first + count - 1 of
 * the sampler set sampler_continue_pixel(..., spp_before, spp_set) gives. */
typedef struct {
    int px, py;
    int spp_before, spp_set;
    int index_first, count;
} WavePixel;

/* Integrates the samples of pixels[0 .. pixel_count) and fills recs completely, pixel by
 * pixel and in sample order within a pixel. Each record is what tracing its sample alone
 * would give (bit for bit: a path's arithmetic does not depend on the other paths).
 * Returns the number of records (the sum of the counts, at most WAVE_SAMPLES). */
int integrate_wave(const IntegratorScene *sc, Wave *w, const WaveSampling *ws, const WavePixel *pixels, int pixel_count,
                   SampleRecord *recs, IntegratorStats *st);

/* The same samples' radiance alone (RadianceRecord: the same L, emission, direct, indirect and
 * filter_weight, bit for bit, and the same counts), for a render whose users read nothing
 * else (render_reads.h; integrator_radiance_only): the 232-byte records are not written at
 * all. The same integrator, with the first-hit fields, the unfiltered parts, the motion and
 * the ray geometry skipped whatever sc says. */
int integrate_wave_radiance(const IntegratorScene *sc, Wave *w, const WaveSampling *ws, const WavePixel *pixels,
                            int pixel_count, RadianceRecord *rads, IntegratorStats *st);

/* Whether integrate_wave_radiance gives a scene's records' users all they asked for: they
 * read no first-hit field, and neither the motion nor the ray geometry is recorded. */
static inline bool integrator_radiance_only(const IntegratorScene *sc)
{
    return sc->skip_first_hit_fields && !sc->record_motion && !sc->record_ray_geometry;
}

#endif
