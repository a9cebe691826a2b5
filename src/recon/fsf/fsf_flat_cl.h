/* Host side of fsf_flat.cl: FSF's indirect-light filter (fsf_flat.h's two spatial passes) on
 * an OpenCL device, the C fsf_filter_flat staying the reference (tests) and the path without a
 * device. */
#ifndef WEDGE_RECON_FSF_FLAT_CL_H
#define WEDGE_RECON_FSF_FLAT_CL_H

#include "core/diag.h"
#include "recon/cl/cl_runtime.h"
#include "recon/fsf/fsf_filter.h"

typedef struct FsfFlatCl FsfFlatCl;

/* The two kernels, and the device buffers kept from one run to the next (made anew when a
 * frame needs more) until fsf_flat_cl_destroy. NULL + Diag when a kernel is missing. */
FsfFlatCl *fsf_flat_cl_create(ClRuntime *rt, Diag *d);
void fsf_flat_cl_destroy(FsfFlatCl *f);

/* fsf_filter_flat on the device: the same arguments and out4 (rgb, weight per pixel), equal to
 * it up to the device's exponential (an ulp or two in the taps' weights). kernel_seconds (may
 * be NULL) receives both passes' device time. The inputs are read in place where the device
 * can (CL_MEM_USE_HOST_PTR: page-aligned arrays on a CPU device), else copied. */
bool fsf_flat_cl_run(FsfFlatCl *f, const float *value4, const int *count, int width, int height, const FsfGrid *g,
                     const FsfPixel *px, const FsfGuides *gd, float *out4, double *kernel_seconds, Diag *d);

#endif
