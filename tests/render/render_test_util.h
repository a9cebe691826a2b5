/* Helpers for the renderer tests: render scene text into a Frame. */
#ifndef WEDGE_TESTS_RENDER_TEST_UTIL_H
#define WEDGE_TESTS_RENDER_TEST_UTIL_H

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/frame.h"
#include "render/light.h"
#include "render/renderer.h"
#include "render/tracer.h"
#include "scene/scene_desc.h"

typedef struct {
    SceneDesc scene;
    Renderer *r;
    Frame frame;
    RenderStats stats;
} TestRender;

/* Parses text and renders it (1 pass), every sample record fed to sink (may be NULL). opt
 * may be NULL. Returns false (message printed) on any failure. */
static inline bool test_render_sink(const char *text, const RenderOptions *opt, SampleSink *sink, TestRender *t)
{
    memset(t, 0, sizeof *t);
    Diag err = {0};
    if (!scene_parse_string(text, strlen(text), "<test>", NULL, &t->scene, &err)) {
        fprintf(stderr, "parse failed: %s\n", err.message);
        return false;
    }
    scene_analyze_effects(&t->scene);
    RenderOptions o = {0};
    if (opt) o = *opt;
    if (!renderer_create(&t->scene, &o, &t->r, &err)) {
        fprintf(stderr, "renderer_create failed: %s\n", err.message);
        scene_desc_free(&t->scene);
        return false;
    }
    if (!frame_init(&t->frame, renderer_width(t->r), renderer_height(t->r))) return false;
    render_pass(t->r, 0, NULL, renderer_spp(t->r), &t->frame, sink);
    t->stats = renderer_stats(t->r);
    return true;
}

/* test_render_sink without a sink. */
static inline bool test_render(const char *text, const RenderOptions *opt, TestRender *t)
{
    return test_render_sink(text, opt, NULL, t);
}

static inline void test_render_free(TestRender *t)
{
    frame_free(&t->frame);
    renderer_destroy(t->r);
    scene_desc_free(&t->scene);
}

/* Parses text and builds its tracer (tr zeroed first); false (message printed) on failure,
 * with the scene freed. */
static inline bool test_build_tracer(const char *text, SceneDesc *scene, Tracer *tr)
{
    Diag err = {0};
    memset(tr, 0, sizeof *tr);
    if (!scene_parse_string(text, strlen(text), "<test>", NULL, scene, &err)) {
        fprintf(stderr, "parse failed: %s\n", err.message);
        return false;
    }
    if (!tracer_build(tr, scene, 1, &err)) {
        fprintf(stderr, "tracer_build failed: %s\n", err.message);
        scene_desc_free(scene);
        return false;
    }
    return true;
}

/* Appends printf-formatted text at text + *len (cap bytes in all); false when it does not fit. */
static inline bool test_appendf(char *text, size_t cap, size_t *len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int w = *len < cap ? vsnprintf(text + *len, cap - *len, fmt, ap) : -1;
    va_end(ap);
    if (w < 0 || *len + (size_t)w >= cap) return false;
    *len += (size_t)w;
    return true;
}

/* Appends a trianglemesh's "point3 P" and "integer indices" for a grid of cols x rows quads to
 * text (cap bytes in all): the points at(ctx, c, r, p) for c <= cols, r <= rows, row by row, and
 * each quad as the triangles (v, v+1, v+cols+2) and (v, v+cols+2, v+cols+1), v its lower corner.
 * false when text is too short. */
static inline bool test_grid_mesh(char *text, size_t cap, int cols, int rows, void (*at)(void *ctx, int c, int r, double p[3]),
                                  void *ctx)
{
    size_t len = strlen(text);
    bool ok = test_appendf(text, cap, &len, "\"point3 P\" [");
    for (int r = 0; r <= rows; ++r)
        for (int c = 0; c <= cols && ok; ++c) {
            double p[3];
            at(ctx, c, r, p);
            ok = test_appendf(text, cap, &len, " %.9g %.9g %.9g", p[0], p[1], p[2]);
        }
    ok = ok && test_appendf(text, cap, &len, " ] \"integer indices\" [");
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols && ok; ++c) {
            int v = r * (cols + 1) + c;
            ok = test_appendf(text, cap, &len, " %d %d %d  %d %d %d", v, v + 1, v + cols + 2, v, v + cols + 2, v + cols + 1);
        }
    return ok && test_appendf(text, cap, &len, " ]");
}

/* A scene's tracer and lights (test_build_lights). */
typedef struct {
    SceneDesc scene;
    Tracer tr;
    LightSet L;
} TestLights;

/* Parses text and builds its tracer and lights; false (message printed) on failure, with
 * everything freed. */
static inline bool test_build_lights(const char *text, TestLights *b)
{
    if (!test_build_tracer(text, &b->scene, &b->tr)) return false;
    Diag err = {0};
    if (lights_build(&b->L, &b->scene, &b->tr, &err)) return true;
    fprintf(stderr, "lights_build: %s\n", err.message);
    tracer_free(&b->tr);
    scene_desc_free(&b->scene);
    return false;
}

static inline void test_lights_free(TestLights *b)
{
    lights_free(&b->L);
    tracer_free(&b->tr);
    scene_desc_free(&b->scene);
}

/* Mean colour of pixel (x, y). */
static inline void test_pixel(const TestRender *t, int x, int y, double rgb[3])
{
    size_t i = (size_t)y * (size_t)t->frame.width + (size_t)x;
    for (int c = 0; c < 3; ++c) rgb[c] = t->frame.spp[i] > 0 ? t->frame.color[3 * i + c] / t->frame.spp[i] : 0.0;
}

/* True when every sum in the frame is finite. */
static inline bool test_frame_finite(const Frame *f)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    const float *planes3[] = {f->color, f->direct, f->indirect, f->emission, f->albedo, f->normal};
    for (size_t k = 0; k < sizeof planes3 / sizeof planes3[0]; ++k)
        for (size_t i = 0; i < 3 * n; ++i)
            if (!isfinite(planes3[k][i])) return false;
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(f->depth[i]) || !isfinite(f->hits[i]) || !isfinite(f->spp[i])) return false;
    return true;
}

/* Mean of the colour over the whole image (average of the three channels). */
static inline double test_mean(const TestRender *t)
{
    size_t n = (size_t)t->frame.width * (size_t)t->frame.height;
    double s = 0.0;
    for (size_t i = 0; i < n; ++i)
        if (t->frame.spp[i] > 0)
            s += (t->frame.color[3 * i] + t->frame.color[3 * i + 1] + t->frame.color[3 * i + 2]) / (3.0 * t->frame.spp[i]);
    return s / (double)n;
}

#endif
