/* Host side of FSF's OpenCL kernels (fsf.cl): the same four passes as fsf_filter_factored,
 * on the device (tested against it). */
#ifndef WEDGE_RECON_FSF_CL_H
#define WEDGE_RECON_FSF_CL_H

#include "core/diag.h"
#include "recon/cl/cl_runtime.h"
#include "recon/fsf/fsf_filter.h"

typedef struct FsfCl FsfCl;

/* Device seconds of each kernel in the last fsf_cl_run (PoCL event profiling), summed over
 * its launches; and the run's wall seconds before the first launch (halos, tap offsets, the
 * buffers) and from it to the download's end. */
typedef struct {
    double taps, bins, pass1a, pass1b, pass2a, pass2b;
    double setup_wall, queue_wall;
} FsfClProfile;
FsfClProfile fsf_cl_profile(const FsfCl *f);

/* An FsfCl keeps its scratch buffers from one run to the next (made anew when a run needs more),
 * until fsf_cl_destroy. */
FsfCl *fsf_cl_create(ClRuntime *rt, Diag *d);
void fsf_cl_destroy(FsfCl *f);

/* fsf_filter_factored on the device: out4 gets (rgb, weight) per pixel. kernel_seconds (may
 * be NULL) receives the kernels' device time, summed over every launch (fsf_cl_profile has
 * it per kernel). The inputs (s's arrays, px, gd's) are read in place (CL_MEM_USE_HOST_PTR:
 * on a CPU device no copy when they are aligned to the device's base address alignment, a
 * page is enough); s's sample arrays hold at least one slot even when s->capacity is 0. */
bool fsf_cl_run(FsfCl *f, const FsfSamples *s, const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd,
                float *out4, double *kernel_seconds, Diag *d);

/* The y2 bins pass 1a fills in one launch (one slice of P each, C in fsf.cl; pass 1b gathers
 * them with one read of each tap): as few launches as hold `bins` with at most
 * FSF_CL_MAX_BINS_PER_LAUNCH slices and at most p_bytes of slices (slice_bytes each; one
 * launch per bin when not even one fits), each launch no larger than that needs: the smallest
 * count with as few launches (12 bins: two launches of 6, not 8 and 4). Each bin's sums are the
 * same whatever the split; a launch shares each pixel's set-up and its scan of the slots
 * between its bins, and pass 1b each tap's read. Up to 4 bins a launch took 25% less time in
 * pass 1a than 1 (docs/benchmarks.md, "FSF's passes, faster"); 8 took another 14% off pass 1a
 * on defocus' 16 bins (docs/benchmarks.md, branch fsf14). */
enum { FSF_CL_MAX_BINS_PER_LAUNCH = 8 };
int fsf_cl_bins_per_launch(int bins, size_t slice_bytes, size_t p_bytes);

#endif
