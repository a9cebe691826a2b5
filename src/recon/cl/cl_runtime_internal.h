/* The ClRuntime structure, for the recon module's own host code only (it needs the OpenCL
 * headers; everything outside src/recon uses the opaque cl_runtime.h). */
#ifndef WEDGE_RECON_CL_RUNTIME_INTERNAL_H
#define WEDGE_RECON_CL_RUNTIME_INTERNAL_H

#ifndef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 120
#endif
#include <CL/cl.h>

#include "recon/cl/cl_runtime.h"

struct ClRuntime {
    cl_platform_id platform;
    cl_device_id device;
    cl_context context;
    cl_command_queue queue; /* in-order, with profiling enabled (kernel timings) */
    cl_program program;
    char label[600];
};

/* Human-readable name of an OpenCL error code ("CL_OUT_OF_RESOURCES"). */
const char *cl_error_name(cl_int err);

/* Creates the named kernel from rt->program; NULL + Diag on failure. */
cl_kernel cl_runtime_kernel(ClRuntime *rt, const char *name, Diag *d);

#endif
