/* Host side of fsf.cl (see fsf_cl.h). The inputs' buffers are made per run around the caller's
 * arrays, the scratch buffers kept from run to run (below); both passes run in bands of image
 * rows through rings of P's and Q's rows (below). */
#include "recon/fsf/fsf_cl.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/clock.h"
#include "recon/cl/cl_runtime_internal.h"
#include "recon/fsf/fsf_cl_kept.h"

_Static_assert(sizeof(FsfPixel) == 8 * sizeof(float), "fsf.cl reads FsfPixel as 8 floats");

/* fsf.cl's FsfArgs, passed by value. */
typedef struct {
    cl_float half1, half2;
    cl_int J, B;
    cl_float cos_normal_min, plane_tol_rel;
    cl_int width, height;
    cl_float prof1, prof2;
    cl_int geo;
    cl_float lc[3], lu[3], lv[3], ln[3];
    cl_float reach;
    cl_float ramp1, ramp2;
    cl_float geo_w1[8];
    cl_int geo_swept;
} FsfArgs;

/* Both passes run in bands of FSF_BAND_ROWS image rows: pass 1a (2a) fills P's (Q's) rows up
 * to the band's last row plus the rows its gathers reach (the band's halo, band_halo_rows),
 * then pass 1b (2b) gathers the band. P and Q are rings of the band plus the largest halo on
 * either side, so neither holds the whole frame, and a band's gathers read rows written a
 * halo before, still in cache: where the taps run along the rows (defocus' first axis, and
 * most of soft_shadows') that is the band itself. Bands of 8 rows: 32 took 4-8% more CPU on
 * a defocus frame at 256x256, 4 and 2 the same as 8 with more launches, and 8 was no slower at
 * 720x720 (docs/benchmarks.md "FSF's filter cost, third round"). The same floats are summed
 * in the same order: the images do not change. */
enum { FSF_BAND_ROWS = 8 };

/* fsf.cl's tap tables: a pixel's slots hold its taps (2 r + 1) and, along the first axis, its
 * running sums (2 r + 2), rounded up to whole float8; FSF_TAP_SLOTS at most */
enum { FSF_TAP_SLOTS = 40 };
/* fsf.cl's node stride along the second axis (a power of two above J <= FSF_MAX_Y2_BINS + 1) */
enum { FSF_NODE_STRIDE2 = 128 };
_Static_assert(FSF_NODE_STRIDE2 > FSF_MAX_Y2_BINS + 1, "fsf.cl packs j0 below q along the second axis");
_Static_assert((int)FSF_TAP_SLOTS >= (int)FSF_CUM && FSF_TAP_SLOTS % 8 == 0, "fsf.cl writes taps 8 at a time");

/* The device buffers a run writes before it reads them (none holds anything from one run to the
 * next): kept between runs, so that a frame's second and third filterings (combined: shadows,
 * indirect light, defocus) and WEDGE_FSF_PROFILE_REPEAT's runs write pages touched before
 * instead of fresh ones (12,000 page faults a run at 256x256, docs/benchmarks.md "FSF's time
 * outside its kernels"). Their memory is the host's, used in place by the device
 * (CL_MEM_USE_HOST_PTR), from huge_pages.h: 2 MB pages where large and the machine has free 2 MB
 * blocks to spare. A one-frame render's kernels touch 40-50 MB of it for the first time, which in
 * 4 KB pages took about 11,000 page faults (docs/benchmarks.md, "FSF's filter share, third
 * round"). */
enum { KEPT_BIN2, KEPT_NTAP, KEPT_NODE, KEPT_TA0, KEPT_TA1, KEPT_CUM, KEPT_P, KEPT_G, KEPT_N };

struct FsfCl {
    ClRuntime *rt;
    cl_kernel taps, bins, pass1a, pass1b, pass2a, pass2b;
    FsfClProfile prof; /* the last run's */
    FsfClKept kept[KEPT_N];
    cl_int *off;       /* the tap tables' offsets, both axes (page aligned: read in place) */
    size_t off_count;
};

/* slices of P that fit in `bytes`, between 1 and `cap` */
static int slices_within(size_t slice_bytes, size_t bytes, int cap)
{
    size_t fit = slice_bytes ? bytes / slice_bytes : (size_t)cap;
    return fit < 1 ? 1 : fit > (size_t)cap ? cap : (int)fit;
}

int fsf_cl_bins_per_launch(int bins, size_t slice_bytes)
{
    int most = slices_within(slice_bytes, FSF_CL_P_BYTES, FSF_CL_BINS_PER_LAUNCH);
    int wide = slices_within(slice_bytes, FSF_CL_P_WIDE_BYTES, FSF_CL_MAX_BINS_PER_LAUNCH);
    if (wide > most) most = wide;
    if (bins < 1) return 1;
    int launches = (bins + most - 1) / most;
    return (bins + launches - 1) / launches;
}

/* Adds an event's device time to *acc (seconds) and releases it. */
static void add_time(cl_event ev, double *acc)
{
    if (!ev) return;
    *acc += cl_event_seconds(ev);
    clReleaseEvent(ev);
}

static bool cl_ok(cl_int err, const char *what, Diag *d)
{
    if (err == CL_SUCCESS) return true;
    diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "OpenCL %s (FSF): %s", what, cl_error_name(err));
    return false;
}

FsfCl *fsf_cl_create(ClRuntime *rt, Diag *d)
{
    FsfCl *f = calloc(1, sizeof *f);
    if (!f) return NULL;
    f->rt = rt;
    if (!(f->taps = cl_runtime_kernel(rt, "fsf_taps", d)) || !(f->bins = cl_runtime_kernel(rt, "fsf_bins", d)) ||
        !(f->pass1a = cl_runtime_kernel(rt, "fsf_pass1a", d)) ||
        !(f->pass1b = cl_runtime_kernel(rt, "fsf_pass1b", d)) || !(f->pass2a = cl_runtime_kernel(rt, "fsf_pass2a", d)) ||
        !(f->pass2b = cl_runtime_kernel(rt, "fsf_pass2b", d))) {
        fsf_cl_destroy(f);
        return NULL;
    }
    return f;
}

void fsf_cl_destroy(FsfCl *f)
{
    if (!f) return;
    for (int k = 0; k < KEPT_N; ++k) fsf_cl_kept_free(&f->kept[k]);
    free(f->off);
    cl_kernel k[6] = {f->taps, f->bins, f->pass1a, f->pass1b, f->pass2a, f->pass2b};
    for (int i = 0; i < 6; ++i)
        if (k[i]) clReleaseKernel(k[i]);
    free(f);
}

/* Kept buffer k with at least `bytes` (fsf_cl_kept.h), retained for the caller: the run
 * releases it as it does the buffers it creates. */
static cl_mem kept_buffer(FsfCl *f, int k, size_t bytes, cl_int *err)
{
    cl_mem m = fsf_cl_kept_get(f->rt->context, &f->kept[k], bytes, err);
    if (m) clRetainMemObject(m);
    return m;
}

/* Offsets per page: each axis' offsets start on a page of the kept array. */
enum { OFFSETS_PER_PAGE = 4096 / sizeof(cl_int) };
static size_t offsets_stride(size_t n) { return (n + OFFSETS_PER_PAGE - 1) / OFFSETS_PER_PAGE * OFFSETS_PER_PAGE; }

/* The kept array of n pixels' tap table offsets along both axes (the second axis' from
 * offsets_stride(n) on), or NULL when out of memory. Page aligned, as fsf_method.c's inputs: the
 * device reads it in place (CL_MEM_USE_HOST_PTR) rather than a copy. */
static cl_int *kept_offsets(FsfCl *f, size_t n)
{
    size_t count = 2 * offsets_stride(n > 0 ? n : 1);
    if (f->off_count >= count) return f->off;
    free(f->off);
    f->off_count = 0;
    if ((f->off = aligned_alloc(4096, count * sizeof(cl_int)))) f->off_count = count;
    return f->off;
}

/* A 1D launch over n work items in groups of a fixed size (see cl_launch_2d: a size PoCL
 * picks itself is compiled anew per global size). */
static cl_int launch1(FsfCl *f, cl_kernel k, size_t n, cl_event *ev)
{
    size_t local = 64;
    size_t global = (n + local - 1) / local * local;
    return clEnqueueNDRangeKernel(f->rt->queue, k, 1, NULL, &global, &local, 0, NULL, ev);
}

/* Sets a kernel's arguments: the FsfArgs, then ints (as cl_int), then buffers. */
static cl_int set_args(cl_kernel k, const FsfArgs *a, const cl_int *ints, int ni, const cl_mem *mems, int nm)
{
    cl_int err = clSetKernelArg(k, 0, sizeof *a, a);
    cl_uint idx = 1;
    for (int i = 0; i < ni; ++i) err |= clSetKernelArg(k, idx++, sizeof(cl_int), &ints[i]);
    for (int i = 0; i < nm; ++i) err |= clSetKernelArg(k, idx++, sizeof(cl_mem), &mems[i]);
    return err;
}

/* The rows that the taps along `axis` of the pixels in rows [y0, y1) reach above and below
 * them (at most FSF_RADIUS_CAP_PX: unit directions): the largest |round(t dy)| over their taps
 * as fsf_taps finds them, plus one row against a different rounding of t dy on the device (a
 * direction along the rows, dy = 0, reaches no other row whatever the rounding). */
static int band_halo_rows(const FsfGrid *g, int width, int y0, int y1, int axis, const FsfPixel *px,
                          const unsigned char *usable)
{
    int reach = 0;
    for (size_t i = (size_t)y0 * (size_t)width; i < (size_t)y1 * (size_t)width && reach < FSF_RADIUS_CAP_PX; ++i) {
        int r = usable[i] ? fsf_tap_radius(g, px[i].sigma_px[axis]) : 0;
        float dy = fabsf(px[i].dir[axis][1]), reach_rows = (float)r * dy; /* NaN: the cap */
        int rows = r == 0 || dy == 0.0f ? 0
                   : reach_rows < (float)FSF_RADIUS_CAP_PX ? (int)floorf(reach_rows + 0.5f) + 1
                                                         : FSF_RADIUS_CAP_PX;
        if (rows > reach) reach = rows;
    }
    return reach < FSF_RADIUS_CAP_PX ? reach : FSF_RADIUS_CAP_PX;
}

/* Each band's halo along `axis` (halo[b] for rows [b band_rows, (b + 1) band_rows)); returns
 * the largest. */
static int band_halos(const FsfGrid *g, int width, int height, int band_rows, int axis, const FsfPixel *px,
                      const unsigned char *usable, int *halo)
{
    int most = 0;
    for (int b = 0, y0 = 0; y0 < height; ++b, y0 += band_rows) {
        int y1 = y0 + band_rows < height ? y0 + band_rows : height;
        halo[b] = band_halo_rows(g, width, y0, y1, axis, px, usable);
        most = halo[b] > most ? halo[b] : most;
    }
    return most;
}

/* Each pixel's first slot in the tap tables along `axis` (off[i]), packed: a pixel's slots are
 * 2 r + 2 rounded up to whole float8 for its radius r (the running sums' length; its taps,
 * 2 r + 1 at most, fit too), instead of FSF_TAP_SLOTS for every pixel. A pixel left out (r =
 * 0) takes 8 slots, not 40, and one that is not usable none (no pass reads its taps): the
 * tables, fresh memory every run, shrink by a third to a half on the bench scenes. Returns the
 * slots in all, or -1 past INT_MAX. */
static long long tap_offsets(const FsfGrid *g, size_t n, int axis, const FsfPixel *px, const unsigned char *usable,
                             cl_int *off)
{
    long long total = 0;
    for (size_t i = 0; i < n; ++i) {
        off[i] = (cl_int)total;
        total += usable[i] ? (2 * fsf_tap_radius(g, px[i].sigma_px[axis]) + 2 + 7) / 8 * 8 : 0;
        if (total > INT_MAX) return -1;
    }
    return total;
}

bool fsf_cl_run(FsfCl *f, const FsfSamples *s, const FsfGrid *g, const FsfPixel *px, const FsfGuides *gd,
                float *out4, double *kernel_seconds, Diag *d)
{
    double t_start = clock_wall_seconds();
    cl_context ctx = f->rt->context;
    cl_command_queue q = f->rt->queue;
    size_t n = (size_t)s->width * (size_t)s->height, slots = n * (size_t)s->capacity;
    size_t J = (size_t)g->shift_nodes, B = (size_t)g->y2_bins;
    FsfArgs a = {g->half_m[0], g->half_m[1], g->shift_nodes, g->y2_bins, gd->cos_normal_min, gd->plane_tol_rel,
                 s->width, s->height, g->profile_half[0], g->profile_half[1], 0, {0}, {0}, {0}, {0}, g->reach_sigmas,
                 g->ramp_m[0], g->ramp_m[1], {0}, 0};
    /* form 4 (fsf_geo_term.h) reads the guides' positions and normals */
    const FsfGeoTerm *geo = gd->geo && gd->pos4 && gd->nrm4 ? gd->geo : NULL;
    if (geo) {
        a.geo = 1;
        memcpy(a.lc, geo->centre, sizeof a.lc), memcpy(a.lu, geo->axis[0], sizeof a.lu);
        memcpy(a.lv, geo->axis[1], sizeof a.lv), memcpy(a.ln, geo->normal, sizeof a.ln);
        a.geo_swept = geo->ramp_m[0] > 0.0f; /* its marginals weighted as fsf_geo_marginal's */
        if (a.geo_swept) fsf_geo_swept_weights(g->half_m[0], geo->ramp_m[0], a.geo_w1);
    }
    if (g->y2_bins != g->shift_nodes - 1 || g->y2_bins > FSF_MAX_Y2_BINS) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "FSF: y2 bins must be shift nodes - 1 (at most %d)", FSF_MAX_Y2_BINS);
        return false;
    }
    int band_rows = FSF_BAND_ROWS;
    int n_bands = (s->height + band_rows - 1) / band_rows;
    int *halo1 = malloc(sizeof(int) * (size_t)n_bands * 2), *halo2 = halo1 ? halo1 + n_bands : NULL;
    cl_int *off = kept_offsets(f, n), *off1 = off ? off + offsets_stride(n > 0 ? n : 1) : NULL;
    long long slots0 = off ? tap_offsets(g, n, 0, px, gd->usable, off) : -1,
              slots1t = off ? tap_offsets(g, n, 1, px, gd->usable, off1) : -1;
    if (!halo1 || slots0 < 0 || slots1t < 0) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF's bands and tap tables");
        free(halo1);
        return false;
    }
    /* at least one slot: a frame without a usable pixel still gets its buffers */
    long long most_slots = slots0 > slots1t ? slots0 : slots1t;
    size_t tap_slots = most_slots > 0 ? (size_t)most_slots : 1;
    /* each band's rows of P (pass 1) and Q (pass 2) that its gathers reach */
    int most1 = band_halos(g, s->width, s->height, band_rows, 0, px, gd->usable, halo1);
    int most2 = band_halos(g, s->width, s->height, band_rows, 1, px, gd->usable, halo2);
    /* P's and Q's rings of rows (the whole frame when it is no taller): the band and both
     * halos */
    int ring1 = s->height < band_rows + 2 * most1 ? s->height : band_rows + 2 * most1;
    int ring2 = s->height < band_rows + 2 * most2 ? s->height : band_rows + 2 * most2;
    /* the second axis' tap nodes are q FSF_NODE_STRIDE2 + j0, q a pixel of Q's ring (fsf.cl) */
    if ((long long)ring2 * s->width >= INT_MAX / FSF_NODE_STRIDE2) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "FSF: an image too wide for the device's tap tables");
        free(halo1);
        return false;
    }
    /* y2 bins per launch of pass 1a (one slice of P each): fsf_cl_bins_per_launch */
    size_t slice_bytes = sizeof(float) * 4 * J * (size_t)s->width * (size_t)ring1;
    int chunk = fsf_cl_bins_per_launch(g->y2_bins, slice_bytes);
    /* pass 2a's Q (FSF_Q2_CL_FLOATS per pixel of its ring, sized for form 4, the larger) lives
     * in P's memory once pass 1 is done */
    size_t p_bytes = slice_bytes * (size_t)chunk,
           q_bytes = sizeof(float) * (size_t)FSF_Q2_CL_FLOATS(B, 1) * (size_t)s->width * (size_t)ring2;
    cl_int err = CL_SUCCESS;
    enum { COUNT, YS, BIN2, VAL, PX, POS, NRM, MEANG, USE, OFF0, OFF1, NTAP, NODE, TA0, TA1, CUM, P, G, NBUF };
    cl_mem b[NBUF] = {0};
    /* the inputs read in place (a CPU device uses the host memory when it is aligned to its
     * base address alignment, fsf_method.c allocates them so; otherwise PoCL copies them) */
    const cl_mem_flags ro = CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR;
    /* a store without slots (capacity 0) still gets a buffer of one float */
    size_t slots1 = slots ? slots : 1;
    b[COUNT] = clCreateBuffer(ctx, ro, sizeof(int) * n, (void *)s->count, &err);
    if (!err) b[YS] = clCreateBuffer(ctx, ro, sizeof(float) * 2 * slots1, (void *)s->y_m, &err);
    if (!err) b[BIN2] = kept_buffer(f, KEPT_BIN2, slots1, &err);
    if (!err) b[VAL] = clCreateBuffer(ctx, ro, sizeof(float) * 3 * slots1, (void *)s->value, &err);
    if (!err) b[PX] = clCreateBuffer(ctx, ro, sizeof(FsfPixel) * n, (void *)px, &err);
    /* without guides (every usable neighbour accepted) fsf_taps reads neither: a float4 each */
    cl_int guided = gd->pos4 && gd->nrm4;
    if (!err) b[POS] = guided ? clCreateBuffer(ctx, ro, sizeof(float) * 4 * n, (void *)gd->pos4, &err)
                              : clCreateBuffer(ctx, CL_MEM_READ_ONLY, sizeof(float) * 4, NULL, &err);
    if (!err) b[NRM] = guided ? clCreateBuffer(ctx, ro, sizeof(float) * 4 * n, (void *)gd->nrm4, &err)
                              : clCreateBuffer(ctx, CL_MEM_READ_ONLY, sizeof(float) * 4, NULL, &err);
    /* without form 4 passes 1a and 2a do not read the mean term: one float */
    if (!err) b[MEANG] = geo ? clCreateBuffer(ctx, ro, sizeof(float) * n, (void *)geo->mean_g, &err)
                             : clCreateBuffer(ctx, CL_MEM_READ_ONLY, sizeof(float), NULL, &err);
    if (!err) b[USE] = clCreateBuffer(ctx, ro, n, (void *)gd->usable, &err);
    if (!err) b[OFF0] = clCreateBuffer(ctx, ro, sizeof(cl_int) * n, off, &err);
    if (!err) b[OFF1] = clCreateBuffer(ctx, ro, sizeof(cl_int) * n, off1, &err);
    if (!err) b[NTAP] = kept_buffer(f, KEPT_NTAP, sizeof(cl_int) * n, &err);
    if (!err) b[NODE] = kept_buffer(f, KEPT_NODE, sizeof(cl_int) * tap_slots, &err);
    if (!err) b[TA0] = kept_buffer(f, KEPT_TA0, sizeof(float) * tap_slots, &err);
    if (!err) b[TA1] = kept_buffer(f, KEPT_TA1, sizeof(float) * tap_slots, &err);
    /* cum1 (pass 1), then pass 2b's output (4 floats per pixel: more than cum1 when few pixels
     * are usable) */
    size_t cum_floats = (size_t)slots0 > 4 * n ? (size_t)slots0 : 4 * n;
    if (!err) b[CUM] = kept_buffer(f, KEPT_CUM, sizeof(float) * cum_floats, &err);
    if (!err) b[P] = kept_buffer(f, KEPT_P, p_bytes > q_bytes ? p_bytes : q_bytes, &err);
    if (!err) b[G] = kept_buffer(f, KEPT_G, sizeof(float) * 4 * B * n, &err);
    bool ok = cl_ok(err, "buffer allocation", d);
    enum { K_TAPS, K_BINS, K_1A, K_1B, K_2A, K_2B, K_N };
    /* one event per launch: taps twice, bins, 1a and 1b at most once per band and bin chunk,
     * 2a and 2b at most once per band */
    size_t max_ev = 3 + 2 * (size_t)((g->y2_bins + chunk - 1) / chunk + 1) * (size_t)n_bands;
    cl_event *evs = calloc(max_ev, sizeof *evs);
    int *evk = calloc(max_ev, sizeof *evk);
    size_t nev = 0;
    if (ok && !(evs && evk)) {
        ok = false;
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for FSF's OpenCL events");
    }
#define EV(k) (evk[nev] = (k), &evs[nev++])
    double t_queue = clock_wall_seconds();
    if (ok) { /* taps along the first axis (and cum1), their nodes in P's ring */
        cl_int ints[4] = {0, ring1, most1, guided};
        cl_mem m[10] = {b[PX], b[POS], b[NRM], b[USE], b[OFF0], b[NTAP], b[NODE], b[TA0], b[TA1], b[CUM]};
        ok = cl_ok(set_args(f->taps, &a, ints, 4, m, 10), "arguments", d) &&
             cl_ok(launch1(f, f->taps, n, EV(K_TAPS)), "taps", d);
    }
    if (ok) {
        cl_int ints[1] = {s->capacity};
        cl_mem m[4] = {b[COUNT], b[YS], b[USE], b[BIN2]};
        ok = cl_ok(set_args(f->bins, &a, ints, 1, m, 4), "arguments", d) &&
             cl_ok(launch1(f, f->bins, n, EV(K_BINS)), "bins", d);
    }
    for (int bin0 = 0; ok && bin0 < g->y2_bins; bin0 += chunk) {
        cl_int c_n = g->y2_bins - bin0 < chunk ? g->y2_bins - bin0 : chunk;
        /* rows [0, filled) of P hold this chunk's bins; the ring keeps the last ring1 of them,
         * which cover the band and its halos: filled <= y1 + most1 and ring1 = band + 2 most1 */
        int filled = 0;
        for (int y0 = 0, band = 0; ok && y0 < s->height; y0 += band_rows, ++band) {
            int y1 = y0 + band_rows < s->height ? y0 + band_rows : s->height;
            int fill = y1 + halo1[band] < s->height ? y1 + halo1[band] : s->height;
            if (fill > filled) {
                cl_int i1a[6] = {bin0, c_n, s->capacity, filled, fill, ring1};
                cl_mem m1a[12] = {b[COUNT], b[YS], b[BIN2], b[VAL], b[PX],  b[USE],
                                  b[OFF0],  b[CUM], b[POS],  b[NRM], b[MEANG], b[P]};
                ok = cl_ok(set_args(f->pass1a, &a, i1a, 6, m1a, 12), "arguments", d) &&
                     cl_ok(launch1(f, f->pass1a, (size_t)(fill - filled) * (size_t)s->width, EV(K_1A)), "pass 1a", d);
                filled = fill;
            }
            cl_int i1b[5] = {bin0, c_n, y0, y1, ring1};
            cl_mem m1b[8] = {b[USE], b[NTAP], b[OFF0], b[NODE], b[TA0], b[TA1], b[P], b[G]};
            ok = ok && cl_ok(set_args(f->pass1b, &a, i1b, 5, m1b, 8), "arguments", d) &&
                 cl_ok(launch1(f, f->pass1b, (size_t)(y1 - y0) * (size_t)s->width, EV(K_1B)), "pass 1b", d);
        }
    }
    if (ok) { /* taps along the second axis, their nodes in Q's ring (in P's memory: pass 1 is done with it) */
        cl_int ints[4] = {1, ring2, most2, guided};
        cl_mem mt[10] = {b[PX], b[POS], b[NRM], b[USE], b[OFF1], b[NTAP], b[NODE], b[TA0], b[TA1], b[CUM]};
        ok = cl_ok(set_args(f->taps, &a, ints, 4, mt, 10), "arguments", d) &&
             cl_ok(launch1(f, f->taps, n, EV(K_TAPS)), "taps", d);
    }
    /* pass 2 in the same bands: 2a fills Q's rows up to the band's end plus its halo, 2b
     * gathers the band */
    for (int y0 = 0, band = 0, filled = 0; ok && y0 < s->height; y0 += band_rows, ++band) {
        int y1 = y0 + band_rows < s->height ? y0 + band_rows : s->height;
        int fill = y1 + halo2[band] < s->height ? y1 + halo2[band] : s->height;
        if (fill > filled) {
            cl_int i2a[3] = {filled, fill, ring2};
            cl_mem m2a[6] = {b[USE], b[POS], b[NRM], b[MEANG], b[G], b[P]};
            ok = cl_ok(set_args(f->pass2a, &a, i2a, 3, m2a, 6), "arguments", d) &&
                 cl_ok(launch1(f, f->pass2a, (size_t)(fill - filled) * (size_t)s->width, EV(K_2A)), "pass 2a", d);
            filled = fill;
        }
        cl_int i2b[2] = {y0, y1};
        cl_mem m2b[9] = {b[PX], b[USE], b[NTAP], b[OFF1], b[NODE], b[TA0], b[TA1], b[P], b[CUM]};
        ok = ok && cl_ok(set_args(f->pass2b, &a, i2b, 2, m2b, 9), "arguments", d) &&
             cl_ok(launch1(f, f->pass2b, (size_t)(y1 - y0) * (size_t)s->width, EV(K_2B)), "pass 2b", d);
    }
    if (ok) ok = cl_ok(clEnqueueReadBuffer(q, b[CUM], CL_TRUE, 0, sizeof(float) * 4 * n, out4, 0, NULL, NULL), "download", d);
    clFinish(q);
#undef EV
    double kt[K_N] = {0};
    for (size_t e = 0; e < nev; ++e) add_time(evs[e], &kt[evk[e]]);
    free(evs), free(evk);
    f->prof = (FsfClProfile){kt[K_TAPS], kt[K_BINS], kt[K_1A],         kt[K_1B],
                             kt[K_2A],   kt[K_2B],   t_queue - t_start, clock_wall_seconds() - t_queue};
    if (ok && kernel_seconds) *kernel_seconds = kt[K_TAPS] + kt[K_BINS] + kt[K_1A] + kt[K_1B] + kt[K_2A] + kt[K_2B];
    for (int i = 0; i < NBUF; ++i)
        if (b[i]) clReleaseMemObject(b[i]);
    free(halo1);
    return ok;
}

FsfClProfile fsf_cl_profile(const FsfCl *f) { return f->prof; }
