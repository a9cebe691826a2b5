/* wedge render [SCENE] [-o OUT] [--spp N] [--res WxH] [--seed N] [--threads N] [--aovs]
 *              [--report FILE.json] [--quiet] [--sampler stratified|sobol]
 *              [--filter auto|aaf|none] [--mu X] [--cl-device N|NAME] [--visualize] [--view NAME]
 *
 * Parses the scene (or the embedded default), renders it with the Monte Carlo renderer,
 * reconstructs it with the chosen filter (src/recon) and writes an EXR (float R G B A, optional AOV layers, header attributes) or an 8-bit PNG
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
#include "core/false_colour.h"
#include "io/image_io.h"
#include "io/ocio.h"
#include "recon/aaf/aaf_render.h"
#include "recon/filter_select.h"
#include "render/frame.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "render/run_report.h"
#include "scene/scene_desc.h"

/* ---- the command line, parsed in one place ---- */

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
    const char *filter;       /* "auto", "aaf" or "none" */
    float mu;                 /* filter knob; 0: each paper's default */
    const char *cl_device;    /* NULL: $WEDGE_CL_DEVICE, else the first GPU, else CPU */
    bool visualize;           /* false-colour PNG maps of filter widths and spp */
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
            "                    [--filter auto|aaf|none] [--mu X] [--cl-device N|NAME] [--visualize]\n"
            "                    [--view NAME]\n\n"
            "Renders a pbrt-v4 scene (without SCENE: the embedded default scene) to OUT.\n\n"
            "  -o OUT          output image, repeatable (one render, several files); .png writes\n"
            "                  8-bit display-referred colour through OpenColorIO ($OCIO or the\n"
            "                  built-in config), anything else EXR\n"
            "                  (default: the scene's Film \"filename\")\n"
            "  --spp N         samples per pixel with --filter none (default: the scene's\n"
            "                  pixelsamples); a filter chooses its own per-pixel counts (--mu)\n"
            "  --res WxH       image size in pixels (default: the scene's film)\n"
            "  --seed N        random seed (default 0); the image depends only on the seed\n"
            "  --threads N     worker threads (default: all cores)\n"
            "  --aovs          add EXR layers albedo, N, Z, direct, indirect, emission, spp\n"
            "  --report FILE   write a JSON run report\n"
            "  --quiet         no progress bar and no warnings on stderr\n"
            "  --sampler KIND  stratified or sobol (default: mapped from the scene's Sampler)\n"
            "  --filter NAME   reconstruction: auto (default: the best filter for each effect the\n"
            "                  scene has; for now axis-aligned filtering), aaf, or none (plain\n"
            "                  Monte Carlo from the same sampler)\n"
            "  --mu X          filter knob (> 0): larger means more samples and narrower filters;\n"
            "                  as X grows the result converges to Monte Carlo (default: each\n"
            "                  filter's default: 2 for shadows and indirect light, 1 for defocus)\n"
            "  --cl-device D   OpenCL device by index or name substring (see 'wedge info --cl');\n"
            "                  default $WEDGE_CL_DEVICE, else the first GPU, else the first CPU\n"
            "  --visualize     also write OUT-beta-EFFECT.png and OUT-spp.png false-colour maps\n"
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

/* Option limits: the parser and its error messages share them. */
#define RENDER_SPP_MAX 16777216
#define RENDER_RES_MAX 65536
#define RENDER_THREADS_MAX 1024
#define RENDER_MU_MAX 1e6
#define RENDER_STR_(x) #x
#define RENDER_STR(x) RENDER_STR_(x)

/* What an option's value must look like, for the error message (buf: room for a phrase
 * built at run time). */
static const char *render_option_wants(const char *opt, char *buf, size_t size)
{
    static const struct {
        const char *opt, *wants;
    } wants[] = {
        {"--spp", "an integer in [1, " RENDER_STR(RENDER_SPP_MAX) "]"},
        {"--res", "WxH with W and H in [1, " RENDER_STR(RENDER_RES_MAX) "] (e.g. 640x360)"},
        {"--seed", "a non-negative integer"},
        {"--threads", "an integer in [1, " RENDER_STR(RENDER_THREADS_MAX) "]"},
        {"--sampler", "stratified or sobol"},
        {"--mu", "a number in (0, " RENDER_STR(RENDER_MU_MAX) "]"},
    };
    for (size_t i = 0; i < sizeof wants / sizeof wants[0]; ++i)
        if (!strcmp(opt, wants[i].opt)) return wants[i].wants;
    if (!strcmp(opt, "--filter")) return recon_filter_choices(buf, size);
    return "another value";
}

/* Returns WEDGE_EXIT_OK or WEDGE_EXIT_USAGE (message printed). */
static int parse_render_args(int argc, char **argv, RenderArgs *a)
{
    *a = (RenderArgs){0};
    a->filter = "auto";
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
            if (a->out_count == (int)(sizeof a->out_paths / sizeof a->out_paths[0])) {
                fprintf(stderr, "wedge render: at most %d -o outputs\n", a->out_count);
                return WEDGE_EXIT_USAGE;
            }
            a->out_paths[a->out_count++] = val;
        } else if (!strcmp(o, "--spp")) {
            NEED_VALUE();
            if (!parse_int(val, 1, RENDER_SPP_MAX, &v)) goto bad_value;
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
            if (!parse_int(w, 1, RENDER_RES_MAX, &wv) || !parse_int(x + 1, 1, RENDER_RES_MAX, &hv)) goto bad_value;
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
            if (!parse_int(val, 1, RENDER_THREADS_MAX, &v)) goto bad_value;
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
            if (!recon_filter_known(val)) goto bad_value;
            a->filter = val;
        } else if (!strcmp(o, "--mu")) {
            NEED_VALUE();
            char *end;
            errno = 0;
            double mu = strtod(val, &end);
            if (errno || end == val || *end || !(mu > 0.0) || !(mu <= RENDER_MU_MAX)) goto bad_value;
            a->mu = (float)mu;
        } else if (!strcmp(o, "--cl-device")) {
            NEED_VALUE();
            a->cl_device = val;
        } else if (!strcmp(o, "--visualize")) {
            a->visualize = true;
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
    bad_value:;
        char wants[128];
        fprintf(stderr, "wedge render: %s wants %s, got '%s'\n", o, render_option_wants(o, wants, sizeof wants), val);
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
    float *direct, *indirect, *emission, *albedo, *normal, *depth, *alpha;
} OutputPlanes;

static void planes_free(OutputPlanes *p)
{
    free(p->direct), free(p->indirect), free(p->emission);
    free(p->albedo), free(p->normal), free(p->depth), free(p->alpha);
}

/* rgb: the final image (3 floats per pixel); aaf: the filter's maps, or NULL. */
static bool write_image(const char *path, const Frame *f, const float *rgb, const AafRenderResult *aaf,
                        const RenderArgs *a, const char *scene_name, double spp_avg, double seconds,
                        SamplerKind sampler, long long *guarded, Diag *err)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    OutputPlanes p = {0};
    if (path_is_png(path)) return ocio_write_png(path, f->width, f->height, rgb, a->view, err);
    p.alpha = malloc(n * sizeof(float));
    if (!p.alpha) goto oom;
    for (size_t i = 0; i < n; ++i) p.alpha[i] = 1.0f;
    ExrChannel ch[24 + AAF_EFFECT_COUNT];
    char beta_names[AAF_EFFECT_COUNT][64];
    int nc = 0;
    ch[nc++] = (ExrChannel){"R", rgb + 0, 3};
    ch[nc++] = (ExrChannel){"G", rgb + 1, 3};
    ch[nc++] = (ExrChannel){"B", rgb + 2, 3};
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
        for (int e = 0; aaf && e < AAF_EFFECT_COUNT; ++e)
            if (aaf->beta_px[e]) {
                snprintf(beta_names[e], sizeof beta_names[e], "aaf.beta_px.%s", aaf_effect_name(e));
                ch[nc++] = (ExrChannel){beta_names[e], aaf->beta_px[e], 1};
            }
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

/* OUT without its extension + suffix: "img.exr" + "-spp.png" -> "img-spp.png". */
static void sibling_path(char *buf, size_t size, const char *out_path, const char *suffix)
{
    const char *dot = strrchr(out_path, '.'), *slash = strrchr(out_path, '/');
    size_t stem = (dot && (!slash || dot > slash)) ? (size_t)(dot - out_path) : strlen(out_path);
    snprintf(buf, size, "%.*s%s", (int)stem, out_path, suffix);
}

/* --visualize: false-colour PNGs of each filter width (pixels) and of the samples per pixel,
 * each scaled to its own maximum (printed, so the colours can be read as numbers). */
static bool write_visualizations(const char *out_path, const Frame *f, const AafRenderResult *aaf, Diag *err)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    float *rgb = malloc(3 * n * sizeof(float));
    if (!rgb) {
        diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for --visualize");
        return false;
    }
    bool ok = true;
    for (int e = -1; ok && e < AAF_EFFECT_COUNT; ++e) {
        const float *values = e < 0 ? f->spp : (aaf ? aaf->beta_px[e] : NULL);
        if (!values) continue;
        char suffix[64], path[4096];
        snprintf(suffix, sizeof suffix, e < 0 ? "-spp.png" : "-beta-%s.png", e < 0 ? "" : aaf_effect_name(e));
        sibling_path(path, sizeof path, out_path, suffix);
        float vmax = false_colour_image(values, n, rgb);
        ok = png_write_display(path, f->width, f->height, rgb, err);
        if (ok) fprintf(stderr, "wedge render: wrote %s (%s, dark = 0 to bright = %g)\n", path,
                        e < 0 ? "samples per pixel" : "filter width in pixels", (double)vmax);
    }
    free(rgb);
    return ok;
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
            diag_print(&err);
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
        diag_print(&err);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
    }
    scene_analyze_effects(&scene);

    RenderOptions ro = {0};
    ro.width = a.width, ro.height = a.height, ro.spp = a.spp, ro.seed = a.seed, ro.threads = a.threads;
    ro.sampler_set = a.sampler_set, ro.sampler = a.sampler;
    bool filtered = strcmp(a.filter, "none") != 0;
    if (filtered && a.spp > 0 && !a.quiet)
        fprintf(stderr, "wedge render: note: --spp is not used with --filter %s, which sets each pixel's samples "
                        "itself; use --mu to trade samples for filter width, or --filter none\n", a.filter);
    ro.record_ray_geometry = filtered; /* plain Monte Carlo pays nothing for the filters' statistics */
    ro.cancel = &interrupt_flag;
    ProgressBar bar = {.out = stderr};
    if (!a.quiet && isatty(STDERR_FILENO)) ro.progress = progress_bar_update, ro.progress_ctx = &bar;

    Renderer *r = NULL;
    if (!renderer_create(&scene, &ro, &r, &err)) {
        diag_print(&err);
        scene_desc_free(&scene);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
    }
    if (!a.quiet)
        for (int i = 0; i < scene.warning_count; ++i) fprintf(stderr, "%s\n", scene.warnings[i]);
    if (!filtered && !a.quiet) note_sobol_count(renderer_sampler(r), renderer_spp(r));

    if (a.out_count == 0) a.out_paths[a.out_count++] = scene.film.filename ? scene.film.filename : "pbrt.exr";
    const char *out_path = a.out_paths[0];
    Frame frame;
    if (!frame_init(&frame, renderer_width(r), renderer_height(r))) {
        fprintf(stderr, "wedge render: out of memory for a %dx%d frame\n", renderer_width(r), renderer_height(r));
        renderer_destroy(r);
        scene_desc_free(&scene);
        return WEDGE_EXIT_RUNTIME;
    }

    interrupt_flag = 0;
    void (*old_handler)(int) = signal(SIGINT, on_sigint);
    AafRenderResult aaf = {0};
    float *mc_rgb = NULL;
    const float *rgb = NULL;
    bool complete;
    long long guarded = 0;
    if (filtered) {
        /* auto and aaf agree until further filters land: AAF for every effect it covers. */
        AafRenderOptions ao = aaf_render_options_default();
        ao.mu = a.mu;
        ao.cl_device = a.cl_device;
        bool ok = aaf_render(r, &ao, &frame, &aaf, &err);
        signal(SIGINT, old_handler == SIG_ERR ? SIG_DFL : old_handler);
        if (ro.progress) progress_bar_finish(&bar);
        if (!ok) {
            diag_print(&err);
            frame_free(&frame);
            renderer_destroy(r);
            scene_desc_free(&scene);
            return err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
        }
        complete = !aaf.cancelled;
        rgb = aaf.rgb;
        guarded += aaf.guarded_events;
    } else {
        complete = render_pass(r, 0, NULL, renderer_spp(r), &frame, NULL);
        signal(SIGINT, old_handler == SIG_ERR ? SIG_DFL : old_handler);
        if (ro.progress) progress_bar_finish(&bar);
        mc_rgb = malloc(3 * (size_t)frame.width * (size_t)frame.height * sizeof(float));
        if (!mc_rgb) {
            fprintf(stderr, "wedge render: out of memory for a %dx%d image\n", frame.width, frame.height);
            frame_free(&frame);
            renderer_destroy(r);
            scene_desc_free(&scene);
            return WEDGE_EXIT_RUNTIME;
        }
        guarded += frame_resolve3(&frame, frame.color, mc_rgb);
        rgb = mc_rgb;
    }
    if (!complete && !a.quiet) fprintf(stderr, "wedge render: interrupted; writing the samples taken so far\n");

    RenderStats st = renderer_stats(r);
    double spp_avg = frame_spp_avg(&frame);
    guarded += st.guarded_events;
    double seconds_total = seconds_now() - t_start;
    const char *scene_name = a.scene_path ? a.scene_path : "<default>";
    int exit_code = WEDGE_EXIT_OK;
    const AafRenderResult *maps = filtered ? &aaf : NULL;
    for (int k = 0; k < a.out_count && exit_code == WEDGE_EXIT_OK; ++k)
        if (!write_image(a.out_paths[k], &frame, rgb, maps, &a, scene_name, spp_avg, seconds_total,
                         renderer_sampler(r), &guarded, &err)) {
            diag_print(&err);
            exit_code = err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
        }
    if (exit_code == WEDGE_EXIT_OK && a.visualize && !write_visualizations(out_path, &frame, maps, &err)) {
        diag_print(&err);
        exit_code = err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
    }
    seconds_total = seconds_now() - t_start;
    if (exit_code == WEDGE_EXIT_OK && a.report_path) {
        RunReport rep = {0};
        rep.width = frame.width, rep.height = frame.height;
        rep.spp_avg = spp_avg;
        rep.seconds_total = seconds_total;
        rep.seconds_trace = st.seconds_trace;
        rep.seconds_filter = filtered ? aaf.seconds_filter : 0.0;
        /* effect -> filter used (the policy's choice, or none when a render was cut short) */
        static const int aaf_index[RECON_EFFECT_COUNT] = {AAF_EFFECT_SHADOWS, AAF_EFFECT_DEFOCUS, -1,
                                                          AAF_EFFECT_INDIRECT};
        for (int e = 0; e < RECON_EFFECT_COUNT; ++e)
            rep.filters[e] = filtered && aaf_index[e] >= 0 ? aaf.filters[aaf_index[e]] : "none";
        rep.mu = filtered ? a.mu : 0.0;
        rep.cl_device = filtered ? aaf.device : NULL;
        rep.seconds_build = st.seconds_build;
        rep.rays_primary = st.rays_primary, rep.rays_shadow = st.rays_shadow, rep.rays_indirect = st.rays_indirect;
        rep.rays_bsdf = st.rays_bsdf;
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
            diag_print(&err);
            exit_code = WEDGE_EXIT_RUNTIME;
        }
    }
    free(mc_rgb);
    aaf_render_result_free(&aaf);
    frame_free(&frame);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return exit_code;
}
