/* wedge compare REF TEST [--json] [--diff OUT.exr|OUT.png]
 *
 * Error metrics of TEST against REF with the exact definitions of issue 5 (see
 * core/image_metrics.h). Either image may be EXR (R, G, B or Y, linear) or PNG (decoded
 * from sRGB to linear, alpha ignored). --diff writes the false-colour relative-error map:
 * as PNG the colours themselves; as EXR the same colours in linear light in R, G, B plus
 * the raw per-pixel relative error in a channel "relerr". */
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
            "usage: wedge compare REF TEST [--json] [--diff OUT.exr|OUT.png]\n"
            "\n"
            "Error of TEST against the reference REF (EXR or PNG; PNG is decoded from sRGB):\n"
            "  relMSE  mean of (t - r)^2 / (r^2 + 0.01) over pixels and channels\n"
            "  MSE     mean of (t - r)^2; RMSE its square root\n"
            "  PSNR    10 log10(1 / MSE of the images clamped to [0,1]), at most 100 dB\n"
            "  SSIM    mean SSIM (11x11 Gaussian, sigma 1.5) of the sRGB-encoded luma\n"
            "  nonfinite  pixels of TEST with a NaN or infinite value (counted as 0 above)\n"
            "\n"
            "  --json         print one JSON object: relmse mse rmse psnr ssim nonfinite\n"
            "  --diff FILE    write a false-colour per-pixel relative error image\n"
            "                 (black < 0.001, blue, cyan, green, yellow, red >= 1;\n"
            "                 magenta where TEST is NaN or infinite)\n"
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

int cmd_compare(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL}, *diff_path = NULL;
    int npaths = 0;
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
    free(ref);
    free(test);
    if (rc != WEDGE_EXIT_OK) {
        fprintf(stderr, "%s\n", err.message);
        return rc;
    }
    if (json) {
        printf("{\"relmse\": %.9g, \"mse\": %.9g, \"rmse\": %.9g, \"psnr\": %.9g, \"ssim\": %.9g, \"nonfinite\": %ld}\n",
               m.relmse, m.mse, m.rmse, m.psnr, m.ssim, m.nonfinite);
    } else {
        printf("relMSE     %.6g\n", m.relmse);
        printf("MSE        %.6g\n", m.mse);
        printf("RMSE       %.6g\n", m.rmse);
        printf("PSNR       %.4f dB\n", m.psnr);
        printf("SSIM       %.6f\n", m.ssim);
        printf("non-finite %ld pixel%s\n", m.nonfinite, m.nonfinite == 1 ? "" : "s");
        if (diff_path) printf("diff       %s\n", diff_path);
    }
    return WEDGE_EXIT_OK;
}
