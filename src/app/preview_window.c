/* The preview's window on SDL2 (see preview_window.h); empty in a build without SDL2.
 *
 * SDL2 is opened at run time (dlopen), when the preview asks for it, not linked: linked, it
 * and what it brings (PulseAudio, X11, Wayland, ...) were mapped and initialised by every
 * wedge process (with MPI's, 53 of the 72 shared objects, ~7 ms of CPU before any work:
 * docs/benchmarks.md, "A process pays only for the libraries it uses"). Its header still
 * gives every type, constant and prototype; the functions come through the table below. */
#ifdef WEDGE_SDL
#include "app/preview_window.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

#include <SDL2/SDL.h>

#ifndef WEDGE_SDL_SONAME
#define WEDGE_SDL_SONAME "libSDL2-2.0.so.0" /* SDL 2's soname since 2.0.0 */
#endif

/* The SDL functions the window uses: (field, SDL name). */
#define PREVIEW_SDL_FUNCTIONS(X) \
    X(set_hint, SDL_SetHint) \
    X(init, SDL_Init) \
    X(quit, SDL_Quit) \
    X(get_error, SDL_GetError) \
    X(create_window, SDL_CreateWindow) \
    X(destroy_window, SDL_DestroyWindow) \
    X(set_window_title, SDL_SetWindowTitle) \
    X(create_renderer, SDL_CreateRenderer) \
    X(destroy_renderer, SDL_DestroyRenderer) \
    X(render_set_logical_size, SDL_RenderSetLogicalSize) \
    X(render_window_to_logical, SDL_RenderWindowToLogical) \
    X(render_clear, SDL_RenderClear) \
    X(render_copy, SDL_RenderCopy) \
    X(render_present, SDL_RenderPresent) \
    X(create_texture, SDL_CreateTexture) \
    X(destroy_texture, SDL_DestroyTexture) \
    X(update_texture, SDL_UpdateTexture) \
    X(poll_event, SDL_PollEvent) \
    X(delay, SDL_Delay)

/* Each a pointer of its function's own type (from SDL's prototype), so a call is checked as a
 * direct call would be. */
#define PREVIEW_SDL_FIELD(field, name) __typeof__(name) *field;
static struct {
    PREVIEW_SDL_FUNCTIONS(PREVIEW_SDL_FIELD)
} sdl;
#undef PREVIEW_SDL_FIELD

/* The outcome of the one load per process (pthread_once): ok, or why not. */
static bool sdl_loaded;
static char sdl_load_error[512];

static void sdl_load_once(void)
{
    /* WEDGE_SDL_LIBRARY (tests): the file to open instead of SDL's soname */
    const char *name = getenv("WEDGE_SDL_LIBRARY");
    if (!name || !*name) name = WEDGE_SDL_SONAME;
    /* local: nothing else binds to SDL's symbols; never closed (its threads and atexit state) */
    void *lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        const char *why = dlerror();
        snprintf(sdl_load_error, sizeof sdl_load_error, "%s", why ? why : name);
        return;
    }
    const char *missing = NULL;
#define PREVIEW_SDL_LOAD(field, fn) \
    if (!(sdl.field = (__typeof__(fn) *)dlsym(lib, #fn)) && !missing) missing = #fn;
    PREVIEW_SDL_FUNCTIONS(PREVIEW_SDL_LOAD)
#undef PREVIEW_SDL_LOAD
    if (missing) {
        snprintf(sdl_load_error, sizeof sdl_load_error, "%s has no %s (SDL older than 2.0.18?)", name, missing);
        return;
    }
    sdl_loaded = true;
}

bool preview_window_library_load(Diag *d)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, sdl_load_once);
    if (sdl_loaded) return true;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
             "cannot load SDL2, which wedge preview needs for its window (%s): install it (Debian and Ubuntu: "
             "apt-get install libsdl2-2.0-0; tools/setup does), or render without a window: wedge render SCENE "
             "--time SECONDS --checkpoint 10 -o out.exr",
             sdl_load_error);
    return false;
}

struct PreviewWindow {
    SDL_Window *window;
    SDL_Renderer *renderer;
    SDL_Texture *texture;
    int width, height;
};

static bool env_set(const char *name)
{
    const char *v = getenv(name);
    return v && *v;
}

bool preview_display_available(void) { return env_set("DISPLAY") || env_set("WAYLAND_DISPLAY"); }

bool preview_window_open(int width, int height, const char *title, PreviewWindow **out, Diag *d)
{
    *out = NULL;
    if (!preview_display_available()) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                 "no display ($DISPLAY and $WAYLAND_DISPLAY are unset): run wedge preview in a desktop session, or "
                 "render without a window and look at the image as it improves: wedge render SCENE --time SECONDS "
                 "--checkpoint 10 -o out.exr");
        return false;
    }
    if (!preview_window_library_load(d)) return false;
    /* Plain 2D blits, no OpenGL anywhere: left to itself SDL accelerates the window's
     * framebuffer with a GL context, which on a machine without a GPU loads Mesa's LLVM
     * rasteriser (slow to start, and its JIT deadlocks AddressSanitizer's unwinder). */
    sdl.set_hint(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0");
    sdl.set_hint(SDL_HINT_RENDER_DRIVER, "software");
    /* Only drivers that show a window: when the display cannot be reached, SDL would
     * otherwise fall back to its offscreen driver and the preview would render into a
     * window nobody can see, forever. ($SDL_VIDEODRIVER still overrides this.) */
    bool x11 = env_set("DISPLAY"), wayland = env_set("WAYLAND_DISPLAY");
    sdl.set_hint(SDL_HINT_VIDEODRIVER, x11 && wayland ? "x11,wayland" : x11 ? "x11" : "wayland");
    /* Ctrl-C in the terminal arrives as SDL_QUIT: a clean quit, like closing the window */
    if (sdl.init(SDL_INIT_VIDEO) != 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                 "cannot open the display %s (%s): check that its server is running and $DISPLAY or "
                 "$WAYLAND_DISPLAY names it, or render without a window: wedge render SCENE --time SECONDS "
                 "--checkpoint 10 -o out.exr",
                 x11 ? getenv("DISPLAY") : getenv("WAYLAND_DISPLAY"), sdl.get_error());
        return false;
    }
    PreviewWindow *w = calloc(1, sizeof *w);
    if (!w) {
        sdl.quit();
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return false;
    }
    w->width = width;
    w->height = height;
    w->window = sdl.create_window(title, SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, width, height,
                                  SDL_WINDOW_RESIZABLE);
    /* the software renderer: no GPU driver needed, and the image is small next to rendering */
    if (w->window) w->renderer = sdl.create_renderer(w->window, -1, SDL_RENDERER_SOFTWARE);
    if (w->renderer) {
        sdl.render_set_logical_size(w->renderer, width, height);
        w->texture = sdl.create_texture(w->renderer, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, width, height);
    }
    if (!w->texture) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot create the preview window: %s", sdl.get_error());
        preview_window_close(w);
        return false;
    }
    *out = w;
    return true;
}

void preview_window_close(PreviewWindow *w)
{
    if (!w) return;
    if (w->texture) sdl.destroy_texture(w->texture);
    if (w->renderer) sdl.destroy_renderer(w->renderer);
    if (w->window) sdl.destroy_window(w->window);
    free(w);
    sdl.quit();
}

bool preview_window_show(PreviewWindow *w, const uint8_t *rgb8, Diag *d)
{
    if (sdl.update_texture(w->texture, NULL, rgb8, 3 * w->width) != 0 || sdl.render_clear(w->renderer) != 0 ||
        sdl.render_copy(w->renderer, w->texture, NULL, NULL) != 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot draw the preview: %s", sdl.get_error());
        return false;
    }
    sdl.render_present(w->renderer);
    return true;
}

void preview_window_set_title(PreviewWindow *w, const char *title) { sdl.set_window_title(w->window, title); }

/* Polls in short naps rather than SDL_WaitEventTimeout: while a thread waits there, SDL's
 * X11 driver records the window to wake, and an event pushed later (while the window is
 * being destroyed) is sent to it from a second connection; the BadWindow error that follows
 * reaches Xlib's default handler, which exits the process with status 1 after a clean quit. */
PreviewEvent preview_window_wait(PreviewWindow *w, int timeout_ms)
{
    enum { NAP_MS = 5 };
    PreviewEvent pe = {PREVIEW_EVENT_NONE, 0, -1, -1};
    SDL_Event ev;
    int waited_ms = 0;
    while (!sdl.poll_event(&ev)) {
        if (waited_ms >= timeout_ms) return pe;
        sdl.delay(NAP_MS);
        waited_ms += NAP_MS;
    }
    switch (ev.type) {
    case SDL_QUIT: pe.kind = PREVIEW_EVENT_QUIT; break;
    case SDL_WINDOWEVENT:
        if (ev.window.event == SDL_WINDOWEVENT_CLOSE) pe.kind = PREVIEW_EVENT_QUIT;
        break;
    case SDL_TEXTINPUT: /* typed characters, keyboard layout applied ('+' included) */
        pe.kind = PREVIEW_EVENT_KEY;
        pe.key = (unsigned char)ev.text.text[0];
        break;
    case SDL_KEYDOWN:
        if (ev.key.keysym.sym == SDLK_ESCAPE) pe.kind = PREVIEW_EVENT_KEY, pe.key = 27;
        if (ev.key.keysym.sym == SDLK_KP_PLUS) pe.kind = PREVIEW_EVENT_KEY, pe.key = '+';
        if (ev.key.keysym.sym == SDLK_KP_MINUS) pe.kind = PREVIEW_EVENT_KEY, pe.key = '-';
        break;
    case SDL_MOUSEMOTION: {
        /* window coordinates to image pixels through the logical size */
        float lx = 0.0f, ly = 0.0f;
        sdl.render_window_to_logical(w->renderer, ev.motion.x, ev.motion.y, &lx, &ly);
        int x = (int)lx, y = (int)ly;
        bool inside = x >= 0 && y >= 0 && x < w->width && y < w->height;
        pe.kind = PREVIEW_EVENT_MOUSE;
        pe.x = inside ? x : -1;
        pe.y = inside ? y : -1;
        break;
    }
    default: break;
    }
    return pe;
}
#else
typedef int wedge_preview_window_needs_sdl2;
#endif
