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

bool preview_display_available(void)
{
    const char *x = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
    return (x && *x) || (wl && *wl);
}

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
    /* Ctrl-C in the terminal arrives as SDL_QUIT: a clean quit, like closing the window */
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                 "cannot open the display (%s): check $DISPLAY, or render without a window: wedge render SCENE "
                 "--time SECONDS --checkpoint 10 -o out.exr",
                 SDL_GetError());
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

PreviewEvent preview_window_wait(PreviewWindow *w, int timeout_ms)
{
    PreviewEvent pe = {PREVIEW_EVENT_NONE, 0, -1, -1};
    SDL_Event ev;
    if (!SDL_WaitEventTimeout(&ev, timeout_ms)) return pe;
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
