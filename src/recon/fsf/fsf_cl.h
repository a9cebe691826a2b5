/* Host side of FSF's OpenCL kernels (fsf.cl): the same four passes as fsf_filter_factored,
 * on the device (tested against it). */
#ifndef WEDGE_RECON_FSF_CL_H
#define WEDGE_RECON_FSF_CL_H

#include "core/diag.h"
#include "recon/cl/cl_runtime.h"
#include "recon/fsf/fsf_filter.h"

typedef struct FsfCl FsfCl;

/* Device seconds of each kernel in the last fsf_cl_run (PoCL event profiling), summed over
 * its launches. */
typedef struct {
    double taps, bins, pass1a, pass1b, pass2a, pass2b;
} FsfClProfile;
FsfClProfile fsf_cl_profile(const FsfCl *f);

FsfCl *fsf_cl_create(ClRuntime *rt, Diag *d);
void fsf_cl_destroy(FsfCl *f);

/* fsf_filter_factored on the device: out4 gets (rgb, weight) per pixel. kernel_seconds (may
 * be NULL) receives the kernels' device time, summed over every launch (fsf_cl_profile has
 * it per kernel). */
bool fsf_cl_run(FsfCl *f, const FsfSamples *s, const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd,
                float *out4, double *kernel_seconds, Diag *d);

#endif
