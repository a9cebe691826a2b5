/* The two clocks wedge times itself with: elapsed (wall) seconds for what a user waits, and the
 * process's CPU seconds (every thread, the OpenCL driver's included) for comparisons that other
 * jobs on a shared machine would otherwise blur. */
#ifndef WEDGE_CORE_CLOCK_H
#define WEDGE_CORE_CLOCK_H

#include <time.h>

static inline double timespec_seconds(struct timespec t) { return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec; }

/* Seconds on a monotonic clock (the origin is arbitrary: take differences). */
static inline double clock_wall_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return timespec_seconds(t);
}

/* CPU seconds this process has used so far, user and system, all threads. */
static inline double clock_cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return timespec_seconds(t);
}

#endif
