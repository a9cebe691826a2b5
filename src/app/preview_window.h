/* The preview's window (SDL2): shows an 8-bit RGB image 1:1 (the window can be resized; the
 * image scales with it), sets the title, and reports key presses, mouse position and the
 * window's closing as simple events. Everything SDL stays in preview_window.c, which opens
 * the SDL2 library at run time (the first preview_window_library_load), so that a process
 * that shows no window never maps it. */
#ifndef WEDGE_APP_PREVIEW_WINDOW_H
#define WEDGE_APP_PREVIEW_WINDOW_H

#include <stdbool.h>
#include <stdint.h>

#include "core/diag.h"

typedef struct PreviewWindow PreviewWindow;

typedef enum {
    PREVIEW_EVENT_NONE,  /* nothing happened within the wait */
    PREVIEW_EVENT_KEY,   /* key: the character typed ('f', 's', '+', ' ', ...) or 27 for Esc */
    PREVIEW_EVENT_MOUSE, /* x, y: the image pixel under the pointer (-1 when outside) */
    PREVIEW_EVENT_QUIT,  /* the window was closed (window manager, Ctrl-C in the terminal) */
} PreviewEventKind;

typedef struct {
    PreviewEventKind kind;
    int key;
    int x, y;
} PreviewEvent;

/* Whether a display is reachable at all ($DISPLAY or $WAYLAND_DISPLAY set), checked before
 * anything is rendered. */
bool preview_display_available(void);

/* Loads SDL2 (once per process; later calls return the first call's outcome). False with d
 * set (exit 3) when the library cannot be opened, the message saying what to install. The
 * soname is the one the build found; $WEDGE_SDL_LIBRARY names another file (tests). */
bool preview_window_library_load(Diag *d);

/* Opens a window for a width x height image (loading SDL2 first). No display, or SDL
 * failing: false with d set (exit 3), the message saying what to do instead. */
bool preview_window_open(int width, int height, const char *title, PreviewWindow **out, Diag *d);
void preview_window_close(PreviewWindow *w);

/* Shows rgb8 (3 bytes per pixel, width x height, top row first). */
bool preview_window_show(PreviewWindow *w, const uint8_t *rgb8, Diag *d);
void preview_window_set_title(PreviewWindow *w, const char *title);

/* Waits up to timeout_ms for one event (returns PREVIEW_EVENT_NONE when none came). */
PreviewEvent preview_window_wait(PreviewWindow *w, int timeout_ms);

#endif
