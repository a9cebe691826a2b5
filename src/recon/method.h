/* A reconstruction method behind one interface (DESIGN.md section 9).
 *
 * The pipeline (pipeline.h) owns sampling, the shared guides (gbuffer.h), the per-sample
 * store (sample_store.h), the OpenCL device, demodulation and compositing; a method sees
 * only what it declares it needs and answers four questions:
 *
 *   how many samples?    pass1_spp, then plan (adaptive methods) or nothing (fixed count)
 *   what to remember?    add_sample: every camera sample, as a sink (its own statistics)
 *   how to filter?       filter_light (a shading effect's demodulated irradiance) and
 *                        filter_radiance (the composite radiance, for the camera effects)
 *   what to show?        aovs: named per-pixel layers for EXR output and the preview
 *
 * Adding a method: one folder under src/recon/ with its ReconMethodClass, one line in
 * methods.c, and its row in select.c's policy. Nothing in src/render/ or src/app/ changes.
 *
 * Shading effects (soft shadows: the direct light; indirect: the indirect light) are filtered
 * before compositing, on irradiance with the albedo divided out; camera effects (defocus,
 * motion) after it, on the composite radiance (blurring texture is the effect there). */
#ifndef WEDGE_RECON_METHOD_H
#define WEDGE_RECON_METHOD_H

#include <stdbool.h>
#include <stddef.h>

#include "core/diag.h"
#include "recon/cl/cl_runtime.h"
#include "recon/dist.h"
#include "recon/gbuffer.h"
#include "recon/sample_store.h"
#include "render/renderer.h"
#include "scene/effects.h"

typedef struct ReconMethod ReconMethod; /* one method's state for one frame (its own type) */

/* What the pipeline gives a method when it creates it. */
typedef struct {
    const Renderer *renderer;   /* camera and lights (renderer_light_info); read only */
    const GBuffer *gbuffer;     /* the shared guides; resolved after every pass */
    SampleStore *store;         /* per-sample records with the fields the method declared;
                                 * NULL when it declared none */
    EffectMask effects;         /* the effects this method filters in this frame */
    float mu;                   /* the filter knob; <= 0: the method's default */
    int spp_budget;             /* > 0: the frame's average samples per pixel (--spp), known
                                 * before pass 1 so that a method whose filter design is fixed
                                 * by then (MAAF) can suit it to the budget; 0: none */
    int method_options[4];      /* method-specific integer options (e.g. MAAF's pairs); 0: default */
    int band_px;                /* the overscan band around the image (overscan.h), which the
                                 * pipeline crops: its pixels need no reconstruction */
} ReconSetup;

/* What the shading filters made of the frame, for a camera-effect filter that runs after them
 * (LR gives each stored sample the filtered light instead of its own noisy one). Per pixel,
 * (r, g, b, usable): the filtered light per unit albedo, usable 0 where it was passed through;
 * the direct light's value is also multiplied by direct_factor (NULL: 1). NULL arrays: that
 * effect was not filtered in this frame. */
typedef struct {
    const float *direct4;
    const float *direct_factor;
    const float *indirect4;
} ReconShadingLight;

/* One named per-pixel layer (EXR channel "name", false-colour PNG "-name.png"). */
typedef struct {
    char name[64];              /* e.g. "aaf.beta_px.soft_shadows" */
    const float *data;          /* width * height floats, owned by the method */
    const char *unit;           /* for messages: "pixels", "samples" */
} ReconAov;

typedef struct {
    const char *name;           /* the --filter value: "aaf" */
    const char *title;          /* one line for `wedge info --filters` */
    EffectMask effects;         /* the effects it can filter */
    bool adaptive;              /* has a plan: pass 1, then per-pixel counts; else a fixed count */
    unsigned sample_fields;     /* per-sample store fields it reads (SAMPLE_FIELD_*); 0: per-pixel only */
    /* Optional: the part of sample_fields the given effects read (the store keeps only the
     * frame's); NULL: all of sample_fields whatever the effects. */
    unsigned (*sample_fields_for)(EffectMask effects);
    /* Pass 1 records SampleRecord's ray geometry when the method filters one of these
     * effects: shadow_geometry, the shadow rays (light point, d_light, d_occluder; closest-hit
     * instead of any-hit traces); bounce_geometry, the first hit's bounce ray too (d_hit, its
     * direction; every such ray traced, without the emitter-box test of a maxdepth-1 frame's
     * last rays). A method must declare what it reads: undeclared entries stay empty. */
    EffectMask shadow_geometry;
    EffectMask bounce_geometry;
    /* The method reads the G-buffer's frame sums and camera alone, its guides (sums, hit,
     * mixed, pos4, nrm4, lobe4, ...) only beside a shading filter. A frame whose methods all
     * say so and that filters no shading effect sums the unfiltered light alone
     * (gbuffer_add_unfiltered). */
    bool guides_unread;
    /* Its shading filters filter a mixed pixel's first surface (gbuffer_track_split,
     * composite_split_light) and its camera-effect filter, if any, reads the composite so made:
     * the pipeline splits a light where the method filtering it and every camera-effect
     * method say so. */
    bool filters_split_pixels;

    /* Samples per pixel of pass 1 (adaptive) or of the whole frame (fixed), for these effects. */
    int (*pass1_spp)(EffectMask effects);
    /* Optional, adaptive methods: under a --spp budget pass 1 takes this share of it (for these
     * effects) instead of pass1_spp, and the plan spends the rest (FSF: its store keeps pass
     * 1's samples, its plan sends the rest where its filters collapse). NULL: pass1_spp. */
    float (*budget_pass1_share)(const Renderer *r, EffectMask effects);
    bool (*create)(const ReconSetup *setup, ReconMethod **out, Diag *d);
    /* Called before each pass: pass 0 is pass 1 (sparse), later passes add samples. */
    void (*begin_pass)(ReconMethod *m, int pass);
    /* Every camera sample of every pass (may be NULL): the method's own statistics. */
    void (*add_sample)(ReconMethod *m, int px, int py, const SampleRecord *r);
    /* Adaptive methods: the total samples each pixel should have (>= its current count in
     * spp_now) at filter knob mu, into spp_total (w * h). May be called several times with
     * different mu (the pipeline searches mu for a --spp budget). NULL for fixed methods. */
    bool (*plan)(ReconMethod *m, float mu, const float *spp_now, int *spp_total, Diag *d);
    /* Builds kernels and device buffers for a width x height frame (called once, on a helper
     * thread while the last pass traces). */
    bool (*open_device)(ReconMethod *m, ClRuntime *rt, Diag *d);
    /* Shading effects: the factor to divide the light by besides the albedo (AAF-shadow's
     * unoccluded irradiance r(x)), or NULL for 1; pixels with factor <= *min_factor are passed
     * through unfiltered. May be NULL. */
    bool (*light_factor)(ReconMethod *m, Effect e, const float **factor, float *min_factor, Diag *d);
    /* Filters a shading effect's demodulated light in place: value4 per pixel is (r, g, b,
     * usable), usable 0 for pixels to pass through (no surface, mixed, black albedo). */
    bool (*filter_light)(ReconMethod *m, Effect e, float *value4, double *kernel_seconds, Diag *d);
    /* Called just before filter_radiance with the shading filters' results (valid until
     * filter_radiance returns). May be NULL. */
    void (*shading_light)(ReconMethod *m, const ReconShadingLight *light);
    /* Filters the composite radiance in place for the camera effects in `effects` (defocus,
     * motion): value4 per pixel is (r, g, b, 1). */
    bool (*filter_radiance)(ReconMethod *m, EffectMask effects, float *value4, double *kernel_seconds, Diag *d);
    /* The per-pixel arrays its sink fills (up to max; returns how many), which the pipeline
     * gathers from the ranks that own the pixels when a frame is shared by MPI ranks
     * (dist.h). Every array the sink writes must be listed, or ranks disagree. May be NULL
     * for a method without a sink. */
    int (*shared)(ReconMethod *m, DistArray *out, int max);
    /* How far beyond a pixel (px) its reconstruction reads samples: the pipeline traces a
     * band that wide around the image and crops it, so that the image border has the
     * samples the interior has (overscan.h). NULL: none. */
    int (*overscan_px)(void);
    /* Its AOV layers after reconstruction (up to max); returns how many. May be NULL. */
    int (*aovs)(ReconMethod *m, ReconAov *out, int max);
    void (*destroy)(ReconMethod *m);
} ReconMethodClass;

/* The registered methods (methods.c), NULL-terminated. */
extern const ReconMethodClass *const recon_methods[];

/* The method called name, or NULL. */
const ReconMethodClass *recon_method_find(const char *name);

#endif
