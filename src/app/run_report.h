/* The machine-readable summary of one render (wedge render --report FILE.json). */
#ifndef WEDGE_APP_RUN_REPORT_H
#define WEDGE_APP_RUN_REPORT_H

#include <stdbool.h>
#include <stdint.h>

#include "core/diag.h"
#include "recon/auto_fallback.h"
#include "scene/scene_desc.h"

typedef struct {
    int width, height;
    double spp_avg;            /* samples traced per visible pixel (the overscan band's included) */
    int overscan_px;           /* the band traced around the image and cropped (0: none) */
    double seconds_total, seconds_trace, seconds_filter, seconds_build;
    double cpu_seconds_total;  /* this process's CPU (every thread) over seconds_total's span */
    long long rays_primary, rays_shadow, rays_indirect, rays_bsdf; /* RenderStats */
    long long guarded_events;  /* guarded divisions / non-finite values replaced, all stages */
    long long nonfinite_pixels;/* pixels of the image that were non-finite and written as 0 */
    EffectMask effects;
    int threads;
    uint64_t seed;
    const char *sampler;       /* "stratified" / "sobol" */
    const char *filter;        /* what was asked: "auto", "aaf", "none" */
    const char *filters[EFFECT_COUNT]; /* per effect (scene/effects.h order): the method used, "none" */
    long long pixels_filtered[EFFECT_COUNT]; /* per effect, pixels its method filtered (ReconResult) */
    float blur_probe_px;       /* auto's blur probe (ReconChoice.blur_px), < 0: not run */
    int blur_probe_unbounded;  /* its samples whose blur overflowed (ReconChoice.blur_unbounded) */
    const AutoFallback *auto_fallback; /* auto's gain-probe decision (ReconChoice.fallback), NULL: none */
    EffectMask auto_fell_back; /* the effects it left to Monte Carlo */
    double mu;                 /* filter knob asked for (0: each paper's default) */
    const char *cl_device;     /* OpenCL device used by the filters, or NULL */
    const char *scene;         /* scene path or "<default>" */
    const char *output;
    bool interrupted;
    long triangles;
    int ranks;                 /* MPI ranks that shared the frame (1: one process) */
    int steps;                 /* reconstructions: 1, more with --time/--checkpoint */
    long long bytes_pass[4];   /* bytes the ranks sent per pass (gathers, plan broadcast) */
} RunReport;

/* Writes the report as one JSON object (keys of issue 3 plus a few extras). err exit 3. */
bool run_report_write(const char *path, const RunReport *r, Diag *err);

#endif
