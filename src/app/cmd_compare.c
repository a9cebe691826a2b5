/* wedge compare REF TEST [--json] [--diff OUT.exr|OUT.png] [--by CHANNEL [--bins E1,E2,...]]
 *
 * Error metrics of TEST against REF with the exact definitions of issue 5 (see
 * core/image_metrics.h). Either image may be EXR (R, G, B or Y, linear) or PNG (decoded
 * from sRGB to linear, alpha ignored). --diff writes the false-colour relative-error map:
 * as PNG the colours themselves; as EXR the same colours in linear light in R, G, B plus
 * the raw per-pixel relative error in a channel "relerr". --by splits relMSE by the value of
 * one of TEST's EXR channels (a filter width, the spp layer): which pixels carry the error;
 * --by edge_px by each pixel's distance to the image's edge (the border's share). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "app/commands.h"
#include "core/diag.h"
#include "core/image_metrics.h"
#include "io/image_io.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wedge compare REF TEST [--json] [--diff OUT.exr|OUT.png] [--by CHANNEL [--bins E1,E2,...]]\n"
            "\n"
            "Error of TEST against the reference REF (EXR or PNG; PNG is decoded from sRGB):\n"
            "  relMSE  mean of (t - r)^2 / (r^2 + 0.01) over pixels and channels\n"
            "  MSE     mean of (t - r)^2; RMSE its square root\n"
            "  PSNR    10 log10(1 / MSE of the images clamped to [0,1]), at most 100 dB\n"
            "  SSIM    mean SSIM (11x11 Gaussian, sigma 1.5) of the sRGB-encoded luma\n"
            "  nonfinite  pixels of TEST with a NaN or infinite value (counted as 0 above); the same\n"
            "             for REF as nonfinite_ref (and a warning on stderr for either)\n"
            "\n"
            "  --json         print one JSON object: relmse mse rmse psnr ssim nonfinite\n"
            "  --diff FILE    write a false-colour per-pixel relative error image\n"
            "                 (black < 0.001, blue, cyan, green, yellow, red >= 1;\n"
            "                 magenta where TEST is NaN or infinite)\n"
            "  --by CHANNEL   split relMSE by the value of TEST's EXR channel CHANNEL (e.g.\n"
            "                 aaf.beta_px.shadow or spp from 'wedge render --aovs'): per bin\n"
            "                 the share of pixels, the mean value, relMSE and share of relMSE;\n"
            "                 edge_px (not a channel): each pixel's distance in pixels to the\n"
            "                 image's nearest edge (0 on the outermost rows and columns), e.g.\n"
            "                 --by edge_px --bins 8 for the 8-pixel border's share\n"
            "  --bins LIST    increasing bin edges for --by (default 0.5,1,2,4,...,256);\n"
            "                 the first bin is open below, the last open above\n"
            "\n"
            "Exit codes: 0 ok, 1 usage, 2 unreadable image or size mismatch, 3 write failure.\n");
}

static bool has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n > e && !strcasecmp(path + n - e, ext);
}

static bool write_diff(const char *path, const float *ref, const float *test, int width, int height, Diag *err)
{
    size_t n = (size_t)width * (size_t)height;
    float *relerr = malloc(n * sizeof *relerr), *colour = malloc(n * 3 * sizeof *colour);
    bool ok = relerr && colour;
    if (!ok) {
        SrcLoc loc = {path, 0, 0};
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
    }
    if (ok) {
        image_relerr_map(ref, test, width, height, relerr, colour);
        if (path_is_png(path)) {
            ok = png_write_display(path, width, height, colour, err);
        } else {
            /* Linear values that display as the map's colours under a plain sRGB view. */
            for (size_t i = 0; i < 3 * n; ++i) colour[i] = srgb_decode(colour[i]);
            ExrChannel ch[] = {{"R", colour, 3}, {"G", colour + 1, 3}, {"B", colour + 2, 3}, {"relerr", relerr, 1}};
            ExrAttr attr = {"wedge.diff", EXR_ATTR_STRING, "relative error sqrt(mean_c (t-r)^2/(r^2+0.01))", 0.0, 0};
            ok = exr_write(path, width, height, ch, 4, &attr, 1, err);
        }
    }
    free(relerr);
    free(colour);
    return ok;
}

enum { MAX_BIN_EDGES = 64 };

/* "0.5,1,2" -> edges; false unless every item is a finite number above the previous one. */
static bool parse_edges(const char *list, double *edges, int *count)
{
    int n = 0;
    const char *p = list;
    for (;;) {
        char *end;
        double v = strtod(p, &end);
        if (end == p || !isfinite(v) || n == MAX_BIN_EDGES || (n > 0 && v <= edges[n - 1])) return false;
        edges[n++] = v;
        if (*end == '\0') break;
        if (*end != ',') return false;
        p = end + 1;
    }
    *count = n;
    return true;
}

/* Reads channel `channel` of the EXR TEST image for --by; an exit code. */
static int read_key(const char *test_path, const char *channel, int width, int height, float **key, Diag *err)
{
    SrcLoc loc = {test_path, 0, 0};
    if (!strcmp(channel, "edge_px")) { /* computed: how far inside the frame a pixel is */
        if (!(*key = malloc((size_t)width * (size_t)height * sizeof(float)))) {
            diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory for --by edge_px");
            return err->exit_code;
        }
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                int dx = x < width - 1 - x ? x : width - 1 - x, dy = y < height - 1 - y ? y : height - 1 - y;
                (*key)[(size_t)y * (size_t)width + (size_t)x] = (float)(dx < dy ? dx : dy);
            }
        return WEDGE_EXIT_OK;
    }
    if (path_is_png(test_path)) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "--by needs an EXR test image (a PNG has no other channels)");
        return err->exit_code;
    }
    int kw = 0, kh = 0;
    if (!exr_read_channel(test_path, channel, &kw, &kh, key, err)) return err->exit_code;
    if (kw != width || kh != height) { /* cannot happen for one file; guards a future reader */
        diag_set(err, WEDGE_EXIT_INPUT, loc, "channel '%s' is %dx%d but the image is %dx%d", channel, kw, kh, width,
                 height);
        free(*key);
        *key = NULL;
        return err->exit_code;
    }
    return WEDGE_EXIT_OK;
}

/* Prints the relMSE of TEST split by the value of `key` (see image_relmse_by_key): a
 * JSON member after the metrics' members, or a table. */
static void print_breakdown(const char *channel, const float *key, const float *ref, const float *test, int width,
                            int height, const double *edges, int edge_count, bool json)
{
    ErrorBin bins[MAX_BIN_EDGES + 1];
    image_relmse_by_key(ref, test, key, width, height, edges, edge_count, bins);
    double total = 0.0, pixels = (double)width * (double)height;
    for (int b = 0; b <= edge_count; ++b) total += bins[b].relmse_sum;
    if (json) {
        printf(", \"by\": {\"channel\": \"");
        for (const char *c = channel; *c; ++c) { /* an EXR channel name may hold any byte */
            if (*c == '"' || *c == '\\') printf("\\%c", *c);
            else if ((unsigned char)*c < 0x20) printf("\\u%04x", (unsigned)(unsigned char)*c);
            else putchar(*c);
        }
        printf("\", \"bins\": [");
    } else {
        printf("\nrelMSE by %s:\n", channel);
        printf("  %-24s %8s %12s %12s %10s\n", "range", "pixels", "mean value", "relMSE", "of relMSE");
    }
    bool first = true;
    for (int b = 0; b <= edge_count; ++b) {
        const ErrorBin *e = &bins[b];
        if (e->pixels == 0) continue; /* empty bins say nothing */
        double pixel_share = (double)e->pixels / pixels, mean_key = e->key_sum / (double)e->pixels;
        double relmse = e->relmse_sum / (double)e->pixels, share = total > 0.0 ? e->relmse_sum / total : 0.0;
        if (json) {
            printf("%s{\"lo\": ", first ? "" : ", ");
            if (b > 0) printf("%.9g", edges[b - 1]); else printf("null"); /* open ends: JSON has no infinity */
            printf(", \"hi\": ");
            if (b < edge_count) printf("%.9g", edges[b]); else printf("null");
            printf(", \"pixels\": %ld, \"pixel_share\": %.9g, \"mean\": %.9g, \"relmse\": %.9g, \"relmse_share\": %.9g}",
                   e->pixels, pixel_share, mean_key, relmse, share);
        } else {
            char range[64];
            if (b == 0) snprintf(range, sizeof range, "< %g", edges[0]);
            else if (b == edge_count) snprintf(range, sizeof range, ">= %g", edges[b - 1]);
            else snprintf(range, sizeof range, "[%g, %g)", edges[b - 1], edges[b]);
            printf("  %-24s %7.1f%% %12.4g %12.4g %9.1f%%\n", range, 100.0 * pixel_share, mean_key, relmse, 100.0 * share);
        }
        first = false;
    }
    if (json) printf("]}");
}

int cmd_compare(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL}, *diff_path = NULL, *by_channel = NULL;
    int npaths = 0, edge_count = 0;
    double edges[MAX_BIN_EDGES];
    for (double e = 0.5; e <= 256.0; e *= 2.0) edges[edge_count++] = e;
    bool json = false;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return WEDGE_EXIT_OK;
        } else if (!strcmp(a, "--json")) {
            json = true;
        } else if (!strcmp(a, "--diff") || !strncmp(a, "--diff=", 7)) {
            if (a[6] == '=') {
                diff_path = a + 7;
            } else if (i + 1 < argc) {
                diff_path = argv[++i];
            } else {
                fprintf(stderr, "error: --diff needs a file name\n");
                usage(stderr);
                return WEDGE_EXIT_USAGE;
            }
            if (!has_extension(diff_path, ".exr") && !has_extension(diff_path, ".png")) {
                fprintf(stderr, "error: --diff file '%s' must end in .exr or .png\n", diff_path);
                return WEDGE_EXIT_USAGE;
            }
        } else if (!strcmp(a, "--by")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "error: --by needs a channel name (e.g. spp)\n");
                return WEDGE_EXIT_USAGE;
            }
            by_channel = argv[++i];
        } else if (!strcmp(a, "--bins")) {
            if (i + 1 >= argc || !parse_edges(argv[i + 1], edges, &edge_count)) {
                fprintf(stderr, "error: --bins needs increasing finite numbers separated by commas (at most %d), "
                                "e.g. --bins 0.5,1,2,4\n",
                        MAX_BIN_EDGES);
                return WEDGE_EXIT_USAGE;
            }
            ++i;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "error: unknown option '%s'\n", a);
            usage(stderr);
            return WEDGE_EXIT_USAGE;
        } else if (npaths < 2) {
            paths[npaths++] = a;
        } else {
            fprintf(stderr, "error: unexpected argument '%s' (give exactly REF and TEST)\n", a);
            usage(stderr);
            return WEDGE_EXIT_USAGE;
        }
    }
    if (npaths != 2) {
        fprintf(stderr, "error: need a reference and a test image\n");
        usage(stderr);
        return WEDGE_EXIT_USAGE;
    }

    Diag err = {0};
    int rw = 0, rh = 0, tw = 0, th = 0;
    float *ref = NULL, *test = NULL;
    if (!image_read_linear_rgb(paths[0], &rw, &rh, &ref, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return err.exit_code;
    }
    if (!image_read_linear_rgb(paths[1], &tw, &th, &test, &err)) {
        fprintf(stderr, "%s\n", err.message);
        free(ref);
        return err.exit_code;
    }
    int rc = WEDGE_EXIT_OK;
    ImageMetrics m;
    if (rw != tw || rh != th) {
        SrcLoc loc = {paths[1], 0, 0};
        diag_set(&err, WEDGE_EXIT_INPUT, loc, "image is %dx%d but the reference %s is %dx%d", tw, th, paths[0], rw,
                 rh);
        rc = err.exit_code;
    } else if (!image_metrics_compute(ref, test, rw, rh, &m)) {
        SrcLoc loc = {NULL, 0, 0};
        diag_set(&err, WEDGE_EXIT_RUNTIME, loc, "out of memory computing SSIM");
        rc = err.exit_code;
    } else if (diff_path && !write_diff(diff_path, ref, test, rw, rh, &err)) {
        rc = err.exit_code;
    }
    float *key = NULL; /* TEST's --by channel, read before anything is printed */
    if (rc == WEDGE_EXIT_OK && by_channel) rc = read_key(paths[1], by_channel, rw, rh, &key, &err);
    if (rc != WEDGE_EXIT_OK) {
        free(ref);
        free(test);
        free(key);
        fprintf(stderr, "%s\n", err.message);
        return rc;
    }
    for (int k = 0; k < 2; ++k) { /* counted as 0 in the metrics: never silently */
        long bad = k == 0 ? m.nonfinite_ref : m.nonfinite;
        if (bad > 0)
            fprintf(stderr, "wedge compare: warning: %s has %ld pixel%s with NaN or infinite values (counted as 0)\n",
                    paths[k], bad, bad == 1 ? "" : "s");
    }
    if (json) {
        printf("{\"relmse\": %.9g, \"mse\": %.9g, \"rmse\": %.9g, \"psnr\": %.9g, \"ssim\": %.9g, \"nonfinite\": %ld, "
               "\"nonfinite_ref\": %ld",
               m.relmse, m.mse, m.rmse, m.psnr, m.ssim, m.nonfinite, m.nonfinite_ref);
    } else {
        printf("relMSE     %.6g\n", m.relmse);
        printf("MSE        %.6g\n", m.mse);
        printf("RMSE       %.6g\n", m.rmse);
        printf("PSNR       %.4f dB\n", m.psnr);
        printf("SSIM       %.6f\n", m.ssim);
        printf("non-finite %ld pixel%s\n", m.nonfinite, m.nonfinite == 1 ? "" : "s");
        printf("non-finite in the reference %ld pixel%s\n", m.nonfinite_ref, m.nonfinite_ref == 1 ? "" : "s");
        if (diff_path) printf("diff       %s\n", diff_path);
    }
    if (key) print_breakdown(by_channel, key, ref, test, rw, rh, edges, edge_count, json);
    if (json) printf("}\n");
    free(ref);
    free(test);
    free(key);
    return WEDGE_EXIT_OK;
}
