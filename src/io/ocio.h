/* OpenColorIO bridge: scene-linear rgb to display-referred rgb through a named view.
 *
 * The config is $OCIO when that variable is set and non-empty, otherwise the small config
 * compiled into wedge (src/io/ocio/wedge_config.ocio.inc: display "sRGB" with views
 * "Standard" (plain sRGB encoding), "Filmic" (film-like tone curve) and "Raw"). The
 * source colour space is the config's scene_linear role; the display is the config's
 * default display. The C++ lives in ocio_shim.cpp; no exception crosses this header. */
#ifndef WEDGE_IO_OCIO_H
#define WEDGE_IO_OCIO_H

#include <stdbool.h>
#include <stddef.h>

#include "core/diag.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct OcioView OcioView;

/* Loads the config and builds the processor for view (NULL or "" means the display's
 * default view, "Standard" in the embedded config). An unknown view fails with
 *   error: unknown view 'NAME' (display 'sRGB' has views: Standard, Filmic, Raw)
 * and exit code 1 (it comes from the command line, --view); an unreadable or invalid
 * $OCIO config fails with exit code 2 naming the file. */
bool ocio_view_open(const char *view, OcioView **out, Diag *err);
/* Transforms pixel_count interleaved rgb triples in place. Non-finite inputs are set to 0
 * first and any non-finite output to 0, so no NaN/Inf leaves; values are not clamped
 * (png_write_display clamps). Thread-safe on one OcioView. */
void ocio_view_apply(const OcioView *v, float *rgb, size_t pixel_count);
/* The names in use: view, display, and where the config came from ("built-in" or the
 * $OCIO path). Valid until ocio_view_close. */
const char *ocio_view_name(const OcioView *v);
const char *ocio_view_display(const OcioView *v);
const char *ocio_view_config_source(const OcioView *v);
void ocio_view_close(OcioView *v);

/* Writes the views of the active config's default display, ", "-separated, into buf
 * (e.g. "Standard, Filmic, Raw" for the built-in config). */
bool ocio_list_views(char *buf, size_t size, Diag *err);

/* The text of the built-in config (what wedge uses when $OCIO is unset). */
const char *ocio_embedded_config(void);

/* Convenience for display-referred output: linear rgb -> view -> 8-bit PNG (atomic write,
 * see io/image_io.h). err exit 1 for an unknown view, 2 for a bad $OCIO, 3 for I/O. */
bool ocio_write_png(const char *path, int width, int height, const float *rgb_linear, const char *view,
                    Diag *err);

#ifdef __cplusplus
}
#endif

#endif
