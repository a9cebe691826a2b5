/* Host side of the separable AAF screen-space filter (kernel aaf_filter_pass in
 * aaf/aaf.cl): uploads the guide buffers once per frame, then filters any number of
 * quantities (direct irradiance, indirect irradiance, primary radiance), each with its own
 * per-pixel width, in two 1D passes (x then y). Buffer layouts are those of aaf.cl. */
#ifndef WEDGE_RECON_AAF_FILTER_H
#define WEDGE_RECON_AAF_FILTER_H

#include <stdbool.h>

#include "core/diag.h"
#include "recon/cl/cl_runtime.h"

typedef struct AafFilter AafFilter;

/* Largest filter radius the device buffers are padded for; larger radii are clamped. */
#define AAF_FILTER_RADIUS_CAP_PX 32

enum { AAF_DIST_WORLD = 0, AAF_DIST_PIXEL = 1 };

typedef struct {
    int mode;               /* AAF_DIST_WORLD or AAF_DIST_PIXEL */
    float cos_normal_min;   /* reject neighbours whose normal is further than this (cos 15 deg) */
    float depth_tol_rel;    /* reject neighbours off the centre's tangent plane by > this * depth */
    float sharp_beta_ratio; /* world mode: reject neighbours whose width is below this times the
                             * centre's, or that are not filtered (0: off) */
} AafFilterRules;

AafFilterRules aaf_filter_rules_default(int mode);

/* Turns a width map into the kernel's per-pixel (1/(2 beta^2), radius_px) pairs:
 * radius = min(ceil(radius_sigmas * beta / d), radius_cap_px) with d the world size of the
 * pixel (pixel_world, or NULL in pixel mode where beta is already in pixels). beta <= 0,
 * NaN, or a radius below 1 pixel leave the pixel unfiltered (radius 0). */
void aaf_filter_make_params(int n, const float *beta, const float *pixel_world, float radius_sigmas,
                            int radius_cap_px, float *param_xy);

AafFilter *aaf_filter_create(ClRuntime *rt, Diag *d);
void aaf_filter_destroy(AafFilter *f);

/* Allocates (and clears) the device buffers for a width x height image ahead of time, e.g. on
 * a helper thread while the renderer traces; aaf_filter_set_guides does it otherwise. */
bool aaf_filter_reserve(AafFilter *f, int width, int height, Diag *d);

/* Uploads the guides (4 floats per pixel each, layouts of aaf.cl); pos and nrm may be NULL
 * when only pixel-mode filtering follows. */
bool aaf_filter_set_guides(AafFilter *f, int width, int height, const float *pos4, const float *nrm4, Diag *d);

/* Filters value4 (rgb + usable flag) into out4 (may alias value4); radii above
 * AAF_FILTER_RADIUS_CAP_PX are clamped to it. Distances are measured in the plane whose unit
 * normal is the centre pixel's entry of plane_normal4 (4 floats per pixel, the 4th unused;
 * AAF-shadow eq. 12: the normal of the pixel's light), or, when it is NULL, in the tangent
 * plane of each centre pixel (AAF-GI). kernel_seconds (may be NULL) receives the
 * device time of the two filter passes as measured by OpenCL profiling. */
bool aaf_filter_run(AafFilter *f, const float *value4, const float *plane_normal4, const float *param_xy,
                    const AafFilterRules *rules, float *out4, double *kernel_seconds, Diag *d);

#endif
