/* What the reconstruction tests share: small scenes and the benchmarks' error measure. */
#ifndef WEDGE_TESTS_RECON_TEST_UTIL_H
#define WEDGE_TESTS_RECON_TEST_UTIL_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "recon/pipeline.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

/* An area light above a floor and a square occluder 1 unit above the floor: penumbrae and a
 * small umbra in view. Direct light only. */
static const char *const SHADOW_SCENE =
    "LookAt -1.5 2.5 -1.5   0.8 0 0.3   0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 30 ]\n"
    "Film \"rgb\" \"integer xresolution\" [ 40 ] \"integer yresolution\" [ 40 ] \"string filename\" [ \"t.exr\" ]\n"
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\n"
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.8 4 -0.8  0.8 4 -0.8  0.8 4 0.8  -0.8 4 0.8 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
    "AttributeEnd\n"
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"
    "Shape \"trianglemesh\" \"point3 P\" [ 0.3 1 -0.3  0.9 1 -0.3  0.9 1 0.3  0.3 1 0.3 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n";

/* A renderer for a scene given as text (2 threads, the seed and spp given); false with the
 * message on stderr. Free with renderer_destroy and scene_desc_free. */
static inline bool recon_test_renderer(const char *text, unsigned seed, int spp, bool ray_geometry, SceneDesc *scene,
                                       Renderer **r)
{
    Diag d = {0};
    if (!scene_parse_string(text, strlen(text), "<test>", NULL, scene, &d)) {
        fprintf(stderr, "%s\n", d.message);
        return false;
    }
    scene_analyze_effects(scene);
    RenderOptions ro;
    memset(&ro, 0, sizeof ro);
    ro.seed = seed;
    ro.spp = spp;
    ro.threads = 2;
    ro.record_ray_geometry = ray_geometry;
    if (!renderer_create(scene, &ro, r, &d)) {
        fprintf(stderr, "%s\n", d.message);
        scene_desc_free(scene);
        return false;
    }
    return true;
}

/* Checks a method's result beyond what recon_test_render checks itself (may be NULL). */
typedef void (*ReconResultCheck)(const ReconResult *res, void *ctx);
/* The same with the whole pipeline after the frame (its result and guides). */
typedef void (*ReconPipelineCheck)(const ReconPipeline *p, void *ctx);

/* One frame of a scene given as text through the reconstruction pipeline with options o (the
 * seed and o->spp also set up the renderer): checks that no pixel came out non-finite, calls
 * check on the pipeline, and returns a copy of the image (3 floats per pixel; free it), or NULL
 * with the message on stderr. */
static inline float *recon_test_render_pipeline(const char *text, unsigned seed, const ReconOptions *o,
                                                ReconPipelineCheck check, void *ctx)
{
    SceneDesc scene;
    Renderer *r;
    if (!recon_test_renderer(text, seed, o->spp, false, &scene, &r)) return NULL;
    ReconPipeline *p = NULL;
    Diag d = {0};
    float *out = NULL;
    if (recon_pipeline_create(r, o, &p, &d) && recon_pipeline_render(p, &d)) {
        const ReconResult *res = recon_pipeline_result(p);
        size_t n3 = 3 * (size_t)res->width * (size_t)res->height;
        if ((out = malloc(sizeof(float) * n3))) memcpy(out, res->rgb, sizeof(float) * n3);
        CHECK(res->nonfinite_pixels == 0);
        if (check) check(p, ctx);
    } else {
        fprintf(stderr, "%s\n", d.message);
        CHECK(false);
    }
    recon_pipeline_destroy(p);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return out;
}

typedef struct {
    ReconResultCheck check;
    void *ctx;
} ReconTestResultCheck;

static inline void recon_test_check_result(const ReconPipeline *p, void *ctx)
{
    const ReconTestResultCheck *c = ctx;
    if (c->check) c->check(recon_pipeline_result(p), c->ctx);
}

/* recon_test_render_pipeline with a check of the result alone (may be NULL). */
static inline float *recon_test_render(const char *text, unsigned seed, const ReconOptions *o, ReconResultCheck check,
                                       void *ctx)
{
    ReconTestResultCheck c = {check, ctx};
    return recon_test_render_pipeline(text, seed, o, recon_test_check_result, &c);
}

/* The text of scenes/bench/NAME.pbrt under $WEDGE_SOURCE_DIR (ctest's working directory
 * otherwise: tests/recon), with room for extra bytes after it; NULL when it cannot be read.
 * Free it. */
static inline char *recon_test_bench_scene(const char *name, size_t extra)
{
    const char *root = getenv("WEDGE_SOURCE_DIR");
    char path[4096];
    snprintf(path, sizeof path, "%s/scenes/bench/%s.pbrt", root ? root : "../..", name);
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = len >= 0 ? calloc((size_t)len + 1 + extra, 1) : NULL;
    if (!text || fread(text, 1, (size_t)len, f) != (size_t)len) {
        free(text);
        text = NULL;
    }
    fclose(f);
    return text;
}

/* recon_test_bench_scene with its film of film x film pixels made res x res; NULL when it
 * cannot be read or its film is not film x film. Free it. */
static inline char *recon_test_bench_scene_resized(const char *name, int film, int res)
{
    char *text = recon_test_bench_scene(name, 16); /* room for a longer resolution */
    char from[128];
    snprintf(from, sizeof from, "\"integer xresolution\" [ %d ] \"integer yresolution\" [ %d ]", film, film);
    char *at = text ? strstr(text, from) : NULL;
    if (!at) {
        free(text);
        return NULL;
    }
    char repl[128];
    int n = snprintf(repl, sizeof repl, "\"integer xresolution\" [ %d ] \"integer yresolution\" [ %d ]", res, res);
    memmove(at + n, at + strlen(from), strlen(at + strlen(from)) + 1);
    memcpy(at, repl, (size_t)n);
    return text;
}

/* A renderer for scenes/bench/NAME.pbrt at its own film (recon_test_renderer, no ray
 * geometry); false when the file cannot be read or built. Free with renderer_destroy and
 * scene_desc_free. */
static inline bool recon_test_bench_renderer(const char *name, unsigned seed, int spp, SceneDesc *scene, Renderer **r)
{
    char *text = recon_test_bench_scene(name, 0);
    bool ok = text && recon_test_renderer(text, seed, spp, false, scene, r);
    free(text);
    return ok;
}

/* The same for the bench scenes with a 128 x 128 film. */
static inline char *recon_test_bench_scene_at(const char *name, int res)
{
    return recon_test_bench_scene_resized(name, 128, res);
}

/* The result's AOV layer called name, or NULL. */
static inline const float *recon_test_aov(const ReconResult *res, const char *name)
{
    for (int k = 0; k < res->aov_count; ++k)
        if (!strcmp(res->aovs[k].name, name)) return res->aovs[k].data;
    return NULL;
}

/* relMSE as in the benchmarks: mean of (x - ref)^2 / (ref^2 + 0.01). */
/* The smallest and largest samples per pixel of a frame's pipeline (its visible image). */
static inline void recon_test_spp_range(const ReconPipeline *p, int *spp_min, int *spp_max)
{
    const GBuffer *g = recon_pipeline_gbuffer(p);
    size_t n = (size_t)g->frame.width * (size_t)g->frame.height;
    *spp_min = -1;
    *spp_max = -1;
    for (size_t i = 0; i < n; ++i) {
        int k = (int)g->frame.spp[i];
        if (*spp_min < 0 || k < *spp_min) *spp_min = k;
        if (k > *spp_max) *spp_max = k;
    }
}

static inline double rel_mse(const float *img, const float *ref, size_t n3)
{
    double s = 0;
    for (size_t i = 0; i < n3; ++i) {
        double e = (double)img[i] - ref[i];
        s += e * e / ((double)ref[i] * ref[i] + 0.01);
    }
    return s / (double)n3;
}

/* The mean relMSE against ref (n3 floats) of `filter` at spp over seeds 1..seeds (a seed whose
 * render fails counts as a failed check and adds nothing). */
static inline double recon_test_seeds_rel_mse(const char *text, const char *filter, int spp, unsigned seeds, const float *ref,
                                              size_t n3)
{
    double e = 0.0;
    for (unsigned seed = 1; seed <= seeds; ++seed) {
        ReconOptions o = {.filter = filter, .spp = spp};
        float *img = recon_test_render(text, seed, &o, NULL, NULL);
        CHECK(img != NULL);
        if (img) e += rel_mse(img, ref, n3) / seeds;
        free(img);
    }
    return e;
}

/* recon_test_render_pipeline with --filter filter and --spp spp (0: none) as the only options. */
static inline float *recon_test_render_spp(const char *text, const char *filter, unsigned seed, int spp,
                                           ReconPipelineCheck check, void *ctx)
{
    ReconOptions o = {.filter = filter, .spp = spp};
    return recon_test_render_pipeline(text, seed, &o, check, ctx);
}

/* The AOV called name of a res_px x res_px frame (checked: NULL when it is missing or the
 * frame has another size). */
static inline const float *recon_test_frame_aov(const ReconPipeline *p, const char *name, int res_px)
{
    const ReconResult *res = recon_pipeline_result(p);
    const GBuffer *g = recon_pipeline_gbuffer(p);
    const float *aov = recon_test_aov(res, name);
    bool ok = aov && res->width == res_px && res->height == res_px && g->width == res_px && g->height == res_px;
    CHECK(ok);
    return ok ? aov : NULL;
}

/* Under a --spp budget with pass 1 at share of it: 1 if pass 1's count or the frame's average
 * (the budget) is wrong, plus the pixels with fewer samples than pass 1. */
static inline long recon_test_budget_wrong(const ReconPipeline *p, float share, int budget)
{
    const ReconResult *res = recon_pipeline_result(p);
    const GBuffer *g = recon_pipeline_gbuffer(p);
    int pass1 = (int)lroundf(share * (float)budget);
    long wrong = res->pass1_spp != pass1 || fabs(res->spp_avg - budget) > 1e-3;
    for (size_t i = 0; i < (size_t)res->width * (size_t)res->height; ++i) wrong += g->frame.spp[i] < (float)pass1;
    return wrong;
}

/* The same over the n pixels (3 floats each) with mask[i] == want. */
static inline double rel_mse_where(const float *img, const float *ref, const unsigned char *mask, int want, size_t n)
{
    double s = 0;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        if (mask[i] != want) continue;
        s += rel_mse(img + 3 * i, ref + 3 * i, 3);
        ++count;
    }
    return count ? s / (double)count : 0.0;
}

#endif
