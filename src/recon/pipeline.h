/* The reconstruction pipeline: everything between a built scene and the finished image, for
 * every --filter (DESIGN.md sections 2 and 9).
 *
 *   select     the method per effect (select.h), the same policy `wedge info` shows
 *   pass 1     sparse, uniform sampling; every sample goes to the shared guides (gbuffer.h),
 *              the per-sample store if a method asked for one, and each method's own sink
 *   plan       adaptive methods say how many samples each pixel needs (the per-pixel maximum
 *              over methods is taken); a --spp budget scales the plans to that average
 *   pass 2     the extra samples, continuing each pixel's pass-1 sampler set, while the
 *              OpenCL device opens on a helper thread
 *   filter     shading effects on demodulated irradiance (direct: soft shadows; indirect),
 *              composite (emission + albedo x filtered light + the unfilterable part), then
 *              the camera effects (defocus, motion) on the composite radiance
 *
 * --filter none is the same pipeline with no method: one pass at --spp (or the scene's
 * count), no sink, the plain mean.
 *
 * Progressive use: recon_pipeline_step renders the first frame as above, then each further
 * call adds samples to every pixel at a doubled mu (the methods' filters narrow, the image
 * converges to the Monte Carlo answer: consistency, docs/design.md) and reconstructs again.
 * Each step is its own sampler pass (seeded from seed, pixel and step), because a stratified
 * set can be continued once but not extended again.
 *
 * Overscan: when a chosen method reads samples beyond a pixel (ReconMethodClass.overscan_px:
 * LR), the renderer traces a band of that many pixels around the image (renderer_set_overscan),
 * everything above runs on the enlarged frame (a --spp budget is per traced pixel), and the
 * result and the guides handed out are the visible image (overscan.h).
 *
 * Several MPI ranks (ReconOptions.dist): each traces the pixels it owns, the pipeline gathers
 * every per-pixel sum to rank 0 after each pass (and each step), rank 0 plans and broadcasts
 * the plan, and reconstructs; the image equals the single-process one (dist.h). Every rank
 * must make the same calls: a decision to stop stepping is rank 0's, broadcast. */
#ifndef WEDGE_RECON_PIPELINE_H
#define WEDGE_RECON_PIPELINE_H

#include <stdbool.h>
#include <stddef.h>

#include "core/diag.h"
#include "recon/dist.h"
#include "recon/gbuffer.h"
#include "recon/method.h"
#include "recon/select.h"
#include "render/renderer.h"

typedef struct {
    const char *filter;        /* "auto", "none" or a method name (recon_filter_known) */
    float mu;                  /* > 0: every method's filter knob; <= 0: each method's default */
    int spp;                   /* > 0: the average samples per pixel of the frame (the budget);
                                * 0: the methods' own (adaptive: the plan at mu; fixed: their
                                * default count; none: the scene's pixelsamples) */
    const char *cl_device;     /* NULL: $WEDGE_CL_DEVICE, else the first GPU, else the first CPU */
    size_t mem_limit_bytes;    /* cap on the per-sample store; 0: half the physical memory */
    int method_options[4];     /* passed to the methods (ReconSetup.method_options) */
    ReconDist *dist;           /* ranks sharing the frame (dist.h); NULL: this process alone.
                                * Only rank 0's result holds the image. */
    unsigned reads;            /* what the caller reads of the frame beyond the image
                                * (render_reads.h: the AOV layers need RENDER_READS_FRAME_GUIDES);
                                * 0: not declared, everything is kept. With a method running
                                * the pipeline keeps everything anyway (its G-buffer reads it). */
    bool no_overscan;          /* true: no band around the image even when a method reads
                                * beyond its pixels (LR); its border is then biased. For
                                * measuring the band's effect (--overscan off). */
} ReconOptions;

enum { RECON_AOV_MAX = 16 };

typedef struct {
    int width, height;
    float *rgb;                /* the image, 3 floats per pixel, all finite */
    ReconChoice choice;        /* the method per effect that filtered this image */
    ReconAov aovs[RECON_AOV_MAX]; /* the methods' layers (valid until the next step or destroy) */
    int aov_count;
    double spp_avg;            /* samples traced per visible pixel (the overscan band's
                                * included: the frame's cost per pixel of the image) */
    int pass1_spp;
    float mu;                  /* the knob of the last reconstruction (0: the methods' defaults) */
    int steps;                 /* reconstructions done (recon_pipeline_step calls that completed) */
    double seconds_filter;     /* wall time spent outside tracing: plans, filters, composite */
    double seconds_kernels;    /* OpenCL device time of the filter passes */
    long long guarded_events;  /* non-finite values replaced by 0, counted (every stage) */
    long long nonfinite_pixels;/* pixels of rgb that came out non-finite and were set to 0 */
    long long pixels_filtered[EFFECT_COUNT]; /* per effect, the pixels its method (choice) was
                                * given to filter: for the shading effects the usable ones (a
                                * surface, not mixed, non-black albedo), the rest pass through;
                                * for the camera effects every pixel */
    bool cancelled;            /* a pass was cancelled: rgb is the unfiltered mean of what was taken */
    char device[600];          /* OpenCL device used ("" when none was needed) */
    int overscan_px;           /* the band traced around the image and cropped (0: none) */
} ReconResult;

typedef struct ReconPipeline ReconPipeline;

/* Selects the methods for the renderer's scene and checks the OpenCL device (a wrong
 * --cl-device or a missing driver fails here, before anything is traced). Errors: exit 1
 * usage (unknown --filter or device), 3 runtime. */
bool recon_pipeline_create(Renderer *r, const ReconOptions *o, ReconPipeline **out, Diag *d);
void recon_pipeline_destroy(ReconPipeline *p);

/* The whole frame: pass 1, plans, pass 2, reconstruction. A cancelled pass (Ctrl-C) is not an
 * error: the result is the plain mean of the samples taken, with cancelled set. */
bool recon_pipeline_render(ReconPipeline *p, Diag *d);

/* Progressive rendering: the first call is recon_pipeline_render, each later call adds
 * samples to every pixel and reconstructs again (see above). spp_cap > 0 caps the frame's
 * average samples per pixel after the step (the plan is scaled down to it: a time budget or a
 * --spp target is met without overshooting); 0: the plan as it is. */
bool recon_pipeline_step(ReconPipeline *p, double spp_cap, Diag *d);

const ReconResult *recon_pipeline_result(const ReconPipeline *p);
/* The guides and the frame's sums (AOVs: albedo, normal, depth, samples per pixel). */
const GBuffer *recon_pipeline_gbuffer(const ReconPipeline *p);

#endif
