/* wedge converge: error-versus-spp and error-versus-time sweeps against a cached reference
 * (issue 5, "References and sweeps").
 *
 *   wedge converge SCENE --spp LIST --methods LIST [--mu LIST] [--ref-spp N] [--res WxH]
 *                  [--cache DIR] [--seed N] [--threads N] --out DIR
 *
 * The reference is rendered once per key (ref_cache.h) and reused afterwards. Every
 * (method, mu, spp) run is a `wedge render` subprocess of this same binary (/proc/self/exe)
 * with its own seed and a --report JSON file, so each run is timed exactly as a user would
 * time it, and a crash in one run cannot corrupt the sweep. Errors are computed here, in
 * process, with the metrics of `wedge compare` (core/image_metrics.h). */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app/commands.h"
#include "app/converge_methods.h"
#include "app/converge_speedup.h"
#include "app/ref_cache.h"
#include "core/cache_home.h"
#include "core/diag.h"
#include "core/image_metrics.h"
#include "io/image_io.h"
#include "scene/scene_desc.h"

#define MAX_LIST 64

/* snprintf for paths: false when the result did not fit (the caller reports it). */
__attribute__((format(printf, 3, 4))) static bool fmt_path(char *out, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(out, size, fmt, ap);
    va_end(ap);
    return n >= 0 && (size_t)n < size;
}

typedef struct {
    const char *scene_path;   /* NULL: the embedded default scene */
    const char *out_dir;
    const char *cache_dir;
    int spp[MAX_LIST];
    int spp_count;
    int baseline_spp[MAX_LIST]; /* --baseline-spp: the Monte Carlo baselines' counts (0 values: --spp) */
    int baseline_spp_count;
    const ConvergeMethod *methods[MAX_LIST];
    int method_count;
    const char *mu[MAX_LIST]; /* kept as typed: used verbatim in file names and the CSV */
    int mu_count;
    int ref_spp;
    int width, height;        /* 0: the scene's film resolution */
    long long seed;
    long long ref_seed;       /* the reference's seed: --ref-seed, else --seed (sweeps of several
                               * seeds then share one reference, rendered once) */
    int threads;              /* 0: the renderer's default (all cores) */
    bool print_key;           /* --ref-key: print the reference key and stop */
    bool no_plots;
} ConvergeOptions;

/* One row of results.csv. */
typedef struct {
    const ConvergeMethod *method;
    const char *mu;
    double spp_avg, seconds_total, seconds_trace, seconds_filter;
    double cpu_seconds_total; /* the render's process CPU over seconds_total's span, every thread */
    double relmse, mse, psnr, ssim;
} ConvergeRow;


static void usage(FILE *f)
{
    fprintf(f,
            "usage: wedge converge [SCENE] --spp LIST --methods LIST [--mu LIST] [--ref-spp N]\n"
            "                      [--baseline-spp LIST] [--res WxH] [--cache DIR] [--seed N]\n"
            "                      [--ref-seed N] [--threads N] [--no-plots] --out DIR\n"
            "       wedge converge [SCENE] --ref-key [--ref-spp N] [--res WxH] [--seed N] [--ref-seed N]\n"
            "\n"
            "Renders a reference once (cached; default ref spp 4096), then every (method, mu, spp)\n"
            "with a fresh seed, and writes DIR/results.csv, DIR/speedup.csv, DIR/images/ and the\n"
            "plots DIR/error_vs_spp.png and DIR/error_vs_seconds.png. Without SCENE the scene\n"
            "embedded in the binary is used. LIST is comma-separated (e.g. 4,16,64).\n"
            "--baseline-spp LIST runs the Monte Carlo baselines (mc, mc-ld) at these counts instead\n"
            "of --spp, so that their error curve brackets the filters' errors (a filter at 8 spp often\n"
            "has the error of Monte Carlo at 100 or more; outside the curve a speedup is extrapolated).\n"
            "--seed N seeds the runs (N + 1, N + 2, ...) and the reference; --ref-seed N gives the\n"
            "reference its own seed, so that sweeps of several seeds share one reference.\n"
            "Equal-error speedups are given in wall time and in CPU time (all threads): the second is\n"
            "steadier on a machine other jobs share, the first is what a user waits.\n"
            "\n"
            "methods:\n");
    for (int i = 0; i < converge_method_count(); ++i) {
        const ConvergeMethod *m = converge_method_at(i);
        fprintf(f, "  %-8s %s%s\n", m->name, m->summary, m->takes_mu ? " (takes --mu)" : "");
    }
    fprintf(f, "\ncache folder: --cache DIR, else $XDG_CACHE_HOME/wedge, else ~/.cache/wedge\n");
}

static bool parse_int(const char *s, long long lo, long long hi, long long *out)
{
    char *end;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi) return false;
    *out = v;
    return true;
}

/* Splits a comma-separated list in place (the strings point into `s`). */
static int split_list(char *s, const char **items, int max)
{
    int n = 0;
    for (char *tok = strtok(s, ","); tok; tok = strtok(NULL, ",")) {
        if (n == max) return -1;
        items[n++] = tok;
    }
    return n;
}

/* Parses a sample-count list ("4,16,64") into out[]; prints the reason and returns false if bad. */
static bool parse_spp_list(const char *list, const char *option, int *out, int *count)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", list);
    const char *items[MAX_LIST];
    int n = split_list(buf, items, MAX_LIST);
    if (n <= 0) {
        fprintf(stderr, "wedge converge: %s wants a list like 4,16,64\n", option);
        return false;
    }
    *count = 0;
    for (int i = 0; i < n; ++i) {
        long long v;
        if (!parse_int(items[i], 1, 1 << 24, &v)) {
            fprintf(stderr, "wedge converge: bad spp '%s' in %s\n", items[i], option);
            return false;
        }
        out[(*count)++] = (int)v;
    }
    return true;
}

static bool is_baseline(const ConvergeMethod *m)
{
    for (int b = 0; b < converge_baseline_method_count; ++b)
        if (!strcmp(m->name, converge_baseline_methods[b])) return true;
    return false;
}

/* Returned by parse_args after --help: nothing more to do. */
#define HELP_SHOWN (-1)

/* Returns WEDGE_EXIT_OK, HELP_SHOWN or WEDGE_EXIT_USAGE (after printing the reason). */
static int parse_args(int argc, char **argv, ConvergeOptions *o)
{
    memset(o, 0, sizeof *o);
    o->ref_spp = 4096;
    o->seed = 1;
    o->ref_seed = -1;
    const char *spp_list = NULL, *baseline_spp_list = NULL, *method_list = NULL, *mu_list = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        long long n;
        bool takes_value = true;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return HELP_SHOWN;
        } else if (!strcmp(a, "--ref-key")) {
            o->print_key = true;
            takes_value = false;
        } else if (!strcmp(a, "--no-plots")) {
            o->no_plots = true;
            takes_value = false;
        } else if (a[0] == '-' && a[1] == '-' && !v) {
            fprintf(stderr, "wedge converge: %s needs a value\n", a);
            return WEDGE_EXIT_USAGE;
        } else if (!strcmp(a, "--spp")) {
            spp_list = v;
        } else if (!strcmp(a, "--baseline-spp")) {
            baseline_spp_list = v;
        } else if (!strcmp(a, "--methods")) {
            method_list = v;
        } else if (!strcmp(a, "--mu")) {
            mu_list = v;
        } else if (!strcmp(a, "--out")) {
            o->out_dir = v;
        } else if (!strcmp(a, "--cache")) {
            o->cache_dir = v;
        } else if (!strcmp(a, "--ref-spp")) {
            if (!parse_int(v, 1, 1 << 24, &n)) {
                fprintf(stderr, "wedge converge: --ref-spp wants a positive integer, got '%s'\n", v);
                return WEDGE_EXIT_USAGE;
            }
            o->ref_spp = (int)n;
        } else if (!strcmp(a, "--seed")) {
            if (!parse_int(v, 0, 1ll << 30, &n)) {
                fprintf(stderr, "wedge converge: --seed wants an integer in [0, 2^30], got '%s'\n", v);
                return WEDGE_EXIT_USAGE;
            }
            o->seed = n;
        } else if (!strcmp(a, "--ref-seed")) {
            if (!parse_int(v, 0, 1ll << 30, &n)) {
                fprintf(stderr, "wedge converge: --ref-seed wants an integer in [0, 2^30], got '%s'\n", v);
                return WEDGE_EXIT_USAGE;
            }
            o->ref_seed = n;
        } else if (!strcmp(a, "--threads")) {
            if (!parse_int(v, 1, 4096, &n)) {
                fprintf(stderr, "wedge converge: --threads wants a positive integer, got '%s'\n", v);
                return WEDGE_EXIT_USAGE;
            }
            o->threads = (int)n;
        } else if (!strcmp(a, "--res")) {
            int w, h;
            char tail;
            if (sscanf(v, "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 65536 || h > 65536) {
                fprintf(stderr, "wedge converge: --res wants WxH (e.g. 128x128), got '%s'\n", v);
                return WEDGE_EXIT_USAGE;
            }
            o->width = w;
            o->height = h;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "wedge converge: unknown option '%s'\n", a);
            return WEDGE_EXIT_USAGE;
        } else if (!o->scene_path) {
            o->scene_path = a;
            takes_value = false;
        } else {
            fprintf(stderr, "wedge converge: more than one scene given ('%s' and '%s')\n", o->scene_path, a);
            return WEDGE_EXIT_USAGE;
        }
        if (takes_value) ++i;
    }
    if (o->print_key) return WEDGE_EXIT_OK;
    if ((o->out_dir && strlen(o->out_dir) > 2048) || (o->cache_dir && strlen(o->cache_dir) > 2048)) {
        fprintf(stderr, "wedge converge: --out and --cache paths are limited to 2048 characters\n");
        return WEDGE_EXIT_USAGE;
    }

    if (!spp_list || !method_list || !o->out_dir) {
        fprintf(stderr, "wedge converge: --spp, --methods and --out are required\n");
        usage(stderr);
        return WEDGE_EXIT_USAGE;
    }
    /* The option strings are copied so that strtok can cut them. */
    static char method_buf[1024], mu_buf[1024];
    snprintf(method_buf, sizeof method_buf, "%s", method_list);
    if (!parse_spp_list(spp_list, "--spp", o->spp, &o->spp_count) ||
        (baseline_spp_list && !parse_spp_list(baseline_spp_list, "--baseline-spp", o->baseline_spp, &o->baseline_spp_count)))
        return WEDGE_EXIT_USAGE;
    const char *items[MAX_LIST];
    int count;
    count = split_list(method_buf, items, MAX_LIST);
    if (count <= 0) {
        fprintf(stderr, "wedge converge: --methods wants a list like mc,mc-ld\n");
        return WEDGE_EXIT_USAGE;
    }
    for (int i = 0; i < count; ++i) {
        const ConvergeMethod *m = converge_method_find(items[i]);
        if (!m) {
            fprintf(stderr, "wedge converge: unknown method '%s'; known:", items[i]);
            for (int k = 0; k < converge_method_count(); ++k) fprintf(stderr, " %s", converge_method_at(k)->name);
            fprintf(stderr, "\n");
            return WEDGE_EXIT_USAGE;
        }
        o->methods[o->method_count++] = m;
    }
    if (mu_list) {
        snprintf(mu_buf, sizeof mu_buf, "%s", mu_list);
        count = split_list(mu_buf, o->mu, MAX_LIST);
        if (count <= 0) {
            fprintf(stderr, "wedge converge: --mu wants a list like 0.5,1,2\n");
            return WEDGE_EXIT_USAGE;
        }
        for (int i = 0; i < count; ++i) {
            char *end;
            double mu = strtod(o->mu[i], &end);
            if (end == o->mu[i] || *end || !(mu > 0) || !isfinite(mu)) {
                fprintf(stderr, "wedge converge: bad mu '%s' in --mu (a positive number)\n", o->mu[i]);
                return WEDGE_EXIT_USAGE;
            }
        }
        o->mu_count = count;
    }
    return WEDGE_EXIT_OK;
}

/* ---- subprocess: wedge render ---- */

typedef struct {
    const char *argv[64];
    int argc;
    char storage[16][64]; /* numbers formatted for argv */
    int used;
} ArgList;

static void arg_add(ArgList *l, const char *s)
{
    if (l->argc < 63) l->argv[l->argc++] = s;
    l->argv[l->argc] = NULL;
}

static void arg_addf(ArgList *l, const char *fmt, long long a, long long b)
{
    if (l->used >= 16) return;
    char *s = l->storage[l->used++];
    snprintf(s, 64, fmt, a, b);
    arg_add(l, s);
}

/* Runs `wedge render` with l's arguments (argv[0] included). Returns the exit code, or
 * WEDGE_EXIT_RUNTIME when the process could not run or died on a signal. */
static int run_render(const ArgList *l)
{
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) {
        fprintf(stderr, "wedge converge: error: cannot start a render: %s\n", strerror(errno));
        return WEDGE_EXIT_RUNTIME;
    }
    if (pid == 0) {
        /* The same binary that runs this sweep renders it: no PATH lookup, no version skew. */
        execv("/proc/self/exe", (char *const *)l->argv);
        fprintf(stderr, "wedge converge: error: cannot run /proc/self/exe: %s\n", strerror(errno));
        _exit(WEDGE_EXIT_RUNTIME);
    }
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return WEDGE_EXIT_RUNTIME;
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    fprintf(stderr, "wedge converge: error: render died on signal %d\n", WIFSIGNALED(status) ? WTERMSIG(status) : -1);
    return WEDGE_EXIT_RUNTIME;
}

static void print_command(FILE *f, const ArgList *l)
{
    fprintf(f, "  wedge");
    for (int i = 1; i < l->argc; ++i) fprintf(f, " %s", l->argv[i]);
    fprintf(f, "\n");
}

/* The render command line shared by references and runs. */
static void base_render_args(ArgList *l, const ConvergeOptions *o, const char *out_image, int spp,
                             long long seed, const char *report)
{
    memset(l, 0, sizeof *l);
    arg_add(l, "wedge");
    arg_add(l, "render");
    if (o->scene_path) arg_add(l, o->scene_path);
    arg_add(l, "-o");
    arg_add(l, out_image);
    if (spp > 0) { /* 0: the filter's own budget (a run per --mu value) */
        arg_add(l, "--spp");
        arg_addf(l, "%lld", spp, 0);
    }
    arg_add(l, "--res");
    arg_addf(l, "%lldx%lld", o->width, o->height);
    arg_add(l, "--seed");
    arg_addf(l, "%lld", seed, 0);
    if (o->threads > 0) {
        arg_add(l, "--threads");
        arg_addf(l, "%lld", o->threads, 0);
    }
    if (report) {
        arg_add(l, "--report");
        arg_add(l, report);
    }
    arg_add(l, "--quiet");
}

/* ---- the run report (flat JSON object of issue 3) ---- */

static char *read_text_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap);
    size_t got;
    while (buf && (got = fread(buf + n, 1, cap - n - 1, f)) > 0) {
        n += got;
        if (cap - n - 1 == 0) {
            char *bigger = realloc(buf, cap * 2);
            if (!bigger) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = bigger;
            cap *= 2;
        }
    }
    fclose(f);
    if (buf) buf[n] = '\0';
    return buf;
}

/* The number after "key": in a flat JSON object; false when absent or not a number. */
static bool json_number(const char *json, const char *key, double *out)
{
    char pattern[80];
    snprintf(pattern, sizeof pattern, "\"%s\"", key);
    const char *p = strstr(json, pattern);
    if (!p) return false;
    p += strlen(pattern);
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
    if (*p != ':') return false;
    ++p;
    char *end;
    double v = strtod(p, &end);
    if (end == p || !isfinite(v)) return false;
    *out = v;
    return true;
}

/* True when a render report says the render was stopped early (Ctrl-C). */
static bool report_interrupted(const char *report)
{
    char *json = read_text_file(report);
    bool yes = json && strstr(json, "\"interrupted\": true");
    free(json);
    return yes;
}

/* ---- output ---- */

static const char *scene_name(const ConvergeOptions *o, char *buf, size_t size)
{
    if (!o->scene_path) return "default";
    const char *base = strrchr(o->scene_path, '/');
    base = base ? base + 1 : o->scene_path;
    snprintf(buf, size, "%s", base);
    char *dot = strrchr(buf, '.');
    if (dot && dot != buf && !strcmp(dot, ".pbrt")) *dot = '\0';
    return buf;
}

static void csv_row(FILE *f, const char *scene, const ConvergeRow *r)
{
    fprintf(f, "%s,%s,%s,%.6g,%.6g,%.6g,%.6g,%.9g,%.9g,%.6f,%.6f,%.6g\n", scene, r->method->name,
            r->mu ? r->mu : "", r->spp_avg, r->seconds_total, r->seconds_trace, r->seconds_filter,
            r->relmse, r->mse, r->psnr, r->ssim, r->cpu_seconds_total);
    fflush(f);
}

static bool copy_file(const char *from, const char *to)
{
    FILE *in = fopen(from, "rb");
    if (!in) return false;
    FILE *out = fopen(to, "wb");
    if (!out) {
        fclose(in);
        return false;
    }
    char buf[1 << 16];
    size_t n;
    bool ok = true;
    while ((n = fread(buf, 1, sizeof buf, in)) > 0)
        if (fwrite(buf, 1, n, out) != n) ok = false;
    ok = ok && !ferror(in);
    fclose(in);
    return fclose(out) == 0 && ok;
}

/* tools/plot-convergence: $WEDGE_PLOT_CONVERGENCE, else the source tree this binary was
 * built from (this file's path tells where it is), else next to the binary's folder. */
static bool find_plot_tool(char *out, size_t size)
{
    const char *env = getenv("WEDGE_PLOT_CONVERGENCE");
    if (env && access(env, X_OK) == 0) {
        snprintf(out, size, "%s", env);
        return true;
    }
    const char *src = __FILE__, *tail = strstr(src, "src/app/cmd_converge.c");
    if (src[0] == '/' && tail) {
        if (fmt_path(out, size, "%.*stools/plot-convergence", (int)(tail - src), src) && access(out, X_OK) == 0)
            return true;
    }
    char exe[4096];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        exe[n] = '\0';
        char *slash = strrchr(exe, '/');
        if (slash) {
            *slash = '\0';
            if (fmt_path(out, size, "%s/../tools/plot-convergence", exe) && access(out, X_OK) == 0) return true;
        }
    }
    return false;
}

static void make_plots(const char *out_dir)
{
    char tool[4096];
    if (!find_plot_tool(tool, sizeof tool)) {
        fprintf(stderr, "wedge converge: warning: tools/plot-convergence not found (set WEDGE_PLOT_CONVERGENCE); no plots\n");
        return;
    }
    ArgList l;
    memset(&l, 0, sizeof l);
    arg_add(&l, tool);
    arg_add(&l, out_dir);
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid == 0) {
        execv(tool, (char *const *)l.argv);
        _exit(127);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        fprintf(stderr, "wedge converge: warning: %s failed; no plots (is gnuplot installed? tools/setup)\n", tool);
}

/* ---- speedup ---- */

/* One block of speedups: every run against one baseline's curve (rows of speedup.csv and
 * lines of the printed table). False, and nothing written, when the sweep has under two runs
 * of the baseline. */
static bool speedup_against(FILE *f, const char *scene, const char *baseline, const ConvergeRow *rows, int row_count,
                            CurvePoint *curve, CurvePoint *curve_cpu)
{
    int n = 0;
    for (int i = 0; i < row_count; ++i)
        if (!strcmp(rows[i].method->name, baseline)) {
            curve_cpu[n] = (CurvePoint){rows[i].spp_avg, rows[i].cpu_seconds_total, rows[i].relmse};
            curve[n++] = (CurvePoint){rows[i].spp_avg, rows[i].seconds_total, rows[i].relmse};
        }
    if (n < 2) return false;
    printf("\nequal-error speedup against %s (relMSE; baseline interpolated in log-log):\n", baseline);
    printf("  %-8s %-6s %9s %11s %11s %10s %10s %10s\n", "method", "mu", "spp", "relMSE", "base spp", "x samples",
           "x time", "x CPU");
    for (int i = 0; i < row_count; ++i) {
        const ConvergeRow *r = &rows[i];
        EqualErrorCost c = equal_error_cost(curve, n, r->relmse);
        if (!c.valid || !(r->spp_avg > 0) || !(r->seconds_total > 0)) continue;
        double x_samples = c.spp / r->spp_avg, x_time = c.seconds / r->seconds_total;
        /* the same error on the CPU-seconds curve (its interpolation in spp is the same) */
        EqualErrorCost c_cpu = equal_error_cost(curve_cpu, n, r->relmse);
        double x_cpu = c_cpu.valid && r->cpu_seconds_total > 0 ? c_cpu.seconds / r->cpu_seconds_total : 0.0;
        fprintf(f, "%s,%s,%s,%s,%.6g,%.6g,%.9g,%.6g,%.6g,%.6g,%.6g,%d,%.6g,%.6g,%.6g\n", scene, r->method->name,
                r->mu ? r->mu : "", baseline, r->spp_avg, r->seconds_total, r->relmse, c.spp, c.seconds, x_samples,
                x_time, c.extrapolated, r->cpu_seconds_total, c_cpu.seconds, x_cpu);
        printf("  %-8s %-6s %9.1f %11.4g %11.1f %10.3g %10.3g %10.3g%s\n", r->method->name, r->mu ? r->mu : "-",
               r->spp_avg, r->relmse, c.spp, x_samples, x_time, x_cpu, c.extrapolated ? "  (extrapolated)" : "");
    }
    return true;
}

static void write_speedup(const char *out_dir, const char *scene, const ConvergeRow *rows, int row_count)
{
    CurvePoint *curve = malloc(sizeof *curve * 2 * (size_t)(row_count ? row_count : 1));
    if (!curve) return;
    CurvePoint *curve_cpu = curve + (row_count ? row_count : 1);
    char path[4096];
    snprintf(path, sizeof path, "%s/speedup.csv", out_dir);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "wedge converge: error: cannot write %s: %s\n", path, strerror(errno));
        free(curve);
        return;
    }
    fprintf(f, "scene,method,mu,baseline,spp_avg,seconds_total,relmse,base_spp,base_seconds,speedup_samples,"
               "speedup_time,extrapolated,cpu_seconds_total,base_cpu_seconds,speedup_cpu\n");
    bool any = false;
    for (int b = 0; b < converge_baseline_method_count; ++b)
        any = speedup_against(f, scene, converge_baseline_methods[b], rows, row_count, curve, curve_cpu) || any;
    if (!any)
        printf("equal-error speedup: needs a Monte Carlo method (%s or %s) with at least two budgets in the sweep\n",
               converge_baseline_methods[0], converge_baseline_methods[1]);
    fclose(f);
    free(curve);
}

/* ---- the sweep ---- */

static int load_scene(const ConvergeOptions *o, SceneDesc *scene)
{
    Diag err = {0};
    bool ok = o->scene_path
                  ? scene_parse_file(o->scene_path, scene, &err)
                  : scene_parse_string(wedge_default_scene, strlen(wedge_default_scene), "<default>", NULL, scene, &err);
    if (!ok) {
        diag_print(&err);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
    }
    return WEDGE_EXIT_OK;
}

static bool compute_errors(const float *ref, const float *img, int w, int h, ConvergeRow *r)
{
    ImageMetrics m;
    if (!image_metrics_compute(ref, img, w, h, &m)) return false;
    r->relmse = m.relmse;
    r->mse = m.mse;
    r->psnr = m.psnr;
    r->ssim = m.ssim;
    return true;
}

/* ---- the sweep's runs ---- */

/* One render of the sweep. */
typedef struct {
    const ConvergeMethod *method;
    const char *mu;  /* NULL: no --mu */
    int spp;         /* the --spp budget; 0 when the filter sets its samples from mu */
    long long seed;
    int step;        /* its place in its (method, mu) list: the round it runs in */
} ConvergeRun;

/* Every run, method by method (each mu of a method in turn, then its budgets): the order of
 * the rows in results.csv. A fresh seed per run, o->seed + 1, + 2, ... (the reference uses
 * --ref-seed, by default o->seed itself): runs are independent of each other and of the
 * reference, so errors do not correlate. A --ref-seed among the runs' seeds would correlate
 * one run with the reference: the caller keeps them apart (tools/bench-summary does). */
static ConvergeRun *plan_runs(const ConvergeOptions *o, int *count)
{
    int most_spp = o->spp_count > o->baseline_spp_count ? o->spp_count : o->baseline_spp_count;
    int max_runs = o->method_count * (o->mu_count > 0 ? o->mu_count : 1) * (most_spp > 0 ? most_spp : 1);
    ConvergeRun *runs = calloc((size_t)(max_runs ? max_runs : 1), sizeof *runs);
    *count = 0;
    if (!runs) return NULL;
    for (int mi = 0; mi < o->method_count; ++mi) {
        const ConvergeMethod *m = o->methods[mi];
        int mu_runs = m->takes_mu && o->mu_count > 0 ? o->mu_count : 1;
        for (int ui = 0; ui < mu_runs; ++ui) {
            const char *mu = m->takes_mu && o->mu_count > 0 ? o->mu[ui] : NULL;
            /* A filter with --mu sets each pixel's samples itself from mu: one run per mu. Without
             * --mu, each --spp value is the filter's average budget (wedge render --spp). */
            bool baseline = o->baseline_spp_count > 0 && is_baseline(m);
            const int *spp = baseline ? o->baseline_spp : o->spp;
            int spp_runs = mu ? 1 : baseline ? o->baseline_spp_count : o->spp_count;
            for (int si = 0; si < spp_runs; ++si) {
                ConvergeRun *r = &runs[(*count)++];
                *r = (ConvergeRun){m, mu, mu ? 0 : spp[si], o->seed + *count, si};
            }
        }
    }
    return runs;
}

/* Renders one run, reads its report and image, and fills row. Returns an exit code. */
static int run_one(const ConvergeOptions *o, const ConvergeRun *run, const char *name, const char *images,
                   const float *ref, ConvergeRow *row)
{
    const ConvergeMethod *m = run->method;
    const char *mu = run->mu;
    char stem[4400], image[4500], report[4500], spp_label[32] = "";
    if (!mu) snprintf(spp_label, sizeof spp_label, "-spp%d", run->spp);
    if (!fmt_path(stem, sizeof stem, "%s/%s-%s%s%s%s", images, name, m->name, mu ? "-mu" : "", mu ? mu : "",
                  spp_label) ||
        !fmt_path(image, sizeof image, "%s.exr", stem) || !fmt_path(report, sizeof report, "%s.json", stem)) {
        fprintf(stderr, "wedge converge: error: output path too long\n");
        return WEDGE_EXIT_RUNTIME;
    }
    ArgList l;
    base_render_args(&l, o, image, run->spp, run->seed, report);
    for (int k = 0; m->render_args[k]; ++k) arg_add(&l, m->render_args[k]);
    if (mu) {
        arg_add(&l, "--mu");
        arg_add(&l, mu);
    }
    int code = run_render(&l);
    if (code != WEDGE_EXIT_OK) {
        fprintf(stderr, "wedge converge: error: render failed (exit %d):\n", code);
        print_command(stderr, &l);
        return code;
    }
    if (report_interrupted(report)) {
        fprintf(stderr, "wedge converge: interrupted; the results so far are in %s/results.csv\n", o->out_dir);
        return WEDGE_EXIT_RUNTIME;
    }
    ConvergeRow r = {.method = m, .mu = mu};
    char *json = read_text_file(report);
    bool have = json && json_number(json, "spp_avg", &r.spp_avg) && json_number(json, "seconds_total", &r.seconds_total) &&
                json_number(json, "seconds_trace", &r.seconds_trace) &&
                json_number(json, "seconds_filter", &r.seconds_filter) &&
                json_number(json, "cpu_seconds_total", &r.cpu_seconds_total);
    free(json);
    if (!have) {
        fprintf(stderr, "wedge converge: error: %s lacks spp_avg/seconds_total/seconds_trace/seconds_filter/"
                        "cpu_seconds_total\n",
                report);
        return WEDGE_EXIT_RUNTIME;
    }
    int w, h;
    float *img = NULL;
    Diag err = {0};
    if (!exr_read_rgb(image, &w, &h, &img, &err)) {
        diag_print(&err);
        return WEDGE_EXIT_RUNTIME;
    }
    bool same = w == o->width && h == o->height;
    if (!same || !compute_errors(ref, img, w, h, &r)) {
        fprintf(stderr, "wedge converge: error: cannot compare %s with the reference\n", image);
        free(img);
        return WEDGE_EXIT_RUNTIME;
    }
    free(img);
    *row = r;
    printf("%-8s %-6s %6d %9.2f %9.3f %12.5g %12.5g %8.3f %7.4f\n", m->name, mu ? mu : "-", run->spp, r.spp_avg,
           r.seconds_total, r.relmse, r.mse, r.psnr, r.ssim);
    fflush(stdout);
    return WEDGE_EXIT_OK;
}

/* results.csv with the finished runs, in the plan's order; rewritten whole after every run
 * (a temporary file renamed over it), so that an interrupted sweep leaves a complete file. */
static bool write_results(const char *path, const char *scene, const ConvergeRow *rows, const bool *done, int count)
{
    char tmp[4500];
    snprintf(tmp, sizeof tmp, "%s.tmp-%ld", path, (long)getpid());
    FILE *csv = fopen(tmp, "w");
    if (!csv) {
        fprintf(stderr, "wedge converge: error: cannot write %s: %s\n", tmp, strerror(errno));
        return false;
    }
    fprintf(csv, "scene,method,mu,spp_avg,seconds_total,seconds_trace,seconds_filter,relmse,mse,psnr,ssim,"
                 "cpu_seconds_total\n");
    for (int i = 0; i < count; ++i)
        if (done[i]) csv_row(csv, scene, &rows[i]);
    bool ok = fclose(csv) == 0 && rename(tmp, path) == 0;
    if (!ok) {
        fprintf(stderr, "wedge converge: error: cannot write %s: %s\n", path, strerror(errno));
        unlink(tmp);
    }
    return ok;
}

int cmd_converge(int argc, char **argv)
{
    ConvergeOptions o;
    int rc = parse_args(argc, argv, &o);
    if (rc == HELP_SHOWN) return WEDGE_EXIT_OK;
    if (rc != WEDGE_EXIT_OK) return rc;

    SceneDesc scene;
    memset(&scene, 0, sizeof scene);
    rc = load_scene(&o, &scene);
    if (rc != WEDGE_EXIT_OK) return rc;
    if (o.width == 0) {
        o.width = scene.film.xres;
        o.height = scene.film.yres;
    }

    /* Reference key, path and (when missing) the reference render. */
    Diag err = {0};
    if (o.ref_seed < 0) o.ref_seed = o.seed;
    RefParams rp = {o.width, o.height, o.ref_spp, (uint64_t)o.ref_seed, converge_reference_args,
                    converge_reference_arg_count};
    char key[33];
    if (!ref_key_for_scene(&scene, o.scene_path ? NULL : wedge_default_scene, &rp, key, &err)) {
        diag_print(&err);
        scene_desc_free(&scene);
        return err.exit_code;
    }
    scene_desc_free(&scene);
    if (o.print_key) {
        printf("%s\n", key);
        return WEDGE_EXIT_OK;
    }
    char cache[4096], ref_path[4200], ref_report[4200];
    if (!ref_cache_dir(o.cache_dir, cache, sizeof cache, &err)) {
        diag_print(&err);
        return err.exit_code;
    }
    snprintf(ref_path, sizeof ref_path, "%s/ref-%s.exr", cache, key);
    snprintf(ref_report, sizeof ref_report, "%s/ref-%s.json", cache, key);
    ArgList l;
    if (access(ref_path, R_OK) == 0) {
        fprintf(stderr, "converge: reference cached: %s\n", ref_path);
    } else {
        fprintf(stderr, "converge: rendering reference (%d spp, %dx%d) -> %s\n", o.ref_spp, o.width, o.height, ref_path);
        /* Rendered under a temporary name and renamed only when complete: a reference cut
         * short (Ctrl-C writes the samples taken so far) must never enter the cache. */
        char ref_tmp[4300];
        snprintf(ref_tmp, sizeof ref_tmp, "%s/ref-%s.%ld.tmp.exr", cache, key, (long)getpid());
        base_render_args(&l, &o, ref_tmp, o.ref_spp, o.ref_seed, ref_report);
        for (int i = 0; i < converge_reference_arg_count; ++i) arg_add(&l, converge_reference_args[i]);
        rc = run_render(&l);
        if (rc == WEDGE_EXIT_OK && report_interrupted(ref_report)) {
            fprintf(stderr, "wedge converge: error: the reference render was interrupted; nothing cached\n");
            rc = WEDGE_EXIT_RUNTIME;
        } else if (rc != WEDGE_EXIT_OK) {
            fprintf(stderr, "wedge converge: error: the reference render failed (exit %d):\n", rc);
            print_command(stderr, &l);
        } else if (rename(ref_tmp, ref_path) != 0) {
            fprintf(stderr, "wedge converge: error: cannot move the reference to %s: %s\n", ref_path, strerror(errno));
            rc = WEDGE_EXIT_RUNTIME;
        }
        if (rc != WEDGE_EXIT_OK) {
            unlink(ref_tmp);
            return rc;
        }
    }
    int ref_w, ref_h;
    float *ref = NULL;
    if (!exr_read_rgb(ref_path, &ref_w, &ref_h, &ref, &err)) {
        diag_print(&err);
        return WEDGE_EXIT_RUNTIME;
    }
    if (ref_w != o.width || ref_h != o.height) {
        fprintf(stderr, "wedge converge: error: reference %s is %dx%d, expected %dx%d\n", ref_path, ref_w, ref_h, o.width, o.height);
        free(ref);
        return WEDGE_EXIT_RUNTIME;
    }

    /* Output folder, CSV header, a copy of the reference beside the results. */
    char path[4400], images[4200];
    snprintf(images, sizeof images, "%s/images", o.out_dir);
    if (!make_dirs(images)) {
        fprintf(stderr, "wedge converge: error: cannot create %s: %s\n", images, strerror(errno));
        free(ref);
        return WEDGE_EXIT_RUNTIME;
    }
    /* The command line, for the benchmark report (tools/bench-report). */
    snprintf(path, sizeof path, "%s/command.txt", o.out_dir);
    FILE *cmd = fopen(path, "w");
    if (cmd) {
        fprintf(cmd, "wedge");
        for (int i = 0; i < argc; ++i) fprintf(cmd, " %s", argv[i]);
        fprintf(cmd, "\nreference: %s (%d spp)\n", ref_path, o.ref_spp);
        /* Timings mean little on a busy machine: record how busy it was. */
        char load[128] = "";
        FILE *la = fopen("/proc/loadavg", "r");
        if (la) {
            if (fgets(load, sizeof load, la)) fprintf(cmd, "load average at start: %s", load);
            fclose(la);
        }
        fclose(cmd);
    }
    snprintf(path, sizeof path, "%s/reference.exr", o.out_dir);
    if (!copy_file(ref_path, path)) fprintf(stderr, "wedge converge: warning: cannot copy the reference to %s\n", path);
    char name_buf[256];
    const char *name = scene_name(&o, name_buf, sizeof name_buf);
    snprintf(path, sizeof path, "%s/results.csv", o.out_dir);

    int run_count = 0;
    ConvergeRun *runs = plan_runs(&o, &run_count);
    ConvergeRow *rows = calloc((size_t)(run_count ? run_count : 1), sizeof *rows);
    bool *done = calloc((size_t)(run_count ? run_count : 1), sizeof *done);
    rc = runs && rows && done ? WEDGE_EXIT_OK : WEDGE_EXIT_RUNTIME;
    if (rc == WEDGE_EXIT_OK && !write_results(path, name, rows, done, run_count)) rc = WEDGE_EXIT_RUNTIME; /* the header */
    printf("%-8s %-6s %6s %9s %9s %12s %12s %8s %7s\n", "method", "mu", "spp", "spp_avg", "seconds", "relMSE", "MSE", "PSNR", "SSIM");
    /* The runs go in rounds, every method's k-th run in round k, rather than one method's
     * whole list after another: a machine whose load drifts during the sweep then slows
     * every method alike instead of whichever method ran during the busy minutes (the
     * equal-error time ratios are the point of the sweep). The seeds and the rows' order
     * in results.csv and speedup.csv are those of the method-by-method plan. */
    int rounds = 0;
    for (int i = 0; i < run_count; ++i) rounds = runs[i].step + 1 > rounds ? runs[i].step + 1 : rounds;
    for (int k = 0; k < rounds && rc == WEDGE_EXIT_OK; ++k)
        for (int i = 0; i < run_count && rc == WEDGE_EXIT_OK; ++i) {
            if (runs[i].step != k) continue;
            rc = run_one(&o, &runs[i], name, images, ref, &rows[i]);
            if (rc != WEDGE_EXIT_OK) break;
            done[i] = true;
            if (!write_results(path, name, rows, done, run_count)) rc = WEDGE_EXIT_RUNTIME;
        }
    free(ref);
    int row_count = 0;
    for (int i = 0; i < run_count; ++i)
        if (done[i]) rows[row_count++] = rows[i];
    if (row_count > 0) {
        write_speedup(o.out_dir, name, rows, row_count);
        if (!o.no_plots) make_plots(o.out_dir);
    }
    free(rows);
    free(done);
    free(runs);
    if (rc == WEDGE_EXIT_OK) printf("\nwrote %s/results.csv, %s/speedup.csv\n", o.out_dir, o.out_dir);
    return rc;
}
