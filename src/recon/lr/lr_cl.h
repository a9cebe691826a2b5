/* Host side of LR's OpenCL kernels (lr.cl): partition statistics on the device, the
 * partitions' filters on the host (lr_partition.c), then the samples' layers, reprojection, the two screen-filter passes and compositing on the device. Same output as
 * lr_reconstruct_c (tested). */
#ifndef WEDGE_RECON_LR_CL_H
#define WEDGE_RECON_LR_CL_H

#include <stddef.h>

#include "core/diag.h"
#include "recon/cl/cl_runtime.h"
#include "recon/lr/lr_reconstruct.h"

typedef struct LrCl LrCl;

/* Where the last lr_cl_run spent its time (for benchmarks): the partitions (wall seconds:
 * statistics on the device, filters on the host) and the device time of the kernels
 * tile_stats, reproject, along, across (one kernel, lr_tile_filter, runs a tile's
 * reprojection and both passes, so their time is counted in kernel_s[1] and kernel_s[2] and
 * kernel_s[3] are 0). */
typedef struct {
    double partition_s;
    double kernel_s[4];
    size_t partitions;
    int max_layers;
} LrClTimes;

LrCl *lr_cl_create(ClRuntime *rt, Diag *d);
void lr_cl_destroy(LrCl *lr);

/* Reconstructs img into out (rgb required, AOVs optional; non-finite sample radiances are
 * skipped and counted in out->nonfinite). kernel_seconds (may be NULL) receives the device
 * time of the four kernels (OpenCL profiling). The samples are read in place during the call. */
LrClTimes lr_cl_last_times(const LrCl *lr);

bool lr_cl_run(LrCl *lr, const LrSamples *img, const LrConfig *cfg, LrOutput *out, double *kernel_seconds, Diag *d);

#endif
