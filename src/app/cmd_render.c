/* wedge render [SCENE] [-o OUT] [--spp N] [--res WxH] [--seed N] [--threads N] [--aovs]
 *              [--report FILE.json] [--quiet] [--sampler stratified|sobol] [--filter none]
 *              [--view NAME]
 *
 * Parses the scene (or the embedded default), renders it with the Monte Carlo renderer and
 * writes an EXR (float R G B A, optional AOV layers, header attributes) or an 8-bit PNG
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
#include "core/diag.h"
#include "io/image_io.h"
#include "io/ocio.h"
#include "render/frame.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "render/run_report.h"
#include "scene/scene_desc.h"

/* ---- the command line, parsed in one place ---- */

typedef struct {
    const char *scene_path;   /* NULL: the embedded default scene */
    const char *out_path;     /* NULL: the film's filename */
    int spp;                  /* 0: scene's */
    int width, height;        /* 0: scene's */
    uint64_t seed;
    int threads;              /* 0: all cores */
    bool aovs;
    const char *report_path;
    bool quiet;
    bool sampler_set;
    SamplerKind sampler;
    const char *filter;       /* "none" (filters register further values) */
    const char *view;         /* OCIO view for PNG output; NULL: the display's default */
    bool help;
} RenderArgs;

static void usage(FILE *f)
{
    char views[256];
    Diag verr = {0};
    if (!ocio_list_views(views, sizeof views, &verr)) snprintf(views, sizeof views, "(config not readable)");
    fprintf(f,
            "usage: wedge render [SCENE] [-o OUT] [--spp N] [--res WxH] [--seed N] [--threads N]\n"
            "                    [--aovs] [--report FILE.json] [--quiet] [--sampler stratified|sobol]\n"
            "                    [--filter none] [--view NAME]\n\n"
            "Renders a pbrt-v4 scene (without SCENE: the embedded default scene) to OUT.\n\n"
            "  -o OUT          output image; .png writes 8-bit display-referred colour through\n"
            "                  OpenColorIO ($OCIO or the built-in config), anything else EXR\n"
            "                  (default: the scene's Film \"filename\")\n"
            "  --spp N         samples per pixel (default: the scene's pixelsamples)\n"
            "  --res WxH       image size in pixels (default: the scene's film)\n"
            "  --seed N        random seed (default 0); the image depends only on the seed\n"
            "  --threads N     worker threads (default: all cores)\n"
            "  --aovs          add EXR layers albedo, N, Z, direct, indirect, emission, spp\n"
            "  --report FILE   write a JSON run report\n"
            "  --quiet         no progress bar and no warnings on stderr\n"
            "  --sampler KIND  stratified or sobol (default: mapped from the scene's Sampler)\n"
            "  --filter NAME   reconstruction filter: none (plain Monte Carlo)\n"
            "  --view NAME     OCIO view for PNG output (default: the display's default view);\n"
            "                  views: %s\n",
            views);
}

static bool parse_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi) return false;
    *out = v;
    return true;
}

/* Returns WEDGE_EXIT_OK or WEDGE_EXIT_USAGE (message printed). */
static int parse_render_args(int argc, char **argv, RenderArgs *a)
{
    *a = (RenderArgs){0};
    a->filter = "none";
    for (int i = 1; i < argc; ++i) {
        const char *o = argv[i];
        const char *val = (i + 1 < argc) ? argv[i + 1] : NULL;
        long v;
#define NEED_VALUE()                                                                   \
    do {                                                                               \
        if (!val) {                                                                    \
            fprintf(stderr, "wedge render: option '%s' needs a value\n", o);           \
            return WEDGE_EXIT_USAGE;                                                   \
        }                                                                              \
        ++i;                                                                           \
    } while (0)
        if (!strcmp(o, "-h") || !strcmp(o, "--help")) {
            a->help = true;
        } else if (!strcmp(o, "-o")) {
            NEED_VALUE();
            a->out_path = val;
        } else if (!strcmp(o, "--spp")) {
            NEED_VALUE();
            if (!parse_int(val, 1, 1L << 24, &v)) goto bad_value;
            a->spp = (int)v;
        } else if (!strcmp(o, "--res")) {
            NEED_VALUE();
            char *x = strchr(val, 'x');
            if (!x) goto bad_value;
            char w[32];
            size_t n = (size_t)(x - val);
            if (n == 0 || n >= sizeof w) goto bad_value;
            memcpy(w, val, n);
            w[n] = 0;
            long wv, hv;
            if (!parse_int(w, 1, 65536, &wv) || !parse_int(x + 1, 1, 65536, &hv)) goto bad_value;
            a->width = (int)wv, a->height = (int)hv;
        } else if (!strcmp(o, "--seed")) {
            NEED_VALUE();
            char *end;
            errno = 0;
            unsigned long long s = strtoull(val, &end, 10);
            if (errno || end == val || *end || val[0] == '-') goto bad_value;
            a->seed = (uint64_t)s;
        } else if (!strcmp(o, "--threads")) {
            NEED_VALUE();
            if (!parse_int(val, 1, 1024, &v)) goto bad_value;
            a->threads = (int)v;
        } else if (!strcmp(o, "--aovs")) {
            a->aovs = true;
        } else if (!strcmp(o, "--report")) {
            NEED_VALUE();
            a->report_path = val;
        } else if (!strcmp(o, "--view")) {
            NEED_VALUE();
            a->view = val;
        } else if (!strcmp(o, "--quiet")) {
            a->quiet = true;
        } else if (!strcmp(o, "--sampler")) {
            NEED_VALUE();
            if (!strcmp(val, "stratified"))
                a->sampler = SAMPLER_STRATIFIED;
            else if (!strcmp(val, "sobol"))
                a->sampler = SAMPLER_SOBOL;
            else
                goto bad_value;
            a->sampler_set = true;
        } else if (!strcmp(o, "--filter")) {
            NEED_VALUE();
            if (strcmp(val, "none")) goto bad_value;
            a->filter = val;
        } else if (o[0] == '-' && o[1]) {
            fprintf(stderr, "wedge render: unknown option '%s'\n", o);
            usage(stderr);
            return WEDGE_EXIT_USAGE;
        } else if (!a->scene_path) {
            a->scene_path = o;
        } else {
            fprintf(stderr, "wedge render: more than one scene given ('%s' and '%s')\n", a->scene_path, o);
            return WEDGE_EXIT_USAGE;
        }
        continue;
    bad_value:
        fprintf(stderr, "wedge render: invalid value '%s' for option '%s'\n", val, o);
        return WEDGE_EXIT_USAGE;
#undef NEED_VALUE
    }
    return WEDGE_EXIT_OK;
}

/* ---- Ctrl-C ---- */

static volatile sig_atomic_t interrupt_flag = 0;

static void on_sigint(int sig)
{
    (void)sig;
    interrupt_flag = 1;
    signal(SIGINT, SIG_DFL); /* a second Ctrl-C kills the process */
}

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- output ---- */

typedef struct {
    float *rgb, *direct, *indirect, *emission, *albedo, *normal, *depth, *alpha;
} OutputPlanes;

static void planes_free(OutputPlanes *p)
{
    free(p->rgb), free(p->direct), free(p->indirect), free(p->emission);
    free(p->albedo), free(p->normal), free(p->depth), free(p->alpha);
}

static bool write_image(const char *path, const Frame *f, const RenderArgs *a, const char *scene_name, double spp_avg,
                        double seconds, SamplerKind sampler, long long *guarded, Diag *err)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    OutputPlanes p = {0};
    p.rgb = malloc(3 * n * sizeof(float));
    if (!p.rgb) goto oom;
    *guarded += frame_resolve3(f, f->color, p.rgb);
    if (path_is_png(path)) {
        bool ok = ocio_write_png(path, f->width, f->height, p.rgb, a->view, err);
        planes_free(&p);
        return ok;
    }
    p.alpha = malloc(n * sizeof(float));
    if (!p.alpha) goto oom;
    for (size_t i = 0; i < n; ++i) p.alpha[i] = 1.0f;
    ExrChannel ch[24];
    int nc = 0;
    ch[nc++] = (ExrChannel){"R", p.rgb + 0, 3};
    ch[nc++] = (ExrChannel){"G", p.rgb + 1, 3};
    ch[nc++] = (ExrChannel){"B", p.rgb + 2, 3};
    ch[nc++] = (ExrChannel){"A", p.alpha, 1};
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
    }
    char seed_txt[32];
    snprintf(seed_txt, sizeof seed_txt, "%" PRIu64, a->seed);
    ExrAttr attrs[] = {
        {"wedge.spp", EXR_ATTR_FLOAT, NULL, spp_avg, 0},
        {"wedge.seed", EXR_ATTR_STRING, seed_txt, 0.0, 0},
        {"wedge.seconds", EXR_ATTR_FLOAT, NULL, seconds, 0},
        {"wedge.version", EXR_ATTR_STRING, WEDGE_VERSION, 0.0, 0},
        {"wedge.scene", EXR_ATTR_STRING, scene_name, 0.0, 0},
        {"wedge.sampler", EXR_ATTR_STRING, sampler_kind_name(sampler), 0.0, 0},
        {"wedge.filter", EXR_ATTR_STRING, a->filter, 0.0, 0},
    };
    ExrWriteOptions wo = {EXR_STORE_FLOAT, EXRC_ZIP, 0, 0};
    bool ok = exr_write_with(path, f->width, f->height, ch, nc, attrs, (int)(sizeof attrs / sizeof attrs[0]), &wo, err);
    *guarded += wo.nonfinite_replaced;
    planes_free(&p);
    return ok;
oom:
    planes_free(&p);
    diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory writing '%s'", path);
    return false;
}

int cmd_render(int argc, char **argv)
{
    double t_start = seconds_now();
    RenderArgs a;
    int rc = parse_render_args(argc, argv, &a);
    if (rc != WEDGE_EXIT_OK) return rc;
    if (a.help) {
        usage(stdout);
        return WEDGE_EXIT_OK;
    }

    Diag err = {0};
    if (a.view) {
        /* Check --view before rendering: a typo must not cost a whole render. */
        OcioView *ov = NULL;
        if (!ocio_view_open(a.view, &ov, &err)) {
            fputs(err.message, stderr);
            if (err.message[0] && err.message[strlen(err.message) - 1] != '\n') fputc('\n', stderr);
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
        fputs(err.message, stderr);
        if (err.message[0] && err.message[strlen(err.message) - 1] != '\n') fputc('\n', stderr);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
    }
    scene_analyze_effects(&scene);

    RenderOptions ro = {0};
    ro.width = a.width, ro.height = a.height, ro.spp = a.spp, ro.seed = a.seed, ro.threads = a.threads;
    ro.sampler_set = a.sampler_set, ro.sampler = a.sampler;
    ro.record_ray_geometry = false; /* --filter none reads no ray geometry */
    ro.cancel = &interrupt_flag;
    ProgressBar bar = {stderr, 0.0, 0, 0};
    if (!a.quiet && isatty(STDERR_FILENO)) ro.progress = progress_bar_update, ro.progress_ctx = &bar;

    Renderer *r = NULL;
    if (!renderer_create(&scene, &ro, &r, &err)) {
        fputs(err.message, stderr);
        if (err.message[0] && err.message[strlen(err.message) - 1] != '\n') fputc('\n', stderr);
        scene_desc_free(&scene);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
    }
    if (!a.quiet)
        for (int i = 0; i < scene.warning_count; ++i) fprintf(stderr, "%s\n", scene.warnings[i]);

    const char *out_path = a.out_path ? a.out_path : (scene.film.filename ? scene.film.filename : "pbrt.exr");
    Frame frame;
    if (!frame_init(&frame, renderer_width(r), renderer_height(r))) {
        fprintf(stderr, "wedge render: out of memory for a %dx%d frame\n", renderer_width(r), renderer_height(r));
        renderer_destroy(r);
        scene_desc_free(&scene);
        return WEDGE_EXIT_RUNTIME;
    }

    interrupt_flag = 0;
    void (*old_handler)(int) = signal(SIGINT, on_sigint);
    bool complete = render_pass(r, 0, NULL, renderer_spp(r), &frame, NULL);
    signal(SIGINT, old_handler == SIG_ERR ? SIG_DFL : old_handler);
    if (ro.progress) progress_bar_finish(&bar);
    if (!complete && !a.quiet) fprintf(stderr, "wedge render: interrupted; writing the samples taken so far\n");

    RenderStats st = renderer_stats(r);
    double spp_avg = frame_spp_avg(&frame);
    long long guarded = st.guarded_events;
    double seconds_total = seconds_now() - t_start;
    const char *scene_name = a.scene_path ? a.scene_path : "<default>";
    int exit_code = WEDGE_EXIT_OK;
    if (!write_image(out_path, &frame, &a, scene_name, spp_avg, seconds_total, renderer_sampler(r), &guarded, &err)) {
        fputs(err.message, stderr);
        if (err.message[0] && err.message[strlen(err.message) - 1] != '\n') fputc('\n', stderr);
        exit_code = err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
    }
    seconds_total = seconds_now() - t_start;
    if (exit_code == WEDGE_EXIT_OK && a.report_path) {
        RunReport rep = {0};
        rep.width = frame.width, rep.height = frame.height;
        rep.spp_avg = spp_avg;
        rep.seconds_total = seconds_total;
        rep.seconds_trace = st.seconds_trace;
        rep.seconds_filter = 0.0;
        rep.seconds_build = st.seconds_build;
        rep.rays_primary = st.rays_primary, rep.rays_shadow = st.rays_shadow, rep.rays_indirect = st.rays_indirect;
        rep.guarded_events = guarded;
        rep.effects = renderer_effects(r);
        rep.threads = renderer_threads(r);
        rep.seed = a.seed;
        rep.sampler = sampler_kind_name(renderer_sampler(r));
        rep.filter = a.filter;
        rep.scene = scene_name;
        rep.output = out_path;
        rep.interrupted = !complete;
        rep.triangles = renderer_triangle_count(r);
        if (!run_report_write(a.report_path, &rep, &err)) {
            fputs(err.message, stderr);
            fputc('\n', stderr);
            exit_code = WEDGE_EXIT_RUNTIME;
        }
    }
    frame_free(&frame);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return exit_code;
}
