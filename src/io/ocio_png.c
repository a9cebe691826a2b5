/* Display-referred PNG output through an OpenColorIO view (issue 4: "PNG output ... goes
 * through it"). */
#include <stdlib.h>
#include <string.h>

#include "io/image_io.h"
#include "io/ocio.h"

bool ocio_write_png(const char *path, int width, int height, const float *rgb_linear, const char *view,
                    Diag *err)
{
    if (width <= 0 || height <= 0 || (long long)width * height > (1LL << 28)) {
        SrcLoc loc = {path, 0, 0};
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot write a %dx%d image", width, height);
        return false;
    }
    OcioView *v = NULL;
    if (!ocio_view_open(view, &v, err)) return false;
    size_t n = (size_t)width * (size_t)height;
    float *display = malloc(n * 3 * sizeof *display);
    if (!display) {
        ocio_view_close(v);
        SrcLoc loc = {path, 0, 0};
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        return false;
    }
    memcpy(display, rgb_linear, n * 3 * sizeof *display);
    ocio_view_apply(v, display, n);
    ocio_view_close(v);
    bool ok = png_write_display(path, width, height, display, err);
    free(display);
    return ok;
}
