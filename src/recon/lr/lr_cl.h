/* Host side of LR's OpenCL kernels (lr.cl): partitions on the host (lr_partition.c), then
 * reprojection, the two screen-filter passes and compositing on the device. Same output as
 * lr_reconstruct_c (tested). */
#ifndef WEDGE_RECON_LR_CL_H
#define WEDGE_RECON_LR_CL_H

#include "core/diag.h"
#include "recon/cl/cl_runtime.h"
#include "recon/lr/lr_reconstruct.h"

typedef struct LrCl LrCl;

LrCl *lr_cl_create(ClRuntime *rt, Diag *d);
void lr_cl_destroy(LrCl *lr);

/* Reconstructs img into out (rgb required, AOVs optional; non-finite sample radiances are
 * skipped and counted in out->nonfinite). kernel_seconds (may be NULL) receives the device
 * time of the three kernels (OpenCL profiling). */
bool lr_cl_run(LrCl *lr, const LrSamples *img, const LrConfig *cfg, LrOutput *out, double *kernel_seconds, Diag *d);

#endif
