/* The ClRuntime structure, for the recon module's own host code only (it needs the OpenCL
 * headers; everything outside src/recon uses the opaque cl_runtime.h). */
#ifndef WEDGE_RECON_CL_RUNTIME_INTERNAL_H
#define WEDGE_RECON_CL_RUNTIME_INTERNAL_H

#ifndef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 120
#endif
#include <CL/cl.h>

#include "recon/cl/cl_runtime.h"

/* One program: the sources it is built from and, once built, the program. */
typedef struct {
    const char *name; /* the embedded file's ("lr.cl"), for logs and tests */
    const char *const *sources;
    int source_count;
    cl_program program; /* NULL until a kernel of it is first asked for */
} ClProgramSlot;

enum { CL_RUNTIME_MAX_PROGRAMS = 16 };

struct ClRuntime {
    cl_platform_id platform;
    cl_device_id device;
    cl_context context;
    cl_command_queue queue; /* in-order, with profiling enabled (kernel timings) */
    ClProgramSlot programs[CL_RUNTIME_MAX_PROGRAMS];
    int program_count;
    int last_slot;      /* the slot of the last kernel found: looked at first */
    int programs_built; /* programs built (from source or the cached binary) so far */
    char label[600];
};

/* Human-readable name of an OpenCL error code ("CL_OUT_OF_RESOURCES"). */
const char *cl_error_name(cl_int err);

/* Creates the named kernel from the program of the source that declares it, building that
 * program first if no kernel of it was asked for before (each embedded source is its own
 * program: a frame pays the driver's parse of its methods' kernels only). NULL + Diag when
 * no source declares the kernel, its program does not build, or the driver refuses it. Not
 * thread-safe: a runtime's kernels are asked for on one thread (the pipeline's opener). */
cl_kernel cl_runtime_kernel(ClRuntime *rt, const char *name, Diag *d);

/* The number of programs built so far (tests: a frame builds its methods' programs and no
 * other). With $WEDGE_CL_LOG=1 each build also says on stderr which source it built, from
 * the cached binary or from source, and its time. */
int cl_runtime_programs_built(const ClRuntime *rt);

/* Launches a 2D kernel over at least gx x gy work items, in work groups of one fixed size
 * (CL_LAUNCH_LOCAL_X x CL_LAUNCH_LOCAL_Y, smaller if the kernel allows fewer): the global size
 * is rounded up to whole groups, so kernels must return for ids past their image. Left to
 * choose, PoCL picks a local size that divides the global size and compiles the kernel anew
 * for each one it has not seen: 0.5-0.65 s at every new image size (131x97, 133x99, 137x101)
 * against 0.02 s for a size seen before. A fixed local size is compiled once. */
enum { CL_LAUNCH_LOCAL_X = 16, CL_LAUNCH_LOCAL_Y = 4 };
bool cl_launch_2d(ClRuntime *rt, cl_kernel k, size_t gx, size_t gy, cl_event *ev, Diag *d);

/* Launches a 2D kernel over exactly gx x gy work items in work groups of one item, for kernels
 * whose items each run a long serial loop with private arrays. PoCL runs a group's items one
 * after the other in a loop it wraps around the kernel, and with several items a group it keeps
 * each item's private arrays in that item's slot of a per-group array, addressed afresh at every
 * access; with one item a group they stay in one place in the caches (docs/benchmarks.md, "LR's
 * reconstruction cost, sixth round" and MAAF's second cost round: the same arithmetic, faster). */
bool cl_launch_serial_2d(ClRuntime *rt, cl_kernel k, size_t gx, size_t gy, cl_event *ev, Diag *d);

/* A finished command's device time in seconds (the queue profiles); 0 for NULL, an event
 * without profiling data, or an end before its start. */
double cl_event_seconds(cl_event ev);

#endif
