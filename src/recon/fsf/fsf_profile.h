/* WEDGE_FSF_PROFILE=1: where an FSF frame's filter time goes. Each stage of the plan and the
 * filters (host work, the OpenCL run, each kernel's device time) is printed to stderr as one
 * line per filtering: wall milliseconds, the process's CPU milliseconds (PoCL's threads
 * included), the system part of them, and its minor page faults (first touches of fresh
 * memory) during the stage. A
 * measuring aid (docs/benchmarks.md, "FSF's filter cost, sixth round"); without the variable
 * every call returns at once. */
#ifndef WEDGE_RECON_FSF_PROFILE_H
#define WEDGE_RECON_FSF_PROFILE_H

#include <stdbool.h>

enum { FSF_PROFILE_STAGES = 24 };

typedef struct {
    bool on;
    int count;
    const char *name[FSF_PROFILE_STAGES];
    double wall_ms[FSF_PROFILE_STAGES], cpu_ms[FSF_PROFILE_STAGES], sys_ms[FSF_PROFILE_STAGES];
    long faults[FSF_PROFILE_STAGES];
    double t_wall, t_cpu, t_sys; /* the last mark's */
    long t_faults;
} FsfProfile;

/* Starts a line (on when WEDGE_FSF_PROFILE is set and not "0"). */
void fsf_profile_begin(FsfProfile *p);
/* Ends the stage that began at the last mark (or fsf_profile_begin), naming it. */
void fsf_profile_mark(FsfProfile *p, const char *stage);
/* A time measured elsewhere (a kernel's device seconds), as a stage without CPU or faults. */
void fsf_profile_add(FsfProfile *p, const char *stage, double seconds);
/* WEDGE_FSF_PROFILE_REPEAT=N with the profile on: the OpenCL passes (and the indirect light's
 * two passes, on the device or in C) are run N more times on the same inputs (their result is the same each time), for warm kernel times and profiles with more
 * samples (the "cl_run" stage then holds all N + 1 runs, the kernel times the last's); else 0. */
int fsf_profile_repeats(const FsfProfile *p);
/* Prints "fsf-profile LABEL: stage wall cpu sys faults ..." and ends the line. */
void fsf_profile_print(FsfProfile *p, const char *label);

#endif
