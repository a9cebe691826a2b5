/* Terminal progress bar for renders: samples done, rays per second, ETA (stderr). */
#ifndef WEDGE_RENDER_PROGRESS_H
#define WEDGE_RENDER_PROGRESS_H

#include <stdio.h>

#include "render/renderer.h"

typedef struct {
    FILE *out;
    double last_print_s;    /* throttles redraws */
    int printed;            /* a line is on screen (needs a final newline) */
    int done_printed;       /* the 100% line is on screen */
    double last_seen_s;     /* the pass clock at the last update: it restarts with each pass */
    int pass;               /* 0-based pass number shown on the line */
} ProgressBar;

/* RenderProgressFn for RenderOptions.progress (ctx = ProgressBar*). */
void progress_bar_update(void *ctx, const RenderProgress *p);
/* Ends the line. */
void progress_bar_finish(ProgressBar *bar);

#endif
