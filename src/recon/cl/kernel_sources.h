/* OpenCL kernel sources embedded at build time (tools/embed-kernels.cmake). */
#ifndef WEDGE_RECON_KERNEL_SOURCES_H
#define WEDGE_RECON_KERNEL_SOURCES_H

typedef struct {
    const char *name;   /* file name, e.g. "aaf.cl" */
    const char *source; /* NUL-terminated OpenCL C */
} WedgeKernelSource;

/* Terminated by an entry with name == NULL. */
extern const WedgeKernelSource wedge_kernel_sources[];

#endif
