/* wedge render [SCENE] [-o OUT] [--spp N] [--res WxH] [--seed N] [--threads N] [--aovs]
 *              [--report FILE.json] [--quiet] [--sampler stratified|sobol]
 *              [--filter auto|METHOD|none] [--mu X] [--mem-limit SIZE] [--cl-device N|NAME]
 *              [--visualize] [--view NAME]
 *
 * Parses the scene (or the embedded default), renders and reconstructs it through the
 * reconstruction pipeline (recon/pipeline.h, every --filter including none) and writes an EXR (float R G B A, optional AOV layers, header attributes) or an 8-bit PNG
 * through an OpenColorIO view (issue 4: every display-referred output goes through OCIO).
 * Ctrl-C stops the render after the rows in flight and writes what was sampled. */
#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "app/commands.h"
#include "app/output_check.h"
#include "app/render_args.h"
#include "app/render_output.h"
#include "app/run_report.h"
#include "core/clock.h"
#include "core/diag.h"
#include "io/ocio.h"
#include "recon/dist.h"
#include "recon/pipeline.h"
#include "recon/select.h"
#include "render/frame.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"


static void usage(FILE *f)
{
    char views[256], filters[256];
    Diag verr = {0};
    recon_filter_choices(filters, sizeof filters);
    if (!ocio_list_views(views, sizeof views, &verr)) snprintf(views, sizeof views, "(config not readable)");
    fprintf(f,
            "usage: wedge render [SCENE] [-o OUT] [--spp N] [--res WxH] [--seed N] [--threads N]\n"
            "                    [--aovs] [--report FILE.json] [--quiet] [--sampler stratified|sobol]\n"
            "                    [--pixel-filter NAME]\n"
            "                    [--filter NAME] [--mu X] [--mem-limit SIZE] [--cl-device N|NAME]\n"
            "                    [--visualize] [--view NAME]\n\n"
            "Renders a pbrt-v4 scene (without SCENE: the embedded default scene) to OUT.\n\n"
            "  -o OUT          output image, repeatable (one render, several files); .png writes\n"
            "                  8-bit display-referred colour through OpenColorIO ($OCIO or the\n"
            "                  built-in config), anything else EXR\n"
            "                  (default: the scene's Film \"filename\")\n"
            "  --spp N         samples per pixel: with --filter none every pixel's count (default:\n"
            "                  the scene's pixelsamples); with a filter the average budget of the\n"
            "                  frame, spread over the pixels by the filter's plan (default: the\n"
            "                  filter's own, set by --mu)\n"
            "  --res WxH       image size in pixels (default: the scene's film)\n"
            "  --seed N        random seed (default 0); the image depends only on the seed\n"
            "  --threads N     worker threads (default: all cores; under mpirun, the rank's bound cores)\n"
            "  --aovs          add EXR layers albedo, N, Z, direct, indirect, emission, spp\n"
            "  --report FILE   write a JSON run report\n"
            "  --quiet         no progress bar and no warnings on stderr\n"
            "  --sampler KIND  stratified or sobol (default: mapped from the scene's Sampler)\n"
            "  --pixel-filter NAME  box, gaussian, triangle, mitchell or sinc with pbrt-v4's\n"
            "                  defaults (default: the scene's PixelFilter, else a box over the pixel)\n"
            "  --filter NAME   reconstruction, one of %s: auto (default) picks the\n"
            "                  measured best method for each effect the scene has ('wedge info\n"
            "                  --filters' lists the methods), none is plain Monte Carlo\n"
            "  --mu X          filter knob (> 0): larger means more samples and narrower filters;\n"
            "                  as X grows the result converges to Monte Carlo (default: each\n"
            "                  filter's default: 2 for shadows and indirect light, 1 for defocus);\n"
            "                  with --spp, --mu shapes the filters and --spp sets the samples\n"
            "  --maaf-pairs N  --filter maaf: filter pairs per 2D subspace, 2N-1 filters each,\n"
            "                  (2N-1)^2 in 4D (1..5); sets the light's, lens's and bounce's\n"
            "                  subspaces alike (default: 2 for the light, 3 for the lens and\n"
            "                  the bounce)\n"
            "  --overscan X    auto (default): when a filter reads samples beyond a pixel (lr),\n"
            "                  also trace a band that wide around the image and crop it, so the\n"
            "                  border is not biased; off: no band (to measure what it does)\n"
            "  --mem-limit S   memory for per-sample storage (filters that keep samples), e.g.\n"
            "                  512M or 8G (default: half the physical memory); a frame that needs\n"
            "                  more is refused before rendering\n"
            "  --cl-device D   OpenCL device by index or name substring (see 'wedge info --cl');\n"
            "                  default $WEDGE_CL_DEVICE, else the first GPU, else the first CPU\n"
            "  --time S        render progressively for S seconds (wall time of the whole command),\n"
            "                  then write: steps add samples to every pixel and filter again,\n"
            "                  each narrower; the first step is the ordinary frame\n"
            "  --checkpoint S  render progressively and write the current filtered image to every\n"
            "                  -o output every S seconds (atomically), until --time or --spp\n"
            "  --visualize     also write OUT-spp.png and a false-colour map per filter layer\n"
            "  --view NAME     OCIO view for PNG output (default: the display's default view);\n"
            "                  views: %s\n",
            filters, views);
}

/* ---- Ctrl-C ---- */

static volatile sig_atomic_t interrupt_flag = 0;

static void on_sigint(int sig)
{
    (void)sig;
    interrupt_flag = 1;
    signal(SIGINT, SIG_DFL); /* a second Ctrl-C kills the process */
}

/* Sample counts that are not powers of two suit the Sobol' sampler less (pbrt-v4 warns too):
 * past 16 spp its padding permutation walks, about 1.2x the render time per sample, and a
 * pixel's points are nets of unequal sizes, one per binary digit of spp, so smooth light
 * converges less well (indirect bench scene, 256x256: relMSE x spp 0.144 at 120 spp against
 * 0.126 at 128; docs/sampling.md). */
static void note_sobol_count(SamplerKind kind, int spp)
{
    if (kind != SAMPLER_SOBOL || spp < 2 || (spp & (spp - 1)) == 0) return;
    int below = 1;
    while (below * 2 < spp) below *= 2;
    fprintf(stderr,
            "wedge render: note: %d samples per pixel is not a power of two, which the Sobol' sampler handles less "
            "well (more time per sample past 16, slower convergence of smooth light); --spp %d or %d avoids it, or "
            "--sampler stratified\n",
            spp, below, below * 2);
}

/* ---- progressive rendering: --time, --checkpoint ---- */

typedef struct {
    const RenderArgs *a;
    ReconPipeline *pipe;
    const Renderer *r;
    const ReconDist *dist;
    const char *scene_name;
    double t_start;           /* the command's start (wall): --time counts from here */
} Progressive;

/* Writes the current image to every -o output (rank 0), atomically. */
static bool write_checkpoint(const Progressive *pr, Diag *err)
{
    const ReconResult *res = recon_pipeline_result(pr->pipe);
    const Frame *frame = &recon_pipeline_gbuffer(pr->pipe)->frame;
    RenderOutputInfo info = {pr->scene_name, pr->a->filter, pr->a->seed, renderer_sampler(pr->r),
                             clock_wall_seconds() - pr->t_start, pr->a->aovs, pr->a->view};
    long long guarded = 0;
    for (int k = 0; k < pr->a->out_count; ++k)
        if (!render_output_write(pr->a->out_paths[k], frame, res, &info, &guarded, err)) return false;
    if (!pr->a->quiet)
        fprintf(stderr, "wedge render: checkpoint at %.1f s, %.1f samples per pixel: %s\n", info.seconds, res->spp_avg,
                pr->a->out_paths[0]);
    return true;
}

/* Steps (recon_pipeline_step) until the target: --time (each step capped to the samples the
 * time left allows at the rate measured so far, so the budget is met, not overshot) or --spp
 * (each step capped to it); with --checkpoint each step is also capped to about one interval,
 * and the image is written after every step that ends one. Rank 0 decides and broadcasts, so
 * every MPI rank makes the same calls. */
static bool render_progressive(const Progressive *pr, Diag *err)
{
    const RenderArgs *a = pr->a;
    ReconDist *dist = (ReconDist *)pr->dist;
    if (!recon_pipeline_step(pr->pipe, 0.0, err)) return false; /* the ordinary frame */
    double t_render0 = pr->t_start, last_checkpoint = clock_wall_seconds();
    /* the visible image's pixels: spp_avg and the caps count samples per visible pixel */
    const ReconResult *first = recon_pipeline_result(pr->pipe);
    double pixels = (double)first->width * (double)first->height;
    for (;;) {
        const ReconResult *res = recon_pipeline_result(pr->pipe);
        int decision[2] = {0, 0}; /* continue?, the step's cap in 1/1024 samples per pixel */
        if (dist->rank == 0 && !res->cancelled) {
            double now = clock_wall_seconds();
            if (a->checkpoint > 0.0 && now - last_checkpoint >= a->checkpoint) {
                if (!write_checkpoint(pr, err)) return false;
                last_checkpoint = now;
            }
            double rate = res->spp_avg * pixels / fmax(now - t_render0, 1e-6); /* samples per second */
            double target = a->spp > 0 ? (double)a->spp : INFINITY, cap = target;
            if (a->time_budget > 0.0) cap = fmin(cap, res->spp_avg + (a->time_budget - (now - pr->t_start)) * rate / pixels);
            /* a step per checkpoint interval, but at least one sample per pixel (each step is a
             * reconstruction, about the cost of a few samples per pixel); the last one to the
             * --spp target goes all the way */
            if (a->checkpoint > 0.0) {
                double step_cap = res->spp_avg + fmax(a->checkpoint * rate / pixels, 1.0);
                cap = fmin(cap, target - step_cap < 1.0 ? target : step_cap);
            }
            /* worth a step: the target's last sample, or a twentieth of a sample per pixel */
            bool worth = cap >= target ? cap * pixels >= res->spp_avg * pixels + 1.0 : cap > res->spp_avg + 0.05;
            if (isfinite(cap) && worth && cap < 2.0e6) {
                decision[0] = 1;
                decision[1] = (int)(cap * 1024.0);
            }
        }
        if (!dist_broadcast_ints(dist, decision, 2, err)) return false;
        if (!decision[0]) return true;
        if (!recon_pipeline_step(pr->pipe, decision[1] / 1024.0, err)) return false;
    }
}

/* An error message, once: every rank meets the same usage and input errors, which rank 0
 * reports; a failure of this rank alone (memory, device) says which rank it was. */
static void print_error(const Diag *err, const ReconDist *dist)
{
    if (dist->rank == 0) diag_print(err);
    else if (err->exit_code != WEDGE_EXIT_USAGE && err->exit_code != WEDGE_EXIT_INPUT)
        fprintf(stderr, "wedge render (MPI rank %d of %d): %s\n", dist->rank, dist->ranks, err->message);
}

static int render_command(int argc, char **argv, ReconDist *dist)
{
    double t_start = clock_wall_seconds(), cpu_start = clock_cpu_seconds();
    RenderArgs a;
    int rc = parse_render_args(argc, argv, "render", &a);
    if (rc != WEDGE_EXIT_OK) return rc;
    if (a.help) {
        if (dist->rank == 0) usage(stdout);
        return WEDGE_EXIT_OK;
    }
    bool root = dist->rank == 0;
    if (!root) a.quiet = true; /* one progress bar and one set of warnings, rank 0's */

    Diag err = {0};
    if (a.view) {
        /* Check --view before rendering: a typo must not cost a whole render. */
        OcioView *ov = NULL;
        if (!ocio_view_open(a.view, &ov, &err)) {
            print_error(&err, dist);
            return err.exit_code ? err.exit_code : WEDGE_EXIT_USAGE;
        }
        ocio_view_close(ov);
    }

    SceneDesc scene;
    memset(&scene, 0, sizeof scene);
    bool parsed = a.scene_path ? scene_parse_file(a.scene_path, &scene, &err)
                               : scene_parse_string(wedge_default_scene, strlen(wedge_default_scene), "<default>", NULL,
                                                    &scene, &err);
    if (!parsed) {
        print_error(&err, dist);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
    }
    scene_analyze_effects(&scene);

    RenderOptions ro = {0};
    ro.width = a.width, ro.height = a.height, ro.seed = a.seed, ro.threads = a.threads;
    /* under mpirun, by default as many render threads as cores the rank is bound to (one with
     * Open MPI's default for up to 2 ranks), not one per core of the node on that one core */
    if (ro.threads <= 0 && dist->ranks > 1) ro.threads = dist_own_cores(dist);
    ro.spp = a.time_budget > 0.0 || a.checkpoint > 0.0 ? 0 : a.spp; /* progressive: the target, not the first step */
    ro.sampler_set = a.sampler_set, ro.sampler = a.sampler;
    ro.pixel_filter = a.pixel_filter;
    ro.cancel = &interrupt_flag;
    ProgressBar bar = {.out = stderr};
    if (!a.quiet && isatty(STDERR_FILENO)) ro.progress = progress_bar_update, ro.progress_ctx = &bar;

    if (a.out_count == 0) a.out_paths[a.out_count++] = scene.film.filename ? scene.film.filename : "pbrt.exr";
    /* every output writable and none of them an input, before anything is traced (rank 0
     * writes them) */
    bool outputs_ok = true;
    for (int k = 0; root && outputs_ok && k < a.out_count; ++k)
        outputs_ok = output_check(a.out_paths[k], "output image", &scene, &err);
    if (root && outputs_ok && a.report_path) outputs_ok = output_check(a.report_path, "report", &scene, &err);
    Renderer *r = NULL;
    bool built = outputs_ok && renderer_create(&scene, &ro, &r, &err);
    if (!built) print_error(&err, dist);
    /* every rank built its scene, or none renders (a rank left out would hang the others) */
    if (!dist_all_ok(dist, built)) {
        if (built && root) fprintf(stderr, "wedge render: another MPI rank could not build the scene (its message is above)\n");
        renderer_destroy(r);
        scene_desc_free(&scene);
        return built ? WEDGE_EXIT_RUNTIME : (err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME);
    }
    if (!a.quiet)
        for (int i = 0; i < scene.warning_count; ++i) fprintf(stderr, "%s\n", scene.warnings[i]);
    const char *out_path = a.out_paths[0];

    ReconOptions po = {0};
    po.filter = a.filter;
    po.mu = a.mu;
    po.method_options[0] = a.maaf_pairs; /* MAAF reads its pairs here (ReconSetup) */
    /* progressive: --spp is where the steps stop, the first step is the default frame */
    bool progressive = a.time_budget > 0.0 || a.checkpoint > 0.0;
    po.spp = progressive ? 0 : a.spp;
    po.cl_device = a.cl_device;
    po.mem_limit_bytes = (size_t)a.mem_limit;
    po.dist = dist;
    po.no_overscan = a.no_overscan;
    po.reads = render_args_reads(&a); /* the outputs' declaration: --filter none skips the rest */
    ReconPipeline *pipe = NULL;
    bool ok = recon_pipeline_create(r, &po, &pipe, &err);
    if (!ok) print_error(&err, dist);
    /* every rank exits with the failing rank's code (only rank 0 checks the OpenCL device) */
    int create_code = dist_max_int(dist, ok ? 0 : (err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME));
    if (ok && create_code != 0) { /* this rank is fine; another one says why it is not */
        recon_pipeline_destroy(pipe);
        renderer_destroy(r);
        scene_desc_free(&scene);
        return create_code;
    }
    if (ok && !a.quiet) {
        const ReconChoice *c = &recon_pipeline_result(pipe)->choice;
        if (!recon_choice_any(c)) note_sobol_count(renderer_sampler(r), a.spp > 0 ? a.spp : renderer_spp(r));
        /* an effect auto's fallback left to Monte Carlo, and why (recon/auto_fallback.h): not the
         * filter auto's table names (`wedge info` judges it the same way); a kept filter's numbers
         * are in --report */
        for (int e = 0; e < EFFECT_COUNT && root; ++e)
            if (effect_in(c->fell_back, (Effect)e))
                fprintf(stderr, "wedge render: --filter auto: %s: %s\n", effect_name((Effect)e), c->reason[e]);
        char warning[RECON_REASON_SIZE];
        if (root && recon_choice_moving_light_warning(c, warning, sizeof warning))
            fprintf(stderr, "wedge render: warning: %s\n", warning);
    }
    interrupt_flag = 0;
    void (*old_handler)(int) = signal(SIGINT, on_sigint);
    /* Under mpirun, Ctrl-C reaches mpirun, which sends the ranks SIGTERM (then SIGKILL after
     * its timeout): treated as Ctrl-C, the ranks finish the rows in flight together and rank 0
     * writes the samples taken. */
    void (*old_term)(int) = dist->ranks > 1 ? signal(SIGTERM, on_sigint) : SIG_ERR;
    const char *scene_name = a.scene_path ? a.scene_path : "<default>";
    Progressive pr = {&a, pipe, r, dist, scene_name, t_start};
    bool rendered = ok && (progressive ? render_progressive(&pr, &err) : recon_pipeline_render(pipe, &err));
    signal(SIGINT, old_handler == SIG_ERR ? SIG_DFL : old_handler);
    if (dist->ranks > 1) signal(SIGTERM, old_term == SIG_ERR ? SIG_DFL : old_term);
    if (ro.progress) progress_bar_finish(&bar);
    if (!rendered) {
        if (ok) print_error(&err, dist);
        recon_pipeline_destroy(pipe);
        renderer_destroy(r);
        scene_desc_free(&scene);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
    }
    const ReconResult *res = recon_pipeline_result(pipe);
    const Frame *frame = &recon_pipeline_gbuffer(pipe)->frame;
    bool complete = !res->cancelled;
    long long guarded = res->guarded_events;
    if (!complete && !a.quiet) fprintf(stderr, "wedge render: interrupted; writing the samples taken so far\n");
    /* a cleaned-up value is never hidden: said here, counted in the report */
    if (res->nonfinite_pixels > 0 && root)
        fprintf(stderr, "wedge render: warning: %lld pixel%s came out NaN or infinite and %s written as 0 (the report's "
                        "nonfinite_pixels; guarded_events counts every value replaced)\n",
                res->nonfinite_pixels, res->nonfinite_pixels == 1 ? "" : "s", res->nonfinite_pixels == 1 ? "was" : "were");

    RenderStats st = renderer_stats(r);
    /* WEDGE_DIST_LOG: each rank's own rays, the work its tiles took (tools/bench-mpi) */
    if (getenv("WEDGE_DIST_LOG") && dist->ranks > 1)
        fprintf(stderr, "dist-rays rank %d: primary %lld shadow %lld indirect %lld bsdf %lld\n", dist->rank,
                st.rays_primary, st.rays_shadow, st.rays_indirect, st.rays_bsdf);
    /* the ranks' rays and guards, all of them (collectives: every rank takes part) */
    st.rays_primary = dist_sum_ll(dist, st.rays_primary), st.rays_shadow = dist_sum_ll(dist, st.rays_shadow);
    st.rays_indirect = dist_sum_ll(dist, st.rays_indirect), st.rays_bsdf = dist_sum_ll(dist, st.rays_bsdf);
    st.guarded_events = dist_sum_ll(dist, st.guarded_events);
    guarded += st.guarded_events;
    double seconds_total = clock_wall_seconds() - t_start;
    int exit_code = WEDGE_EXIT_OK;
    if (!root) { /* rank 0 writes the image, the layers and the report */
        recon_pipeline_destroy(pipe);
        renderer_destroy(r);
        scene_desc_free(&scene);
        return exit_code;
    }
    RenderOutputInfo info = {scene_name, a.filter, a.seed, renderer_sampler(r), seconds_total, a.aovs, a.view};
    for (int k = 0; k < a.out_count && exit_code == WEDGE_EXIT_OK; ++k)
        if (!render_output_write(a.out_paths[k], frame, res, &info, &guarded, &err)) {
            print_error(&err, dist);
            exit_code = err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
        }
    if (exit_code == WEDGE_EXIT_OK && a.visualize && !render_output_visualize(out_path, frame, res, &err)) {
        print_error(&err, dist);
        exit_code = err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
    }
    seconds_total = clock_wall_seconds() - t_start;
    if (exit_code == WEDGE_EXIT_OK && a.report_path) {
        RunReport rep = {0};
        rep.width = frame->width, rep.height = frame->height;
        rep.spp_avg = res->spp_avg;
        rep.overscan_px = res->overscan_px;
        rep.seconds_total = seconds_total;
        rep.cpu_seconds_total = clock_cpu_seconds() - cpu_start;
        rep.seconds_trace = st.seconds_trace;
        rep.seconds_filter = res->seconds_filter;
        /* effect -> method used (the policy's choice, or none when a render was cut short) */
        for (int e = 0; e < EFFECT_COUNT; ++e) {
            rep.filters[e] = recon_choice_name(&res->choice, (Effect)e);
            rep.pixels_filtered[e] = res->pixels_filtered[e];
        }
        rep.blur_probe_px = res->choice.blur_px;
        rep.blur_probe_unbounded = res->choice.blur_unbounded;
        rep.auto_fallback = res->choice.fallback_decided ? &res->choice.fallback : NULL;
        rep.auto_fell_back = res->choice.fell_back;
        rep.mu = res->mu;
        rep.cl_device = res->device[0] ? res->device : NULL;
        rep.seconds_build = st.seconds_build;
        rep.rays_primary = st.rays_primary, rep.rays_shadow = st.rays_shadow, rep.rays_indirect = st.rays_indirect;
        rep.rays_bsdf = st.rays_bsdf;
        rep.guarded_events = guarded;
        rep.nonfinite_pixels = res->nonfinite_pixels;
        rep.effects = renderer_effects(r);
        rep.threads = renderer_threads(r);
        rep.seed = a.seed;
        rep.sampler = sampler_kind_name(renderer_sampler(r));
        rep.filter = a.filter;
        rep.scene = scene_name;
        rep.output = out_path;
        rep.interrupted = !complete;
        rep.triangles = renderer_triangle_count(r);
        rep.ranks = dist->ranks;
        rep.steps = res->steps;
        for (int k = 0; k < 4; ++k) rep.bytes_pass[k] = dist->bytes_sent[k];
        if (!run_report_write(a.report_path, &rep, &err)) {
            print_error(&err, dist);
            exit_code = WEDGE_EXIT_RUNTIME;
        }
    }
    recon_pipeline_destroy(pipe);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return exit_code;
}

int cmd_render(int argc, char **argv)
{
    ReconDist dist;
    Diag err = {0};
    if (!dist_init(&argc, &argv, &dist, &err)) { /* mpirun, and no MPI library to load */
        diag_print(&err);
        dist_finish(&dist);
        return err.exit_code;
    }
    int rc = render_command(argc, argv, &dist);
    dist_finish(&dist);
    return rc;
}
