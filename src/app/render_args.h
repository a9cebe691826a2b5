/* The options of `wedge render`, parsed in one place; `wedge preview` takes the same ones
 * that make sense for a window. */
#ifndef WEDGE_APP_RENDER_ARGS_H
#define WEDGE_APP_RENDER_ARGS_H

#include <stdbool.h>
#include <stdint.h>

#include "core/sampler.h"

typedef struct {
    const char *scene_path;   /* NULL: the embedded default scene */
    const char *out_paths[8]; /* -o, repeatable (one render, several files); none: the film's filename */
    int out_count;
    int spp;                  /* 0: scene's */
    int width, height;        /* 0: scene's */
    uint64_t seed;
    int threads;              /* 0: all cores */
    bool aovs;
    const char *report_path;
    bool quiet;
    bool sampler_set;
    SamplerKind sampler;
    const char *pixel_filter; /* --pixel-filter; NULL: the scene's PixelFilter, else box */
    const char *filter;       /* "auto", a method's name or "none" */
    float mu;                 /* filter knob; 0: each paper's default */
    int maaf_pairs;           /* --maaf-pairs N: MAAF's filter pairs in every 2D subspace; 0: each subspace's default */
    double mem_limit;         /* bytes for per-sample storage; 0: half the physical memory */
    const char *cl_device;    /* NULL: $WEDGE_CL_DEVICE, else the first GPU, else CPU */
    bool visualize;           /* false-colour PNG maps of filter widths and spp */
    double time_budget;       /* --time: seconds of progressive rendering; 0: one frame */
    double checkpoint;        /* --checkpoint: seconds between checkpoint writes; 0: none */
    const char *view;         /* OCIO view for PNG output; NULL: the display's default */
    bool no_overscan;         /* --overscan off: no band traced around the image (LR) */
    bool help;
} RenderArgs;

/* Parses argv (argv[0] is the command name); command ("render", "preview") names it in
 * messages. Returns WEDGE_EXIT_OK or WEDGE_EXIT_USAGE (message printed). */
int parse_render_args(int argc, char **argv, const char *command, RenderArgs *a);

/* What `wedge render`'s outputs read of the frame beyond the image (render/render_reads.h),
 * declared for the pipeline (ReconOptions.reads): the AOV layers (--aovs, also at every
 * checkpoint) read the frame's albedo, normal and depth sums; --visualize keeps everything
 * too (it writes the spp map and the methods' layers, and may write more). The image, the
 * report and the spp attribute read the radiance sums and counts alone. */
unsigned render_args_reads(const RenderArgs *a);

#endif
