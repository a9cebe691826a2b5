/* The preview's window on SDL2 (see preview_window.h); empty in a build without SDL2. */
#ifdef WEDGE_SDL
#include "app/preview_window.h"

#include <stdlib.h>

#include <SDL2/SDL.h>

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
    /* Plain 2D blits, no OpenGL anywhere: left to itself SDL accelerates the window's
     * framebuffer with a GL context, which on a machine without a GPU loads Mesa's LLVM
     * rasteriser (slow to start, and its JIT deadlocks AddressSanitizer's unwinder). */
    SDL_SetHint(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0");
    SDL_SetHint(SDL_HINT_RENDER_DRIVER, "software");
    /* Only drivers that show a window: when the display cannot be reached, SDL would
     * otherwise fall back to its offscreen driver and the preview would render into a
     * window nobody can see, forever. ($SDL_VIDEODRIVER still overrides this.) */
    bool x11 = env_set("DISPLAY"), wayland = env_set("WAYLAND_DISPLAY");
    SDL_SetHint(SDL_HINT_VIDEODRIVER, x11 && wayland ? "x11,wayland" : x11 ? "x11" : "wayland");
    /* Ctrl-C in the terminal arrives as SDL_QUIT: a clean quit, like closing the window */
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                 "cannot open the display %s (%s): check that its server is running and $DISPLAY or "
                 "$WAYLAND_DISPLAY names it, or render without a window: wedge render SCENE --time SECONDS "
                 "--checkpoint 10 -o out.exr",
                 x11 ? getenv("DISPLAY") : getenv("WAYLAND_DISPLAY"), SDL_GetError());
        return false;
    }
    PreviewWindow *w = calloc(1, sizeof *w);
    if (!w) {
        SDL_Quit();
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory");
        return false;
    }
    w->width = width;
    w->height = height;
    w->window = SDL_CreateWindow(title, SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, width, height,
                                 SDL_WINDOW_RESIZABLE);
    /* the software renderer: no GPU driver needed, and the image is small next to rendering */
    if (w->window) w->renderer = SDL_CreateRenderer(w->window, -1, SDL_RENDERER_SOFTWARE);
    if (w->renderer) {
        SDL_RenderSetLogicalSize(w->renderer, width, height);
        w->texture = SDL_CreateTexture(w->renderer, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, width, height);
    }
    if (!w->texture) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot create the preview window: %s", SDL_GetError());
        preview_window_close(w);
        return false;
    }
    *out = w;
    return true;
}

void preview_window_close(PreviewWindow *w)
{
    if (!w) return;
    if (w->texture) SDL_DestroyTexture(w->texture);
    if (w->renderer) SDL_DestroyRenderer(w->renderer);
    if (w->window) SDL_DestroyWindow(w->window);
    free(w);
    SDL_Quit();
}

bool preview_window_show(PreviewWindow *w, const uint8_t *rgb8, Diag *d)
{
    if (SDL_UpdateTexture(w->texture, NULL, rgb8, 3 * w->width) != 0 || SDL_RenderClear(w->renderer) != 0 ||
        SDL_RenderCopy(w->renderer, w->texture, NULL, NULL) != 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "cannot draw the preview: %s", SDL_GetError());
        return false;
    }
    SDL_RenderPresent(w->renderer);
    return true;
}

void preview_window_set_title(PreviewWindow *w, const char *title) { SDL_SetWindowTitle(w->window, title); }

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
    while (!SDL_PollEvent(&ev)) {
        if (waited_ms >= timeout_ms) return pe;
        SDL_Delay(NAP_MS);
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
        SDL_RenderWindowToLogical(w->renderer, ev.motion.x, ev.motion.y, &lx, &ly);
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
