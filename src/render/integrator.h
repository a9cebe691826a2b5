/* The integrator: radiance of one camera sample, split the way the filters need it
 * (emission seen directly, direct light at the first hit, indirect light), by next-event
 * estimation with multiple importance sampling against BSDF sampling (Veach 1997, power
 * heuristic) and, for max_depth >= 2, BSDF-sampled bounces (direct lighting at each bounce
 * vertex). Everything after the first bounce counts as indirect. */
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
    float time01_fixed;        /* without sample_time: every ray's time (integrator_fixed_time01) */
    const PixelFilter *pixel_filter; /* NULL: the box over the pixel (the film sample as is) */
} IntegratorScene;

typedef struct {
    long long rays_primary, rays_shadow, rays_indirect, rays_bsdf;
    long long guarded_events;  /* non-finite values replaced, degenerate divisions skipped */
} IntegratorStats;

/* The pose fraction of every ray when no time is sampled (shutter fraction 0), once per
 * scene instead of per sample: store it in time01_fixed after filling the other fields. */
float integrator_fixed_time01(const IntegratorScene *sc);

/* Traces camera sample (sampler positioned at the start of a sample) of pixel (px, py) and
 * fills rec completely. */
void integrate_camera_sample(const IntegratorScene *sc, PixelSampler *s, int px, int py, SampleRecord *rec,
                             IntegratorStats *st);

#endif
