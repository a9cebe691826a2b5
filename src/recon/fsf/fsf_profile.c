/* FSF's stage timings (fsf_profile.h). */
#include "recon/fsf/fsf_profile.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "core/clock.h"

static void now(double *wall_ms, double *cpu_ms, double *sys_ms, long *faults)
{
    *wall_ms = 1e3 * clock_wall_seconds();
    *cpu_ms = 1e3 * clock_cpu_seconds();
    struct rusage use;
    getrusage(RUSAGE_SELF, &use);
    *faults = use.ru_minflt;
    *sys_ms = 1e3 * (double)use.ru_stime.tv_sec + 1e-3 * (double)use.ru_stime.tv_usec;
}

void fsf_profile_begin(FsfProfile *p)
{
    const char *env = getenv("WEDGE_FSF_PROFILE");
    p->on = env && strcmp(env, "0") != 0;
    p->count = 0;
    if (p->on) now(&p->t_wall, &p->t_cpu, &p->t_sys, &p->t_faults);
}

void fsf_profile_mark(FsfProfile *p, const char *stage)
{
    if (!p->on || p->count >= FSF_PROFILE_STAGES) return;
    double w, c, sy;
    long f;
    now(&w, &c, &sy, &f);
    p->name[p->count] = stage;
    p->wall_ms[p->count] = w - p->t_wall, p->cpu_ms[p->count] = c - p->t_cpu, p->sys_ms[p->count] = sy - p->t_sys;
    p->faults[p->count] = f - p->t_faults;
    p->count++;
    p->t_wall = w, p->t_cpu = c, p->t_sys = sy, p->t_faults = f;
}

void fsf_profile_add(FsfProfile *p, const char *stage, double seconds)
{
    if (!p->on || p->count >= FSF_PROFILE_STAGES) return;
    p->name[p->count] = stage;
    p->wall_ms[p->count] = 1e3 * seconds, p->cpu_ms[p->count] = p->sys_ms[p->count] = 0.0, p->faults[p->count] = 0;
    p->count++;
}

int fsf_profile_repeats(const FsfProfile *p)
{
    const char *env = getenv("WEDGE_FSF_PROFILE_REPEAT");
    int n = p->on && env ? atoi(env) : 0;
    return n > 0 ? n : 0;
}

void fsf_profile_print(FsfProfile *p, const char *label)
{
    if (!p->on) return;
    char line[64 * FSF_PROFILE_STAGES];
    int at = snprintf(line, sizeof line, "fsf-profile %s:", label);
    for (int k = 0; k < p->count && at > 0 && (size_t)at < sizeof line; ++k)
        at += snprintf(line + at, sizeof line - (size_t)at, " %s %.2f %.2f %.2f %ld", p->name[k], p->wall_ms[k],
                       p->cpu_ms[k], p->sys_ms[k], p->faults[k]);
    fprintf(stderr, "%s\n", line);
    p->count = 0;
}
