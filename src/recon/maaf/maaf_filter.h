/* The MAAF image-space pass (seeds/003 eq. 21, 4D soft-shadow filter as the product of two 2D
 * designs): OpenCL kernels maaf_unpack, maaf_rows and maaf_cols in maaf/maaf.cl, and its plain C
 * reference, which computes the same sums in the same order (tests/recon/test_maaf_filter.c and
 * test_maaf_filter_lanes.c check they agree). The host arrays below are row-major, width x
 * height, no padding; maaf.cl describes its own planes. */
#ifndef WEDGE_RECON_MAAF_FILTER_H
#define WEDGE_RECON_MAAF_FILTER_H

#include <stdbool.h>

#include "core/diag.h"
#include "recon/cl/cl_runtime.h"
#include "recon/maaf/maaf_design.h"

/* Components of the half set (p > 0, or p = 0 and q >= 0) of (2N - 1)^2: ((2N-1)^2 + 1) / 2. */
#define MAAF_COMPS_MAX (((2 * MAAF_PAIRS_MAX - 1) * (2 * MAAF_PAIRS_MAX - 1) + 1) / 2)
int maaf_component_count(int pairs);
/* Eq. 20's sums of one sample: ysum (8 floats per component, the layout of MaafFilterInput's
 * ysum) += f4 (r, g, b, w) x w_c for each component c, w (2 comps floats) its complex factor
 * (re, im). */
void maaf_factors_accumulate(int comps, const float *w, const float f4[4], float *ysum);
/* Per pixel parameters: radius (pixels), then per band p: amplitude, C_x, sx^2 / 2. */
#define MAAF_PARAM_STRIDE (1 + 3 * MAAF_PAIRS_MAX)
/* Largest radius in pixels (the kernel's cost grows with it). */
#define MAAF_RADIUS_CAP_PX 32

/* A band of image rows of the sums in the image pass's own layout (maaf.cl's yp planes):
 * maaf_filter_run runs the pass one band of MAAF_BAND_ROWS rows at a time and hands each band's
 * planes (mapped from the device buffer: on a CPU device the pass's own memory) to the input's
 * fill, which writes every pixel of those rows once with maaf_planes_put. Only a band of the
 * sums exists at a time (3.7 MB instead of 27 MB at 256x256 and N = 3, memory touched for the
 * first time every frame), and no per-pixel array of the sums nor a copy of it is needed
 * (docs/algorithms.md 9.10, 9.16). */
typedef struct {
    float *base;           /* pixel (x, y)'s float k at base[(y - y0) row + k plane + MAAF_PLANES_PAD + x] */
    size_t row, plane;
    int width, height, per; /* per: 8 floats per component, then the flag plane */
    int y0;                 /* the band's first image row */
    /* per pixel of the band's rows (width a row), NULL for all: 1 where some row-pass work item
     * reads every plane of the pixel; 0 where only the central component's 8 planes and the flag
     * are read (maaf_planes_put writes only those, the flag over them) */
    const unsigned char *full;
} MaafPlanes;
/* Writes the sums of image rows [y0, y1) into pl (maaf_planes_put, every pixel once). */
typedef void (*MaafPlanesFill)(void *ctx, const MaafPlanes *pl, int y0, int y1);
/* Rows per band of the image pass (the row pass's output is kept as a ring of this many rows
 * plus the run's largest radius on either side). */
#define MAAF_BAND_ROWS 32

typedef struct {
    int width, height, pairs;
    const float *ysum;     /* 8 floats per component per pixel: Y_c re (r, g, b, w), im (r, g, b, w);
                            * NULL when fill writes them */
    const float *pos4;     /* world position, camera depth */
    const float *nrm4;     /* unit normal, object id */
    const float *frame4;   /* the light's first axis t1 (unit), usable flag (0: not filtered, not used) */
    const float *axis2_4;  /* the light's second axis t2 (unit), unused */
    const float *param;    /* MAAF_PARAM_STRIDE per pixel */
    float cos_normal_min;  /* neighbour rejection, as AAF's */
    float depth_tol_rel;
    /* the sharpness rule: a neighbour whose central sx^2 is above this times the centre's
     * (its std under 1/sqrt(this) of the centre's) holds detail the centre's filter would
     * smear and is left out; 0 means MAAF_SHARP_FACTOR_DEFAULT */
    float sharp_factor;
    MaafPlanesFill fill;   /* writes the sums band by band (ysum NULL), or NULL */
    void *fill_ctx;
} MaafFilterInput;

/* The sharpness rule's factor for the light and bounce filters: a neighbour's std under half
 * the centre's (AAF's rule of docs/algorithms.md 3.3). */
#define MAAF_SHARP_FACTOR_DEFAULT 4.0f

/* The light-plane axes of a unit normal (zero normal: +z), as the kernel builds them. */
void maaf_basis(const float n[3], float t1[3], float t2[3]);

/* in's sharpness factor, its default where it is 0. */
float maaf_sharp_factor(const MaafFilterInput *in);

/* out4: filtered rgb and a flag per pixel (0: unchanged, 1: filtered, 2: central component only). */
void maaf_filter_reference(const MaafFilterInput *in, float *out4);

/* Writes in to path for tests/recon/bench_maaf_filter.c: the magic, width, height, pairs (int32),
 * cos_normal_min, depth_tol_rel (float), then ysum, pos4, nrm4, frame4, axis2_4 and param. The
 * method writes one file per image pass when WEDGE_MAAF_DUMP is set (its value the prefix). */
#define MAAF_DUMP_MAGIC "MAAFDMP1"
#define MAAF_DUMP_ENV "WEDGE_MAAF_DUMP"
bool maaf_filter_dump(const MaafFilterInput *in, const char *path);

typedef struct MaafFilter MaafFilter;
MaafFilter *maaf_filter_create(ClRuntime *rt, Diag *d);
void maaf_filter_destroy(MaafFilter *f);
/* Same as maaf_filter_reference, on the device; kernel_seconds (may be NULL): both passes'
 * device time. */
bool maaf_filter_run(MaafFilter *f, const MaafFilterInput *in, float *out4, double *kernel_seconds, Diag *d);
/* Zero floats on either side of each row of a plane. */
#define MAAF_PLANES_PAD 8
/* Pixel (x, y)'s sums (per floats as one pixel of MaafFilterInput.ysum), NULL for a pixel that is
 * not usable (zeros), and its flag (a non-finite sum). */
void maaf_planes_put(const MaafPlanes *pl, int x, int y, const float *v);
/* Whether pixel (x, y) of the band needs every float of its sums (else the first 8 alone). */
bool maaf_planes_full(const MaafPlanes *pl, int x, int y);
/* The sums of pixel (x, y) back (per floats, the flag left out). */
void maaf_planes_get(const MaafPlanes *pl, int x, int y, float *v);
/* The last run's device seconds of each kernel: maaf_unpack, maaf_rows, maaf_cols (benchmarks). */
#define MAAF_FILTER_KERNELS 3
void maaf_filter_kernel_seconds(const MaafFilter *f, double seconds[MAAF_FILTER_KERNELS]);

#endif
