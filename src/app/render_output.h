/* What a render writes: the image as EXR (with the AOV layers and header attributes) or as
 * display-referred PNG through an OpenColorIO view, and the false-colour maps of
 * --visualize. Shared by `wedge render` (final image, checkpoints) and `wedge preview` (the
 * `s` key). Every file is written atomically (io/atomic_file.h). */
#ifndef WEDGE_APP_RENDER_OUTPUT_H
#define WEDGE_APP_RENDER_OUTPUT_H

#include <stdbool.h>
#include <stdint.h>

#include "core/diag.h"
#include "core/sampler.h"
#include "recon/pipeline.h"
#include "render/frame.h"

typedef struct {
    const char *scene_name;   /* wedge.scene */
    const char *filter;       /* wedge.filter: what was asked for */
    uint64_t seed;
    SamplerKind sampler;
    double seconds;           /* wedge.seconds */
    bool aovs;                /* add the AOV layers (albedo, N, Z, direct, ..., method layers) */
    const char *view;         /* OCIO view for PNG; NULL: the display's default */
} RenderOutputInfo;

/* path ending in .png: 8-bit through the view; anything else: EXR. f: the frame's sums (AOVs),
 * res: the image and the methods' layers. Non-finite values the EXR writer replaces are added
 * to *guarded. */
bool render_output_write(const char *path, const Frame *f, const ReconResult *res, const RenderOutputInfo *info,
                         long long *guarded, Diag *err);

/* --visualize: OUT-spp.png and OUT-<layer>.png per method layer, false colour. */
bool render_output_visualize(const char *out_path, const Frame *f, const ReconResult *res, Diag *err);

#endif
