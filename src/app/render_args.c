/* The options of wedge render (see render_args.h). */
#include "app/render_args.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/diag.h"
#include "recon/maaf/maaf_design.h"
#include "recon/select.h"
#include "render/pixel_filter.h"
#include "render/render_reads.h"
#include "scene/scene_desc.h"

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
#define RENDER_SPP_MAX SCENE_SPP_MAX /* scene/scene_desc.h: one bound for the scene and the command line */
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
        {"--pixel-filter", "box, gaussian, triangle, mitchell or sinc"},
        {"--mu", "a number in (0, " RENDER_STR(RENDER_MU_MAX) "]"},
        {"--maaf-pairs", "an integer in [1, " RENDER_STR(MAAF_PAIRS_MAX) "]"},
        {"--mem-limit", "a size in bytes with an optional K, M or G suffix (e.g. 512M)"},
        {"--time", "a number of seconds in (0, 1e7]"},
        {"--checkpoint", "a number of seconds in (0, 1e7]"},
        {"--overscan", "auto or off"},
    };
    for (size_t i = 0; i < sizeof wants / sizeof wants[0]; ++i)
        if (!strcmp(opt, wants[i].opt)) return wants[i].wants;
    if (!strcmp(opt, "--filter")) return recon_filter_choices(buf, size);
    return "another value";
}

int parse_render_args(int argc, char **argv, const char *command, RenderArgs *a)
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
            fprintf(stderr, "wedge %s: option '%s' needs a value\n", command, o);           \
            return WEDGE_EXIT_USAGE;                                                   \
        }                                                                              \
        ++i;                                                                           \
    } while (0)
        if (!strcmp(o, "-h") || !strcmp(o, "--help")) {
            a->help = true;
        } else if (!strcmp(o, "-o")) {
            NEED_VALUE();
            if (a->out_count == (int)(sizeof a->out_paths / sizeof a->out_paths[0])) {
                fprintf(stderr, "wedge %s: at most %d -o outputs\n", command, a->out_count);
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
        } else if (!strcmp(o, "--pixel-filter")) {
            NEED_VALUE();
            PixelFilterKind kind;
            if (!pixel_filter_kind_from_name(val, &kind)) goto bad_value;
            a->pixel_filter = val;
        } else if (!strcmp(o, "--filter")) {
            NEED_VALUE();
            char why[160];
            if (strchr(val, '=') && !recon_filter_problem(val, why, sizeof why)) {
                fprintf(stderr, "wedge %s: --filter %s: %s\n", command, val, why);
                return WEDGE_EXIT_USAGE;
            }
            if (!recon_filter_known(val)) goto bad_value;
            a->filter = val;
        } else if (!strcmp(o, "--mu")) {
            NEED_VALUE();
            char *end;
            errno = 0;
            double mu = strtod(val, &end);
            if (errno || end == val || *end || !(mu > 0.0) || !(mu <= RENDER_MU_MAX)) goto bad_value;
            a->mu = (float)mu;
        } else if (!strcmp(o, "--overscan")) {
            NEED_VALUE();
            if (strcmp(val, "auto") != 0 && strcmp(val, "off") != 0) goto bad_value;
            a->no_overscan = !strcmp(val, "off");
        } else if (!strcmp(o, "--maaf-pairs")) {
            NEED_VALUE();
            char *end;
            errno = 0;
            long pairs = strtol(val, &end, 10);
            if (errno || end == val || *end || pairs < 1 || pairs > MAAF_PAIRS_MAX) goto bad_value;
            a->maaf_pairs = (int)pairs;
        } else if (!strcmp(o, "--mem-limit")) {
            NEED_VALUE();
            char *end;
            errno = 0;
            double bytes = strtod(val, &end);
            double unit = !*end ? 1.0 : !strcmp(end, "K") ? 1024.0 : !strcmp(end, "M") ? 1048576.0
                                    : !strcmp(end, "G") ? 1073741824.0 : 0.0;
            if (errno || end == val || unit == 0.0 || !(bytes >= 1.0) || !(bytes * unit < 1e18)) goto bad_value;
            a->mem_limit = bytes * unit;
        } else if (!strcmp(o, "--cl-device")) {
            NEED_VALUE();
            a->cl_device = val;
        } else if (!strcmp(o, "--time") || !strcmp(o, "--checkpoint")) {
            NEED_VALUE();
            char *end;
            errno = 0;
            double sec = strtod(val, &end);
            if (errno || end == val || *end || !(sec > 0.0) || !(sec <= 1e7)) goto bad_value;
            if (!strcmp(o, "--time")) a->time_budget = sec;
            else a->checkpoint = sec;
        } else if (!strcmp(o, "--visualize")) {
            a->visualize = true;
        } else if (o[0] == '-' && o[1]) {
            fprintf(stderr, "wedge %s: unknown option '%s' (wedge %s --help lists them)\n", command, o, command);
            return WEDGE_EXIT_USAGE;
        } else if (!a->scene_path) {
            a->scene_path = o;
        } else {
            fprintf(stderr, "wedge %s: more than one scene given ('%s' and '%s')\n", command, a->scene_path, o);
            return WEDGE_EXIT_USAGE;
        }
        continue;
    bad_value:;
        char wants[192];
        fprintf(stderr, "wedge %s: %s wants %s, got '%s'\n", command, o, render_option_wants(o, wants, sizeof wants), val);
        return WEDGE_EXIT_USAGE;
#undef NEED_VALUE
    }
    /* an option that would do nothing is a mistake worth saying, not ignoring */
    bool plain = !strcmp(a->filter, "none");
    const struct {
        bool pointless;
        const char *why;
    } pointless[] = {
        {a->checkpoint > 0.0 && !(a->time_budget > 0.0) && a->spp == 0,
         "--checkpoint writes the image while a progressive render runs and needs its target: add --time SECONDS "
         "or --spp N"},
        {plain && a->mu > 0.0f, "--mu sets a filter's knob and does nothing with --filter none (plain Monte Carlo); "
                                "drop --mu, or choose a filter (--filter auto)"},
        {a->maaf_pairs > 0 && strcmp(a->filter, "maaf") != 0,
         "--maaf-pairs sets MAAF's number of filter pairs and needs --filter maaf"},
        {plain && a->cl_device, "--cl-device picks the device the filters run on and does nothing with --filter "
                                "none; drop it, or choose a filter"},
        {plain && a->no_overscan, "--overscan off turns off the band a filter traces around the image and does "
                                  "nothing with --filter none; drop it, or choose a filter"},
        {plain && a->mem_limit > 0.0, "--mem-limit caps a filter's per-sample storage and does nothing with --filter "
                                      "none; drop it, or choose a filter"},
    };
    for (size_t k = 0; k < sizeof pointless / sizeof pointless[0]; ++k)
        if (pointless[k].pointless) {
            fprintf(stderr, "wedge %s: %s\n", command, pointless[k].why);
            return WEDGE_EXIT_USAGE;
        }
    return WEDGE_EXIT_OK;
}


unsigned render_args_reads(const RenderArgs *a)
{
    unsigned reads = RENDER_READS_RADIANCE;
    if (a->aovs || a->visualize) reads |= RENDER_READS_ALL;
    return reads;
}
