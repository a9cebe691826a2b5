/* Which OpenCL source declares a kernel: the runtime builds one program per embedded source
 * (cl_runtime.h) and, asked for a kernel by name, builds only the source that declares it.
 * The sources are ours and declare kernels one way, "__kernel void NAME(" (any white space
 * between the words, "kernel" also accepted), which is what this recognises; a test checks
 * it against the kernel names the compiler reports for every embedded source. */
#ifndef WEDGE_RECON_CL_KERNEL_DECL_H
#define WEDGE_RECON_CL_KERNEL_DECL_H

#include <stdbool.h>

/* Whether source declares a kernel called name (an occurrence of name inside a longer
 * identifier, a call or a comment that does not read "kernel void name(" does not count). */
bool kernel_declared(const char *source, const char *name);

#endif
