/* wedge preview [SCENE] [--res WxH] [--filter NAME] [--spp N] [--time S] [--view NAME]
 *               [--cl-device D] [--seed N] [--threads N] [--outdir DIR] [--exit-at-target]
 *
 * A window that shows the image while it renders: a worker thread runs the reconstruction
 * pipeline's steps (recon_pipeline_step: each adds samples to every pixel and filters again,
 * narrower), and the window thread shows each new image through the OpenColorIO view,
 * handling events at least every 50 ms so the window never stalls on rendering.
 *
 * Keys: f filtered / unfiltered, a cycle layers (image, samples per pixel, each filter layer,
 * albedo, normal), s save (EXR and PNG), + / - exposure, space pause / resume, q or Esc quit.
 * The pointer's pixel (value, samples, filter width) is shown in the title. */
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "app/commands.h"
#include "app/render_args.h"
#include "app/render_output.h"
#include "core/clock.h"
#include "core/diag.h"
#include "core/false_colour.h"
#include "io/ocio.h"
#include "recon/pipeline.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

#ifdef WEDGE_SDL
#include "app/preview_window.h"
#endif

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wedge preview [SCENE] [--res WxH] [--filter NAME] [--mu X] [--spp N] [--time S]\n"
            "                     [--view NAME] [--cl-device D] [--seed N] [--threads N] [--sampler KIND]\n"
            "                     [--outdir DIR] [--exit-at-target]\n\n"
            "Renders a pbrt-v4 scene (without SCENE: the embedded default scene) into a window,\n"
            "progressively: each step adds samples to every pixel and filters again, narrower, so\n"
            "the image converges to the Monte Carlo answer. Options as for 'wedge render', plus:\n\n"
            "  --spp N           stop adding samples at N per pixel on average (the window stays open)\n"
            "  --time S          stop after S seconds (the window stays open)\n"
            "  --outdir DIR      where the s key saves (default: next to the scene, or here)\n"
            "  --exit-at-target  close the window when --spp or --time is reached (scripts)\n\n"
            "keys: f filtered/unfiltered   a cycle layers (image, spp, filter widths, albedo, normal)\n"
            "      s save EXR + PNG   + / - exposure   space pause/resume   q or Esc quit\n");
}

/* ---- what the worker hands the window after each step ---- */

enum { LAYER_IMAGE = 0, LAYER_SPP = 1 }; /* then the filter layers, albedo, normal */

typedef struct {
    int width, height;
    float *filtered, *plain;           /* rgb */
    float *spp, *albedo, *normal;      /* spp 1, others 3 per pixel */
    float *aov[RECON_AOV_MAX];
    char aov_name[RECON_AOV_MAX][64];
    int aov_count;
    ReconResult res;                   /* scalars and choice; res.rgb points at filtered */
    double seconds;
    int generation;                    /* bumped by every step */
} Snapshot;

typedef struct {
    pthread_mutex_t lock;
    pthread_cond_t wake;
    Snapshot snap;
    bool paused, quit, done;           /* done: target reached or failed */
    bool failed;
    Diag diag;
    volatile sig_atomic_t cancel;      /* the renderer's flag: a quit stops a step quickly */
    /* the worker's own */
    ReconPipeline *pipe;
    const Renderer *r;
    int spp_target;                    /* 0: none */
    double time_target, t0;
} Shared;

static bool snapshot_init(Snapshot *s, int w, int h)
{
    memset(s, 0, sizeof *s);
    size_t n = (size_t)w * (size_t)h;
    s->width = w, s->height = h;
    s->filtered = calloc(3 * n, sizeof(float));
    s->plain = calloc(3 * n, sizeof(float));
    s->spp = calloc(n, sizeof(float));
    s->albedo = calloc(3 * n, sizeof(float));
    s->normal = calloc(3 * n, sizeof(float));
    for (int k = 0; k < RECON_AOV_MAX; ++k) s->aov[k] = calloc(n, sizeof(float));
    bool ok = s->filtered && s->plain && s->spp && s->albedo && s->normal;
    for (int k = 0; k < RECON_AOV_MAX; ++k) ok = ok && s->aov[k];
    return ok;
}

static void snapshot_free(Snapshot *s)
{
    free(s->filtered), free(s->plain), free(s->spp), free(s->albedo), free(s->normal);
    for (int k = 0; k < RECON_AOV_MAX; ++k) free(s->aov[k]);
}

/* Copies the pipeline's state after a step (called with the lock held). */
static void snapshot_take(Snapshot *s, const ReconPipeline *pipe, double seconds)
{
    const ReconResult *res = recon_pipeline_result(pipe);
    const Frame *f = &recon_pipeline_gbuffer(pipe)->frame;
    size_t n = (size_t)s->width * (size_t)s->height;
    memcpy(s->filtered, res->rgb, 3 * n * sizeof(float));
    memcpy(s->spp, f->spp, n * sizeof(float));
    frame_resolve3(f, f->color, s->plain);
    frame_resolve3(f, f->albedo, s->albedo);
    frame_resolve_normal(f, s->normal);
    s->aov_count = res->aov_count;
    for (int k = 0; k < res->aov_count; ++k) {
        memcpy(s->aov[k], res->aovs[k].data, n * sizeof(float));
        snprintf(s->aov_name[k], sizeof s->aov_name[k], "%s", res->aovs[k].name);
    }
    s->res = *res;
    s->res.rgb = s->filtered;
    for (int k = 0; k < res->aov_count; ++k) s->res.aovs[k].data = s->aov[k];
    s->seconds = seconds;
    s->generation++;
}

/* ---- the worker: steps until the target, quit or failure ---- */

static void *worker_main(void *arg)
{
    Shared *sh = arg;
    for (;;) {
        pthread_mutex_lock(&sh->lock);
        while (sh->paused && !sh->quit) pthread_cond_wait(&sh->wake, &sh->lock);
        bool quit = sh->quit;
        int steps = sh->snap.res.steps;
        double spp_now = sh->snap.res.spp_avg;
        pthread_mutex_unlock(&sh->lock);
        if (quit) break;
        double elapsed = clock_wall_seconds() - sh->t0;
        bool reached = steps > 0 && ((sh->spp_target > 0 && spp_now + 1e-9 >= sh->spp_target) ||
                                     (sh->time_target > 0.0 && elapsed >= sh->time_target));
        if (reached) break;
        /* each step capped to what is left of the targets, at the rate measured so far */
        double cap = sh->spp_target > 0 ? (double)sh->spp_target : 0.0;
        if (steps > 0 && sh->time_target > 0.0) {
            double t_cap = spp_now + (sh->time_target - elapsed) * spp_now / fmax(elapsed, 1e-6);
            cap = cap > 0.0 ? fmin(cap, t_cap) : t_cap;
        }
        Diag d = {0};
        bool ok = recon_pipeline_step(sh->pipe, cap, &d);
        pthread_mutex_lock(&sh->lock);
        if (!ok) {
            sh->failed = true;
            sh->diag = d;
        } else if (!recon_pipeline_result(sh->pipe)->cancelled) {
            snapshot_take(&sh->snap, sh->pipe, clock_wall_seconds() - sh->t0);
        }
        bool stop = !ok || recon_pipeline_result(sh->pipe)->cancelled ||
                    (cap > 0.0 && recon_pipeline_result(sh->pipe)->spp_avg == spp_now && steps > 0);
        pthread_mutex_unlock(&sh->lock);
        if (stop) break;
    }
    pthread_mutex_lock(&sh->lock);
    sh->done = true;
    pthread_mutex_unlock(&sh->lock);
    return NULL;
}

/* ---- the display: a layer of the snapshot through the view, to 8 bits ---- */

typedef struct {
    int layer;                /* LAYER_IMAGE, LAYER_SPP, 2 .. 2 + aov_count - 1, then albedo, normal */
    bool filtered;
    float exposure_stops;
} ViewState;

static int layer_count(const Snapshot *s) { return 2 + s->aov_count + 2; }

static const char *layer_name(const Snapshot *s, int layer)
{
    if (layer == LAYER_IMAGE) return "image";
    if (layer == LAYER_SPP) return "samples per pixel";
    if (layer < 2 + s->aov_count) return s->aov_name[layer - 2];
    return layer == 2 + s->aov_count ? "albedo" : "normal";
}

/* display-referred rgb (0..1) of the chosen layer into rgb (3 floats per pixel) */
static void layer_display(const Snapshot *s, const ViewState *v, const OcioView *ocio, float *rgb)
{
    size_t n = (size_t)s->width * (size_t)s->height;
    if (v->layer == LAYER_IMAGE) {
        const float *src = v->filtered ? s->filtered : s->plain;
        float gain = exp2f(v->exposure_stops);
        for (size_t i = 0; i < 3 * n; ++i) rgb[i] = src[i] * gain;
        ocio_view_apply(ocio, rgb, n);
    } else if (v->layer == LAYER_SPP) {
        false_colour_image(s->spp, n, rgb);
    } else if (v->layer < 2 + s->aov_count) {
        false_colour_image(s->aov[v->layer - 2], n, rgb);
    } else if (v->layer == 2 + s->aov_count) {
        memcpy(rgb, s->albedo, 3 * n * sizeof(float));
    } else {
        for (size_t i = 0; i < 3 * n; ++i) rgb[i] = 0.5f * s->normal[i] + 0.5f;
    }
}

static void to_rgb8(const float *rgb, size_t n3, uint8_t *out)
{
    for (size_t i = 0; i < n3; ++i) {
        float v = rgb[i];
        v = isfinite(v) ? (v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v) : 0.0f;
        out[i] = (uint8_t)lrintf(v * 255.0f);
    }
}

/* "stem" of the scene path for saved files: dir/name.pbrt -> name */
static void scene_stem(const char *path, char *out, size_t size)
{
    const char *base = path ? strrchr(path, '/') : NULL;
    base = base ? base + 1 : (path ? path : "default");
    const char *dot = strrchr(base, '.');
    int len = dot && dot > base ? (int)(dot - base) : (int)strlen(base);
    snprintf(out, size, "%.*s", len, base);
}

/* s: the current image as EXR (linear) and PNG (as shown, exposure included), atomically. */
static bool save_image(const Snapshot *s, const ViewState *v, const RenderArgs *a, const char *outdir,
                       const Renderer *r, Diag *d, char *saved, size_t saved_size)
{
    char dir[4096], stem[512], exr[4700], png[4700];
    if (outdir) snprintf(dir, sizeof dir, "%s", outdir);
    else if (a->scene_path && strrchr(a->scene_path, '/'))
        snprintf(dir, sizeof dir, "%.*s", (int)(strrchr(a->scene_path, '/') - a->scene_path), a->scene_path);
    else snprintf(dir, sizeof dir, ".");
    scene_stem(a->scene_path, stem, sizeof stem);
    snprintf(exr, sizeof exr, "%s/%s-preview-%.0fspp.exr", dir, stem, s->res.spp_avg);
    snprintf(png, sizeof png, "%s/%s-preview-%.0fspp.png", dir, stem, s->res.spp_avg);
    Frame shape = {0};
    shape.width = s->width, shape.height = s->height;
    RenderOutputInfo info = {a->scene_path ? a->scene_path : "<default>", a->filter, a->seed, renderer_sampler(r),
                             s->seconds, false, a->view};
    long long guarded = 0;
    ReconResult res = s->res;
    res.rgb = v->filtered ? s->filtered : s->plain;
    if (!render_output_write(exr, &shape, &res, &info, &guarded, d)) return false;
    size_t n3 = 3 * (size_t)s->width * (size_t)s->height;
    float *shown = malloc(n3 * sizeof(float));
    if (!shown) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory saving the preview");
        return false;
    }
    float gain = exp2f(v->exposure_stops);
    for (size_t i = 0; i < n3; ++i) shown[i] = res.rgb[i] * gain;
    bool ok = ocio_write_png(png, s->width, s->height, shown, a->view, d);
    free(shown);
    snprintf(saved, saved_size, "%s and %s", exr, png);
    return ok;
}

/* The title: progress and methods, or the pixel under the pointer. */
static void make_title(const Snapshot *s, const ViewState *v, bool paused, bool done, int px, int py, char *out,
                       size_t size)
{
    int at = snprintf(out, size, "wedge preview - %.1f spp, %.1f s", s->res.spp_avg, s->seconds);
    for (int e = 0; e < EFFECT_COUNT && at < (int)size; ++e)
        if (s->res.choice.reason[e][0])
            at += snprintf(out + at, size - (size_t)at, ", %s: %s", effect_name((Effect)e),
                           recon_choice_name(&s->res.choice, (Effect)e));
    if (at < (int)size)
        at += snprintf(out + at, size - (size_t)at, " - %s%s%s%s", layer_name(s, v->layer),
                       v->layer == LAYER_IMAGE && !v->filtered ? " (unfiltered)" : "", paused ? " [paused]" : "",
                       done ? " [done]" : "");
    if (v->exposure_stops != 0.0f && at < (int)size)
        at += snprintf(out + at, size - (size_t)at, " [%+.1f EV]", (double)v->exposure_stops);
    if (px >= 0 && py >= 0 && px < s->width && py < s->height && at < (int)size) {
        size_t i = (size_t)py * (size_t)s->width + (size_t)px;
        const float *c = (v->filtered ? s->filtered : s->plain) + 3 * i;
        at += snprintf(out + at, size - (size_t)at, " - (%d, %d): %.4g %.4g %.4g, %.0f spp", px, py, (double)c[0],
                       (double)c[1], (double)c[2], (double)s->spp[i]);
        for (int k = 0; k < s->aov_count && at < (int)size; ++k)
            at += snprintf(out + at, size - (size_t)at, ", %s %.3g", s->aov_name[k], (double)s->aov[k][i]);
    }
}

int cmd_preview(int argc, char **argv)
{
#ifndef WEDGE_SDL
    (void)argc, (void)argv;
    fprintf(stderr, "wedge preview: this wedge was built without SDL2: install libsdl2-dev (tools/setup does) and "
                    "rebuild, or render without a window: wedge render SCENE --time SECONDS --checkpoint 10\n");
    return WEDGE_EXIT_RUNTIME;
#else
    /* the preview's own options first; the rest are wedge render's */
    const char *outdir = NULL;
    bool exit_at_target = false;
    char **rest = calloc((size_t)argc + 1, sizeof *rest);
    if (!rest) return WEDGE_EXIT_RUNTIME;
    int nrest = 0;
    for (int i = 0; i < argc; ++i) {
        if (!strcmp(argv[i], "--outdir") && i + 1 < argc) outdir = argv[++i];
        else if (!strcmp(argv[i], "--exit-at-target")) exit_at_target = true;
        else if (!strcmp(argv[i], "--outdir")) {
            fprintf(stderr, "wedge preview: option '--outdir' needs a value\n");
            free(rest);
            return WEDGE_EXIT_USAGE;
        } else rest[nrest++] = argv[i];
    }
    RenderArgs a;
    int rc = parse_render_args(nrest, rest, "preview", &a);
    free(rest);
    if (rc != WEDGE_EXIT_OK) return rc;
    if (a.help) {
        usage(stdout);
        return WEDGE_EXIT_OK;
    }
    if (a.out_count || a.report_path || a.aovs || a.visualize || a.checkpoint > 0.0) {
        fprintf(stderr, "wedge preview: -o, --report, --aovs, --visualize and --checkpoint are wedge render's; the "
                        "preview saves with the s key (--outdir)\n");
        return WEDGE_EXIT_USAGE;
    }
    if (exit_at_target && !a.spp && !(a.time_budget > 0.0)) {
        fprintf(stderr, "wedge preview: --exit-at-target needs a target: --spp N or --time S\n");
        return WEDGE_EXIT_USAGE;
    }
    Diag err = {0};
    if (!preview_display_available()) { /* before anything is rendered */
        PreviewWindow *none = NULL;
        preview_window_open(1, 1, "", &none, &err);
        diag_print(&err);
        return WEDGE_EXIT_RUNTIME;
    }
    if (!preview_window_library_load(&err)) { /* SDL2 missing: said before anything is rendered too */
        diag_print(&err);
        return err.exit_code;
    }
    OcioView *ocio = NULL;
    if (!ocio_view_open(a.view, &ocio, &err)) {
        diag_print(&err);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_USAGE;
    }
    SceneDesc scene;
    memset(&scene, 0, sizeof scene);
    bool parsed = a.scene_path ? scene_parse_file(a.scene_path, &scene, &err)
                               : scene_parse_string(wedge_default_scene, strlen(wedge_default_scene), "<default>",
                                                    NULL, &scene, &err);
    if (!parsed) {
        diag_print(&err);
        ocio_view_close(ocio);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
    }
    Shared sh;
    memset(&sh, 0, sizeof sh);
    pthread_mutex_init(&sh.lock, NULL);
    pthread_cond_init(&sh.wake, NULL);
    RenderOptions ro = {0};
    ro.width = a.width, ro.height = a.height, ro.seed = a.seed, ro.threads = a.threads;
    ro.sampler_set = a.sampler_set, ro.sampler = a.sampler;
    ro.pixel_filter = a.pixel_filter;
    ro.cancel = &sh.cancel;
    Renderer *r = NULL;
    ReconPipeline *pipe = NULL;
    PreviewWindow *win = NULL;
    uint8_t *rgb8 = NULL;
    float *disp = NULL;
    int exit_code = WEDGE_EXIT_RUNTIME;
    bool worker_started = false;
    pthread_t worker;
    if (!renderer_create(&scene, &ro, &r, &err)) goto fail;
    if (!a.quiet)
        for (int i = 0; i < scene.warning_count; ++i) fprintf(stderr, "%s\n", scene.warnings[i]);
    ReconOptions po = {.filter = a.filter, .mu = a.mu, .cl_device = a.cl_device,
                       .mem_limit_bytes = (size_t)a.mem_limit, .method_options = {a.maaf_pairs},
                       .no_overscan = a.no_overscan};
    if (!recon_pipeline_create(r, &po, &pipe, &err)) goto fail;
    /* the visible image (without an overscan band) */
    int w = recon_pipeline_result(pipe)->width, h = recon_pipeline_result(pipe)->height;
    size_t n = (size_t)w * (size_t)h;
    if (!snapshot_init(&sh.snap, w, h) || !(rgb8 = malloc(3 * n)) || !(disp = malloc(3 * n * sizeof(float)))) {
        diag_set(&err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for a %dx%d preview", w, h);
        goto fail;
    }
    char title[1024];
    snprintf(title, sizeof title, "wedge preview - %s - starting", a.scene_path ? a.scene_path : "<default>");
    if (!preview_window_open(w, h, title, &win, &err)) goto fail;
    memset(rgb8, 0, 3 * n);
    if (!preview_window_show(win, rgb8, &err)) goto fail;

    sh.pipe = pipe;
    sh.r = r;
    sh.spp_target = a.spp;
    sh.time_target = a.time_budget;
    sh.t0 = clock_wall_seconds();
    if (pthread_create(&worker, NULL, worker_main, &sh) != 0) {
        diag_set(&err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot start the render thread");
        goto fail;
    }
    worker_started = true;

    ViewState view = {LAYER_IMAGE, true, 0.0f};
    int shown_generation = 0, mouse_x = -1, mouse_y = -1;
    bool redraw = false, quit = false;
    exit_code = WEDGE_EXIT_OK;
    while (!quit) {
        PreviewEvent ev = preview_window_wait(win, 50);
        pthread_mutex_lock(&sh.lock);
        if (ev.kind == PREVIEW_EVENT_QUIT || (ev.kind == PREVIEW_EVENT_KEY && (ev.key == 'q' || ev.key == 27))) quit = true;
        else if (ev.kind == PREVIEW_EVENT_KEY && ev.key == 'f') view.filtered = !view.filtered, redraw = true;
        else if (ev.kind == PREVIEW_EVENT_KEY && ev.key == 'a') view.layer = (view.layer + 1) % layer_count(&sh.snap), redraw = true;
        else if (ev.kind == PREVIEW_EVENT_KEY && ev.key == '+') view.exposure_stops += 0.5f, redraw = true;
        else if (ev.kind == PREVIEW_EVENT_KEY && ev.key == '-') view.exposure_stops -= 0.5f, redraw = true;
        else if (ev.kind == PREVIEW_EVENT_KEY && ev.key == ' ') {
            sh.paused = !sh.paused;
            pthread_cond_broadcast(&sh.wake);
            redraw = true;
        } else if (ev.kind == PREVIEW_EVENT_MOUSE) mouse_x = ev.x, mouse_y = ev.y, redraw = true;
        else if (ev.kind == PREVIEW_EVENT_KEY && ev.key == 's' && sh.snap.generation > 0) {
            char saved[9500];
            Diag serr = {0};
            if (save_image(&sh.snap, &view, &a, outdir, r, &serr, saved, sizeof saved))
                fprintf(stderr, "wedge preview: saved %s\n", saved);
            else
                diag_print(&serr);
        }
        if (sh.failed) {
            diag_print(&sh.diag);
            exit_code = sh.diag.exit_code ? sh.diag.exit_code : WEDGE_EXIT_RUNTIME;
            sh.failed = false;
        }
        if (sh.snap.generation != shown_generation) shown_generation = sh.snap.generation, redraw = true;
        if (exit_at_target && sh.done) quit = true;
        if (redraw && sh.snap.generation > 0) {
            layer_display(&sh.snap, &view, ocio, disp);
            to_rgb8(disp, 3 * n, rgb8);
            make_title(&sh.snap, &view, sh.paused, sh.done, mouse_x, mouse_y, title, sizeof title);
        }
        pthread_mutex_unlock(&sh.lock);
        if (redraw && shown_generation > 0) {
            preview_window_set_title(win, title);
            if (!preview_window_show(win, rgb8, &err)) {
                diag_print(&err);
                exit_code = WEDGE_EXIT_RUNTIME;
                quit = true;
            }
        }
        redraw = false;
    }
    /* quit: stop the step in flight quickly (its samples are dropped with the window) */
    pthread_mutex_lock(&sh.lock);
    sh.quit = true;
    sh.cancel = 1;
    pthread_cond_broadcast(&sh.wake);
    pthread_mutex_unlock(&sh.lock);
    pthread_join(worker, NULL);
    worker_started = false;
    if (!a.quiet)
        fprintf(stderr, "wedge preview: %.1f samples per pixel in %.2f s (%d steps)\n", sh.snap.res.spp_avg,
                sh.snap.seconds, sh.snap.res.steps);
    goto done;
fail:
    diag_print(&err);
    exit_code = err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
done:
    if (worker_started) {
        sh.quit = true;
        sh.cancel = 1;
        pthread_cond_broadcast(&sh.wake);
        pthread_join(worker, NULL);
    }
    preview_window_close(win);
    free(rgb8);
    free(disp);
    snapshot_free(&sh.snap);
    recon_pipeline_destroy(pipe);
    renderer_destroy(r);
    scene_desc_free(&scene);
    ocio_view_close(ocio);
    pthread_mutex_destroy(&sh.lock);
    pthread_cond_destroy(&sh.wake);
    return exit_code;
#endif
}
