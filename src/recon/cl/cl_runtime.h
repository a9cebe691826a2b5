/* The OpenCL side of the reconstruction stage: choosing a device, creating a context and
 * queue, and building the kernels embedded in the binary (the .cl files under src/recon).
 *
 * The OpenCL types stay hidden behind ClRuntime so that code including this header needs no
 * OpenCL headers (and no CL_TARGET_OPENCL_VERSION). Only the recon module sees the CL API. */
#ifndef WEDGE_RECON_CL_RUNTIME_H
#define WEDGE_RECON_CL_RUNTIME_H

#include <stdbool.h>
#include <stdio.h>

#include "core/diag.h"

typedef struct ClRuntime ClRuntime;

/* The Debian package that provides a CPU OpenCL driver; named in the "no platform" error. */
#define WEDGE_CL_PACKAGE_HINT "pocl-opencl-icd"

/* Environment variable consulted when no explicit device is given. */
#define WEDGE_CL_DEVICE_ENV "WEDGE_CL_DEVICE"

/* Opens a device (context and queue). Each embedded kernel source (one .cl file, one
 * method's kernels) becomes its own program, built on the first request for one of its
 * kernels (the pipeline's opener thread asks for its methods' kernels while pass 1 traces):
 * the driver then parses only the kernels the frame uses.
 * device_choice: NULL or "" -> $WEDGE_CL_DEVICE if set, else the first GPU, else the first
 * CPU (else the first device of any type). A decimal number N selects the N-th device in the
 * order recon_print_devices lists them (0-based, across all platforms); anything else is
 * matched case-insensitively as a substring of the device name, then of the platform name.
 * On failure returns NULL and fills d (exit code WEDGE_EXIT_RUNTIME, or WEDGE_EXIT_USAGE for a
 * device choice that matches nothing). A program that does not build is reported, with the
 * driver's build log, by the kernel lookup that builds it (cl_runtime_internal.h). */
ClRuntime *cl_runtime_create(const char *device_choice, Diag *d);

/* Same, but builds the given sources, now, into one program instead of the embedded ones
 * (tests, tools): a build failure is reported here. */
ClRuntime *cl_runtime_create_with_sources(const char *device_choice, const char *const *sources,
                                          int source_count, Diag *d);

/* Whether cl_runtime_create(device_choice) would find its device (same errors), without
 * creating anything: a few milliseconds once the driver is loaded, so a filter can fail
 * before it renders rather than after. */
bool cl_runtime_check_device(const char *device_choice, Diag *d);

void cl_runtime_destroy(ClRuntime *rt);

/* "DEVICE NAME (PLATFORM NAME)", for reports and logs. */
const char *cl_runtime_device_label(const ClRuntime *rt);

/* Lists platforms and devices with the index that --cl-device N accepts (wedge info --cl).
 * Returns false (after printing the reason) when no OpenCL platform is available. */
bool recon_print_devices(FILE *out);

#endif
