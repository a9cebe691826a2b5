/* wedge convert IN OUT [--view NAME]
 *
 * Image conversion, as pbrt's `imgtool convert` does it: an EXR (linear R, G, B or Y) or a
 * PNG (decoded from sRGB) in; out a PNG through the same OpenColorIO view that `wedge
 * render -o X.png` uses (so a render's EXR converts to exactly the PNG the render would have
 * written), or a float32 RGB EXR. The benchmark tools use it to show references and other
 * renders side by side. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/commands.h"
#include "core/diag.h"
#include "io/image_io.h"
#include "io/ocio.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wedge convert IN OUT [--view NAME]\n"
            "\n"
            "Converts IN (EXR, or PNG decoded from sRGB) to OUT: a .png is written through the\n"
            "OpenColorIO view NAME (default: the config's default view, as wedge render does),\n"
            "anything else as a float32 RGB EXR. Non-finite pixels are written as 0.\n"
            "\n"
            "Exit codes: 0 ok, 1 usage, 2 unreadable input, 3 write failure.\n");
}

int cmd_convert(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *view = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return WEDGE_EXIT_OK;
        } else if (!strcmp(a, "--view")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "wedge convert: --view needs a view name (see 'wedge render --help')\n");
                return WEDGE_EXIT_USAGE;
            }
            view = argv[++i];
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "wedge convert: unknown option '%s'\n", a);
            usage(stderr);
            return WEDGE_EXIT_USAGE;
        } else if (!in) {
            in = a;
        } else if (!out) {
            out = a;
        } else {
            fprintf(stderr, "wedge convert: more than two images given ('%s')\n", a);
            return WEDGE_EXIT_USAGE;
        }
    }
    if (!in || !out) {
        usage(stderr);
        return WEDGE_EXIT_USAGE;
    }
    Diag err = {0};
    int w = 0, h = 0;
    float *rgb = NULL;
    if (!image_read_linear_rgb(in, &w, &h, &rgb, &err)) {
        diag_print(&err);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_INPUT;
    }
    size_t n = (size_t)w * (size_t)h;
    for (size_t i = 0; i < 3 * n; ++i) /* no NaN or Inf reaches an output */
        if (!(rgb[i] - rgb[i] == 0.0f)) rgb[i] = 0.0f;
    bool ok;
    if (path_is_png(out)) {
        ok = ocio_write_png(out, w, h, rgb, view, &err);
    } else {
        ExrChannel ch[] = {{"R", rgb, 3}, {"G", rgb + 1, 3}, {"B", rgb + 2, 3}};
        ok = exr_write(out, w, h, ch, 3, NULL, 0, &err);
    }
    free(rgb);
    if (!ok) {
        diag_print(&err);
        return err.exit_code ? err.exit_code : WEDGE_EXIT_RUNTIME;
    }
    return WEDGE_EXIT_OK;
}
