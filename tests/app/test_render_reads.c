/* `wedge render`'s outputs declare what they read (render_args_reads, issue 22), and the
 * pipeline skips the rest only under --filter none:
 *  - --filter none without --aovs: the frame's guide sums are skipped, the image is bit for
 *    bit that of a render that keeps them;
 *  - --filter none --aovs (and --visualize): the guide sums are kept, bit for bit those of an
 *    undeclared render (the AOV layers are what they were), and render_output_write refuses
 *    a frame whose guides were skipped rather than write empty layers;
 *  - a filter keeps everything whatever the outputs declare (its G-buffer reads it), and its
 *    frame holds every sum;
 *  - --filter none without --aovs makes a frame of the colour and the counts alone
 *    (frame_init_planes), whose colour and counts are the full frame's bit for bit. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/render_args.h"
#include "app/render_output.h"
#include "check.h"
#include "recon/pipeline.h"
#include "render/render_reads.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

static const char *SCENE_TEXT =
    "LookAt 0 1.5 -5  0 0.3 0  0 1 0 Camera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 20 ] \"integer yresolution\" [ 14 ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 4 ]\n"
    "WorldBegin\n"
    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ 6 6 6 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.5 3 -0.5  0.5 3 -0.5  0.5 3 0.5  -0.5 3 0.5 ]\n"
    "  \"integer indices\" [ 0 2 1 0 3 2 ] AttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.5 0.4 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "Translate 0 0.6 0 Shape \"sphere\" \"float radius\" [ 0.6 ]\n";

typedef struct {
    Frame frame;      /* a copy of the pipeline's frame */
    float *rgb;       /* the image */
    unsigned reads;   /* what the pipeline told the renderer */
} Rendered;

static void rendered_free(Rendered *r) { frame_free(&r->frame), free(r->rgb); }

/* Renders SCENE_TEXT as `wedge render ARGS...` would declare its reads (declare false: as a
 * caller that declares nothing). */
static bool render_with(const char *const *args, int argc, bool declare, Rendered *out)
{
    char *argv[16];
    argv[0] = "render";
    for (int i = 0; i < argc; ++i) argv[i + 1] = (char *)args[i];
    RenderArgs a;
    if (parse_render_args(argc + 1, argv, "render", &a) != 0) return false;
    SceneDesc scene;
    memset(&scene, 0, sizeof scene);
    Diag err = {0};
    if (!scene_parse_string(SCENE_TEXT, strlen(SCENE_TEXT), "<test>", NULL, &scene, &err)) return false;
    scene_analyze_effects(&scene);
    RenderOptions ro = {.seed = 5, .threads = 2};
    Renderer *r = NULL;
    ReconPipeline *pipe = NULL;
    bool ok = renderer_create(&scene, &ro, &r, &err);
    ReconOptions po = {.filter = a.filter, .reads = declare ? render_args_reads(&a) : 0};
    ok = ok && recon_pipeline_create(r, &po, &pipe, &err) && recon_pipeline_render(pipe, &err);
    if (ok) {
        const Frame *f = &recon_pipeline_gbuffer(pipe)->frame;
        size_t n = (size_t)f->width * (size_t)f->height;
        /* the same planes as the pipeline's frame (those its reads asked for) */
        ok = frame_init_planes(&out->frame, f->width, f->height, frame_planes(f)) &&
             (out->rgb = malloc(3 * n * sizeof(float)));
        if (ok) {
            float *const dst[] = {out->frame.color, out->frame.direct, out->frame.indirect, out->frame.emission,
                                  out->frame.albedo, out->frame.normal};
            const float *const src[] = {f->color, f->direct, f->indirect, f->emission, f->albedo, f->normal};
            for (int k = 0; k < 6; ++k)
                if (src[k]) memcpy(dst[k], src[k], 3 * n * sizeof(float));
            if (f->depth) memcpy(out->frame.depth, f->depth, n * sizeof(float));
            if (f->hits) memcpy(out->frame.hits, f->hits, n * sizeof(float));
            memcpy(out->frame.spp, f->spp, n * sizeof(float));
            out->frame.guides_skipped = f->guides_skipped;
            memcpy(out->rgb, recon_pipeline_result(pipe)->rgb, 3 * n * sizeof(float));
            out->reads = renderer_reads(r);
        }
    } else {
        fprintf(stderr, "render failed: %s\n", err.message);
    }
    recon_pipeline_destroy(pipe);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return ok;
}

static bool same(const float *a, const float *b, size_t n) { return memcmp(a, b, n * sizeof(float)) == 0; }

static bool same_guides(const Frame *a, const Frame *b)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    return same(a->albedo, b->albedo, 3 * n) && same(a->normal, b->normal, 3 * n) && same(a->depth, b->depth, n) &&
           same(a->hits, b->hits, n) && same(a->direct, b->direct, 3 * n) && same(a->indirect, b->indirect, 3 * n) &&
           same(a->emission, b->emission, 3 * n);
}

int main(void)
{
    static const char *const none[] = {"--filter", "none"};
    static const char *const none_aovs[] = {"--filter", "none", "--aovs"};
    static const char *const none_vis[] = {"--filter", "none", "--visualize"};
    Rendered full, skip, aovs, vis;
    if (!render_with(none, 2, false, &full) || !render_with(none, 2, true, &skip) ||
        !render_with(none_aovs, 3, true, &aovs) || !render_with(none_vis, 3, true, &vis))
        return 1;
    size_t n = (size_t)full.frame.width * (size_t)full.frame.height;

    /* undeclared: everything kept */
    CHECK(full.reads == 0 && !full.frame.guides_skipped && frame_planes(&full.frame) == FRAME_PLANES_ALL);
    /* --filter none, no AOVs: a frame of the colour and the counts alone (no guides, no
     * parts), the image the same */
    CHECK(skip.reads == RENDER_READS_RADIANCE && skip.frame.guides_skipped && frame_planes(&skip.frame) == 0);
    CHECK(same(full.rgb, skip.rgb, 3 * n) && same(full.frame.spp, skip.frame.spp, n));
    CHECK(same(full.frame.color, skip.frame.color, 3 * n));
    /* --aovs and --visualize declare the guides and the parts: the layers' sums as the
     * undeclared render's */
    CHECK(frame_planes(&aovs.frame) == FRAME_PLANES_ALL && frame_planes(&vis.frame) == FRAME_PLANES_ALL);
    CHECK(render_reads_frame_guides(aovs.reads) && !aovs.frame.guides_skipped);
    CHECK(same_guides(&full.frame, &aovs.frame) && same(full.rgb, aovs.rgb, 3 * n));
    CHECK(render_reads_frame_guides(vis.reads) && !vis.frame.guides_skipped && same_guides(&full.frame, &vis.frame));

    /* the AOV layers from a skipped frame: refused, not written empty */
    ReconResult res = {.width = skip.frame.width, .height = skip.frame.height, .rgb = skip.rgb, .spp_avg = 4.0};
    RenderOutputInfo info = {"<test>", "none", 5, SAMPLER_STRATIFIED, 0.0, true, NULL};
    long long guarded = 0;
    Diag err = {0};
    char path[256];
    snprintf(path, sizeof path, "%s/wedge_test_render_reads_%ld.exr", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp",
             (long)getpid());
    CHECK(!render_output_write(path, &skip.frame, &res, &info, &guarded, &err));
    CHECK(strstr(err.message, "AOV") != NULL);
    info.aovs = false; /* the image alone is fine */
    CHECK(render_output_write(path, &skip.frame, &res, &info, &guarded, &err));
    remove(path);

    /* a filter keeps everything whatever the outputs declare (creating its pipeline checks the
     * OpenCL device: without one this part is not run) */
    SceneDesc scene;
    memset(&scene, 0, sizeof scene);
    Renderer *r = NULL;
    ReconPipeline *pipe = NULL;
    RenderOptions ro = {.reads = RENDER_READS_RADIANCE};
    CHECK(scene_parse_string(SCENE_TEXT, strlen(SCENE_TEXT), "<test>", NULL, &scene, &err));
    scene_analyze_effects(&scene);
    CHECK(renderer_create(&scene, &ro, &r, &err));
    ReconOptions po = {.filter = "aaf", .reads = RENDER_READS_RADIANCE};
    if (recon_pipeline_create(r, &po, &pipe, &err)) {
        CHECK(renderer_reads(r) == RENDER_READS_ALL);
        /* and its frame holds every sum */
        CHECK(recon_pipeline_render(pipe, &err));
        CHECK(frame_planes(&recon_pipeline_gbuffer(pipe)->frame) == FRAME_PLANES_ALL);
    } else fprintf(stderr, "note: no OpenCL device, the filter's declaration not checked: %s\n", err.message);
    recon_pipeline_destroy(pipe);
    renderer_destroy(r);
    scene_desc_free(&scene);
    rendered_free(&full), rendered_free(&skip), rendered_free(&aovs), rendered_free(&vis);
    CHECK_DONE();
}
