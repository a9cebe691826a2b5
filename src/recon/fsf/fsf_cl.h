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
 * them with one read of each tap), for slices of slice_bytes: as few launches as hold `bins`
 * with at most `most` slices, then the smallest count with that many launches (12 bins: two
 * launches of 6, not 8 and 4). `most` is FSF_CL_BINS_PER_LAUNCH slices within FSF_CL_P_BYTES
 * (the rule before 2026-12-01: 4 slices took 25% less time in pass 1a than 1, docs/benchmarks.md
 * "FSF's passes, faster"), or up to FSF_CL_MAX_BINS_PER_LAUNCH where that many fit in
 * FSF_CL_P_WIDE_BYTES: a launch shares each pixel's set-up and its scan of the slots between its
 * bins, and pass 1b each tap's read (8 bins took 14% off pass 1a on defocus at 256 x 256,
 * docs/benchmarks.md, branch fsf14), but P's ring is fresh memory in a one-frame process, so
 * the wider launches stop where the ring would pass 16 MB (at 256 x 256 defocus' 8 slices are 4.2
 * MB, about what its Q takes of the same memory anyway, soft_shadows' 6 are 9.1 MB instead of 6.1;
 * at 720 x 720 defocus keeps 8 of 1.5 MB, soft_shadows 4 of 4.6 MB instead of 8, 36 MB). Each
 * bin's sums are the same whatever the split. At least 1 (slices of 0 bytes: the cap). */
#define FSF_CL_P_BYTES ((size_t)72 << 20)
#define FSF_CL_P_WIDE_BYTES ((size_t)16 << 20)
enum { FSF_CL_BINS_PER_LAUNCH = 4, FSF_CL_MAX_BINS_PER_LAUNCH = 8 };
int fsf_cl_bins_per_launch(int bins, size_t slice_bytes);

#endif
