/* Two-way parallel for (see recon_parallel.h). */
#include "recon/recon_parallel.h"

#include <pthread.h>
#include <stdbool.h>

/* Below this many items a thread start (tens of microseconds) costs more than it saves. */
#define MIN_PARALLEL_ITEMS 4096

typedef struct {
    ReconRangeFn fn;
    void *ctx;
    size_t begin, end;
    int part;
} ReconJob;

static void *job_main(void *arg)
{
    ReconJob *j = arg;
    j->fn(j->ctx, j->begin, j->end, j->part);
    return NULL;
}

void recon_parallel_for_work(size_t n, size_t work_items, ReconRangeFn fn, void *ctx)
{
    ReconJob jobs[RECON_PARTS];
    for (int p = 0; p < RECON_PARTS; ++p) {
        jobs[p].fn = fn;
        jobs[p].ctx = ctx;
        jobs[p].begin = n * (size_t)p / RECON_PARTS;
        jobs[p].end = n * (size_t)(p + 1) / RECON_PARTS;
        jobs[p].part = p;
    }
    pthread_t threads[RECON_PARTS];
    bool started[RECON_PARTS] = {false};
    if (work_items >= MIN_PARALLEL_ITEMS && n >= RECON_PARTS)
        for (int p = 1; p < RECON_PARTS; ++p) started[p] = pthread_create(&threads[p], NULL, job_main, &jobs[p]) == 0;
    job_main(&jobs[0]);
    for (int p = 1; p < RECON_PARTS; ++p) {
        if (started[p]) pthread_join(threads[p], NULL);
        else job_main(&jobs[p]);
    }
}

void recon_parallel_for(size_t n, ReconRangeFn fn, void *ctx) { recon_parallel_for_work(n, n, fn, ctx); }
