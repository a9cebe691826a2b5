/* A one-line progress bar redrawn with '\r'. */
#include "render/progress.h"

#include <stdbool.h>

static void human(double v, char *buf, size_t n)
{
    if (v >= 1e9)
        snprintf(buf, n, "%.2fG", v / 1e9);
    else if (v >= 1e6)
        snprintf(buf, n, "%.2fM", v / 1e6);
    else if (v >= 1e3)
        snprintf(buf, n, "%.1fk", v / 1e3);
    else
        snprintf(buf, n, "%.0f", v);
}

void progress_bar_update(void *ctx, const RenderProgress *p)
{
    ProgressBar *bar = ctx;
    /* A renderer's clock restarts with every pass (a filter's adaptive second pass, say):
     * keep the finished pass's line and start a new one. */
    if (bar->printed && p->seconds < bar->last_seen_s) {
        fputc('\n', bar->out);
        bar->printed = 0;
        bar->done_printed = 0;
        bar->last_print_s = 0.0;
        ++bar->pass;
    }
    bar->last_seen_s = p->seconds;
    bool done = p->samples_done >= p->samples_total;
    if (done && bar->done_printed) return;
    if (!done && bar->printed && p->seconds - bar->last_print_s < 0.1) return;
    bar->done_printed = done;
    bar->last_print_s = p->seconds;
    double frac = p->samples_total > 0 ? (double)p->samples_done / (double)p->samples_total : 1.0;
    enum { WIDTH = 30 };
    char bar_txt[WIDTH + 1];
    int filled = (int)(frac * WIDTH + 0.5);
    for (int i = 0; i < WIDTH; ++i) bar_txt[i] = i < filled ? '#' : '-';
    bar_txt[WIDTH] = 0;
    char done_s[32], total_s[32], rate_s[32];
    human((double)p->samples_done, done_s, sizeof done_s);
    human((double)p->samples_total, total_s, sizeof total_s);
    double rate = p->seconds > 0.0 ? (double)p->rays_done / p->seconds : 0.0;
    human(rate, rate_s, sizeof rate_s);
    double eta = (frac > 0.0 && frac < 1.0) ? p->seconds * (1.0 - frac) / frac : 0.0;
    fprintf(bar->out, "\rpass %d [%s] %3.0f%%  %s/%s samples  %s rays/s  ETA %5.1fs ", bar->pass + 1, bar_txt, 100.0 * frac, done_s, total_s,
            rate_s, eta);
    fflush(bar->out);
    bar->printed = 1;
}

void progress_bar_finish(ProgressBar *bar)
{
    if (bar->printed) fputc('\n', bar->out);
    bar->printed = 0;
    bar->done_printed = 0;
}
