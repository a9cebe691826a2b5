/* Writing a render's images (see render_output.h). */
#include "app/render_output.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/false_colour.h"
#include "io/image_io.h"
#include "io/ocio.h"


typedef struct {
    float *direct, *indirect, *emission, *albedo, *normal, *depth, *alpha;
} OutputPlanes;

static void planes_free(OutputPlanes *p)
{
    free(p->direct), free(p->indirect), free(p->emission);
    free(p->albedo), free(p->normal), free(p->depth), free(p->alpha);
}

bool render_output_write(const char *path, const Frame *f, const ReconResult *res, const RenderOutputInfo *a,
                         long long *guarded, Diag *err)
{
    const float *rgb = res->rgb;
    double spp_avg = res->spp_avg;
    size_t n = (size_t)f->width * (size_t)f->height;
    OutputPlanes p = {0};
    if (path_is_png(path)) return ocio_write_png(path, f->width, f->height, rgb, a->view, err);
    p.alpha = malloc(n * sizeof(float));
    if (!p.alpha) goto oom;
    for (size_t i = 0; i < n; ++i) p.alpha[i] = 1.0f;
    ExrChannel ch[24 + RECON_AOV_MAX];
    int nc = 0;
    ch[nc++] = (ExrChannel){"R", rgb + 0, 3};
    ch[nc++] = (ExrChannel){"G", rgb + 1, 3};
    ch[nc++] = (ExrChannel){"B", rgb + 2, 3};
    ch[nc++] = (ExrChannel){"A", p.alpha, 1};
    /* a user that did not declare its need (render_reads.h) */
    if (a->aovs && (f->guides_skipped || frame_planes(f) != FRAME_PLANES_ALL)) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                 "internal error: the AOV layers of %s were asked for, but the render was told nothing reads them "
                 "(the frame's albedo, normal, depth, direct, indirect and emission sums were not all kept)",
                 path);
        free(p.alpha);
        return false;
    }
    if (a->aovs) {
        p.direct = malloc(3 * n * sizeof(float));
        p.indirect = malloc(3 * n * sizeof(float));
        p.emission = malloc(3 * n * sizeof(float));
        p.albedo = malloc(3 * n * sizeof(float));
        p.normal = malloc(3 * n * sizeof(float));
        p.depth = malloc(n * sizeof(float));
        if (!p.direct || !p.indirect || !p.emission || !p.albedo || !p.normal || !p.depth) goto oom;
        *guarded += frame_resolve3(f, f->direct, p.direct);
        *guarded += frame_resolve3(f, f->indirect, p.indirect);
        *guarded += frame_resolve3(f, f->emission, p.emission);
        *guarded += frame_resolve3(f, f->albedo, p.albedo);
        *guarded += frame_resolve_normal(f, p.normal);
        *guarded += frame_resolve_depth(f, p.depth);
        static const char *const rgb_names[3][3] = {
            {"albedo.R", "albedo.G", "albedo.B"}, {"direct.R", "direct.G", "direct.B"}, {"indirect.R", "indirect.G", "indirect.B"}};
        float *rgb_planes[3] = {p.albedo, p.direct, p.indirect};
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) ch[nc++] = (ExrChannel){rgb_names[k][c], rgb_planes[k] + c, 3};
        ch[nc++] = (ExrChannel){"emission.R", p.emission + 0, 3};
        ch[nc++] = (ExrChannel){"emission.G", p.emission + 1, 3};
        ch[nc++] = (ExrChannel){"emission.B", p.emission + 2, 3};
        ch[nc++] = (ExrChannel){"N.X", p.normal + 0, 3};
        ch[nc++] = (ExrChannel){"N.Y", p.normal + 1, 3};
        ch[nc++] = (ExrChannel){"N.Z", p.normal + 2, 3};
        ch[nc++] = (ExrChannel){"Z", p.depth, 1};
        ch[nc++] = (ExrChannel){"spp", f->spp, 1};
        for (int k = 0; k < res->aov_count; ++k) ch[nc++] = (ExrChannel){res->aovs[k].name, res->aovs[k].data, 1};
    }
    char seed_txt[32];
    snprintf(seed_txt, sizeof seed_txt, "%" PRIu64, a->seed);
    ExrAttr attrs[] = {
        {"wedge.spp", EXR_ATTR_FLOAT, NULL, spp_avg, 0},
        {"wedge.seed", EXR_ATTR_STRING, seed_txt, 0.0, 0},
        {"wedge.seconds", EXR_ATTR_FLOAT, NULL, a->seconds, 0},
        {"wedge.version", EXR_ATTR_STRING, WEDGE_VERSION, 0.0, 0},
        {"wedge.scene", EXR_ATTR_STRING, a->scene_name, 0.0, 0},
        {"wedge.sampler", EXR_ATTR_STRING, sampler_kind_name(a->sampler), 0.0, 0},
        {"wedge.filter", EXR_ATTR_STRING, a->filter, 0.0, 0},
    };
    ExrWriteOptions wo = {EXR_STORE_FLOAT, EXRC_ZIP, 0, 0, 0};
    bool ok = exr_write_with(path, f->width, f->height, ch, nc, attrs, (int)(sizeof attrs / sizeof attrs[0]), &wo, err);
    *guarded += wo.nonfinite_replaced;
    planes_free(&p);
    return ok;
oom:
    planes_free(&p);
    diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory writing '%s'", path);
    return false;
}

/* OUT without its extension + suffix: "img.exr" + "-spp.png" -> "img-spp.png". */
static void sibling_path(char *buf, size_t size, const char *out_path, const char *suffix)
{
    const char *dot = strrchr(out_path, '.'), *slash = strrchr(out_path, '/');
    size_t stem = (dot && (!slash || dot > slash)) ? (size_t)(dot - out_path) : strlen(out_path);
    snprintf(buf, size, "%.*s%s", (int)stem, out_path, suffix);
}

/* --visualize: false-colour PNGs of the samples per pixel and of each method layer (filter
 * widths), each scaled to its own maximum (printed, so the colours can be read as numbers):
 * OUT-spp.png, OUT-<layer>.png. */
bool render_output_visualize(const char *out_path, const Frame *f, const ReconResult *res, Diag *err)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    float *rgb = malloc(3 * n * sizeof(float));
    if (!rgb) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for --visualize");
        return false;
    }
    bool ok = true;
    for (int k = -1; ok && k < res->aov_count; ++k) {
        const float *values = k < 0 ? f->spp : res->aovs[k].data;
        char suffix[96], path[4096];
        snprintf(suffix, sizeof suffix, "-%s.png", k < 0 ? "spp" : res->aovs[k].name);
        sibling_path(path, sizeof path, out_path, suffix);
        float vmax = false_colour_image(values, n, rgb);
        ok = png_write_display(path, f->width, f->height, rgb, err);
        if (ok) fprintf(stderr, "wedge render: wrote %s (%s, dark = 0 to bright = %g)\n", path,
                        k < 0 ? "samples per pixel" : res->aovs[k].unit, (double)vmax);
    }
    free(rgb);
    return ok;
}

