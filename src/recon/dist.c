/* Several ranks, one frame (see dist.h). */
#define _GNU_SOURCE /* sched_setaffinity, cpu_set_t (Linux) */
#include "recon/dist.h"

#include <dirent.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/env_knob.h"

#ifdef __linux__
#include <sched.h>
_Static_assert(sizeof(cpu_set_t) == DIST_CPU_BYTES, "a core mask is the C library's cpu_set_t");
#endif

#ifdef WEDGE_MPI
#include "recon/mpi_library.h"

/* The MPI library, once dist_init has loaded it (mpirun started the process); NULL otherwise,
 * and then no MPI function is called. */
static const MpiLibrary *mpi;
#endif

/* The longest nap between two looks at a collective a rank waits in (quiet_arrival): the
 * latency it can add to a collective, per round of the barrier's messages. */
#define QUIET_NAP_MAX_NS 200000L
/* The most bytes a rank sends to or receives from rank 0 in one round of an exchange, and
 * the most rank 0 receives or sends in one round from all of them together. */
#define DIST_CHUNK_BYTES ((size_t)4 << 20)
#define DIST_ROUND_BYTES ((size_t)64 << 20)

bool dist_available(void)
{
#ifdef WEDGE_MPI
    return true;
#else
    return false;
#endif
}

/* mpirun (Open MPI, or a PMI launcher) says so in the environment; a wedge started by hand
 * must not pay for MPI_Init (or fail without a launcher). */
static bool launched_by_mpirun(void)
{
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMI_SIZE") || getenv("PMIX_RANK");
}

#ifdef WEDGE_MPI
/* The union of the core masks of the ranks that share this rank's node (a communicator of
 * the ranks that can share memory: one node), gathered once at start. */
static void node_cpus_init(ReconDist *d)
{
#ifdef __linux__
    cpu_set_t own;
    CPU_ZERO(&own);
    if (sched_getaffinity(0, sizeof own, &own) != 0) CPU_ZERO(&own); /* unknown: still take part */
    MPI_Comm node;
    if (mpi->comm_split_type(mpi->comm_world, MPI_COMM_TYPE_SHARED, 0, mpi->info_null, &node) != MPI_SUCCESS)
        return;
    mpi->comm_set_errhandler(node, mpi->errors_return);
    int n = 0;
    mpi->comm_size(node, &n);
    cpu_set_t *all = malloc((size_t)n * sizeof *all);
    if (all &&
        mpi->allgather(&own, (int)sizeof own, mpi->type_byte, all, (int)sizeof own, mpi->type_byte, node) == MPI_SUCCESS &&
        CPU_COUNT(&own) > 0) {
        cpu_set_t any;
        CPU_ZERO(&any);
        for (int k = 0; k < n; ++k) CPU_OR(&any, &any, &all[k]);
        memcpy(d->own_cpus, &own, sizeof own);
        memcpy(d->node_cpus, &any, sizeof any);
        d->cpus_known = true;
    }
    free(all);
    mpi->comm_free(&node);
#else
    (void)d;
#endif
}
#endif

void dist_node_cpus(const ReconDist *d, bool on)
{
#ifdef __linux__
    if (!d || !d->cpus_known || memcmp(d->own_cpus, d->node_cpus, DIST_CPU_BYTES) == 0) return;
    /* WEDGE_DIST_CORES=own (for measuring against it): every thread on its rank's cores */
    static int own_only = -1;
    static const char *const cores_names[] = {"node", "own"};
    if (own_only < 0) own_only = env_knob_choice("WEDGE_DIST_CORES", cores_names, 2, 0) == 1;
    if (own_only) return;
    cpu_set_t set;
    memcpy(&set, on ? d->node_cpus : d->own_cpus, sizeof set);
    sched_setaffinity(0, sizeof set, &set); /* the calling thread; a failure leaves it as it was */
#else
    (void)d, (void)on;
#endif
}

int dist_own_cores(const ReconDist *d)
{
#ifdef __linux__
    if (!d || !d->cpus_known) return 0;
    cpu_set_t set;
    memcpy(&set, d->own_cpus, sizeof set);
    return CPU_COUNT(&set);
#else
    (void)d;
    return 0;
#endif
}

int dist_thread_ids(int *tid, int max)
{
    DIR *dir = opendir("/proc/self/task");
    int n = 0;
    for (struct dirent *e; dir && n < max && (e = readdir(dir));)
        if (e->d_name[0] != '.') tid[n++] = atoi(e->d_name);
    if (dir) closedir(dir);
    return n;
}

#ifdef __linux__
/* Appends " " and the cores of mask (a cpu_set_t's bytes) as a list ("0-3,6", "-" for none)
 * to out (n bytes, at *at). */
static void append_cpus(const unsigned char *mask, char *out, size_t n, int *at)
{
    cpu_set_t set;
    memcpy(&set, mask, sizeof set);
    const char *sep = " ";
    for (int c = 0; c < CPU_SETSIZE && *at >= 0 && (size_t)*at < n; ++c) {
        if (!CPU_ISSET(c, &set) || (c > 0 && CPU_ISSET(c - 1, &set))) continue; /* not a run's first */
        int last = c;
        while (last + 1 < CPU_SETSIZE && CPU_ISSET(last + 1, &set)) ++last;
        *at += last > c ? snprintf(out + *at, n - (size_t)*at, "%s%d-%d", sep, c, last)
                        : snprintf(out + *at, n - (size_t)*at, "%s%d", sep, c);
        sep = ",";
    }
    if (*sep == ' ' && *at >= 0 && (size_t)*at < n) *at += snprintf(out + *at, n - (size_t)*at, " -");
}
#endif

void dist_log_new_threads(const ReconDist *d, const int *before, int before_count, const char *what)
{
#ifdef __linux__
    if (!d || !getenv("WEDGE_DIST_LOG")) return;
    char line[2048];
    int at = snprintf(line, sizeof line, "dist-cpus rank %d: own", d->rank);
    append_cpus(d->own_cpus, line, sizeof line, &at);
    at += snprintf(line + at, sizeof line - (size_t)at, " node");
    append_cpus(d->node_cpus, line, sizeof line, &at);
    at += snprintf(line + at, sizeof line - (size_t)at, " %s", what);
    int now[256], n = dist_thread_ids(now, 256);
    for (int k = 0; k < n && at > 0 && (size_t)at < sizeof line; ++k) {
        bool old = false;
        for (int j = 0; j < before_count && !old; ++j) old = before[j] == now[k];
        cpu_set_t set;
        if (old || sched_getaffinity(now[k], sizeof set, &set) != 0) continue;
        append_cpus((const unsigned char *)&set, line, sizeof line, &at);
    }
    fprintf(stderr, "%s\n", line); /* one write: mpirun interleaves the ranks' writes */
#else
    (void)d, (void)before, (void)before_count, (void)what;
#endif
}

bool dist_init(int *argc, char ***argv, ReconDist *d, Diag *e)
{
    memset(d, 0, sizeof *d);
    d->rank = 0;
    d->ranks = 1;
#ifdef WEDGE_MPI
    if (!launched_by_mpirun()) return true;
    /* the library only now: a wedge not started by mpirun never maps it (mpi_library.h) */
    if (!(mpi = mpi_library_load(e))) return false;
    int inited = 0;
    mpi->initialized(&inited);
    if (!inited && mpi->init(argc, argv) != MPI_SUCCESS) return true; /* as before the library was loaded lazily */
    /* errors come back as codes (reported with a message, exit 3), not an abort */
    mpi->comm_set_errhandler(mpi->comm_world, mpi->errors_return);
    mpi->comm_rank(mpi->comm_world, &d->rank);
    mpi->comm_size(mpi->comm_world, &d->ranks);
    node_cpus_init(d);
#else
    (void)argc, (void)argv, (void)e;
#endif
    return true;
}

void dist_finish(ReconDist *d)
{
#ifdef WEDGE_MPI
    int inited = 0, done = 0;
    if (mpi) {
        mpi->initialized(&inited);
        mpi->finalized(&done);
    }
    if (inited && !done) mpi->finalize();
#endif
    free(d->owner);
    free(d->owner_before);
    free(d->tile_seconds);
    free(d->tile_samples);
    free(d->xbuf);
    d->owner = d->owner_before = NULL;
    d->tile_seconds = d->tile_samples = NULL;
    d->xbuf = NULL;
    d->xbuf_bytes = 0;
}

bool dist_tiles_reset(ReconDist *d, int width, int height, Diag *e)
{
    if (!d) return true;
    d->width = width, d->height = height;
    d->tiles_x = (width + DIST_TILE_PX - 1) / DIST_TILE_PX;
    d->tile_count = d->tiles_x * ((height + DIST_TILE_PX - 1) / DIST_TILE_PX);
    d->tiles_moved = 0;
    free(d->owner);
    free(d->owner_before);
    free(d->tile_seconds);
    free(d->tile_samples);
    d->owner = d->owner_before = NULL;
    d->tile_seconds = d->tile_samples = NULL;
    if (d->ranks <= 1) return true;
    d->owner = malloc((size_t)d->tile_count * sizeof(int));
    d->owner_before = malloc((size_t)d->tile_count * sizeof(int));
    d->tile_seconds = calloc((size_t)d->tile_count, sizeof(double));
    d->tile_samples = calloc((size_t)d->tile_count, sizeof(double));
    if (!d->owner || !d->owner_before || !d->tile_seconds || !d->tile_samples) {
        diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the MPI tile owners (%dx%d)", width, height);
        return false;
    }
    /* pass 1: the interleave (every pixel takes the same count). Tile t to rank t mod ranks
     * balanced pass 1 better than diagonals, (tx + ty) mod ranks (the CPU seconds of the
     * busier rank over the mean, medians of 6: soft_shadows 1.015 against 1.037, combined
     * 1.009 against 1.038) */
    for (int t = 0; t < d->tile_count; ++t) d->owner[t] = d->owner_before[t] = t % d->ranks;
    return true;
}

int dist_owner(const ReconDist *d, int px, int py)
{
    if (!d || d->ranks <= 1 || !d->owner) return 0;
    return d->owner[(py / DIST_TILE_PX) * d->tiles_x + px / DIST_TILE_PX];
}

/* A tile in dist_balance's order: decreasing cost, then increasing index (qsort is not
 * stable; the index makes the order total, so every rank sorts alike). */
typedef struct {
    double cost;
    int tile;
} TileCost;

static int by_cost_desc(const void *pa, const void *pb)
{
    const TileCost *a = pa, *b = pb;
    if (a->cost != b->cost) return a->cost > b->cost ? -1 : 1;
    return (a->tile > b->tile) - (a->tile < b->tile);
}

void dist_balance(const double *tile_cost, const int *before, int tile_count, int ranks, int *owner)
{
    TileCost *order = malloc((size_t)tile_count * sizeof *order);
    double *load = calloc((size_t)ranks, sizeof(double));
    double total = 0.0;
    for (int t = 0; t < tile_count; ++t) total += tile_cost[t];
    double ideal = total / ranks;
    if (!order || !load) { /* out of memory: the interleave (balanced for even costs) */
        for (int t = 0; t < tile_count; ++t) owner[t] = t % ranks;
        free(order);
        free(load);
        return;
    }
    for (int t = 0; t < tile_count; ++t) order[t] = (TileCost){tile_cost[t], t};
    qsort(order, (size_t)tile_count, sizeof *order, by_cost_desc);
    /* 1. Each rank keeps its previous tiles, cheapest first, while its sum stays within the
     *    ideal: an overloaded rank gives away its dearest tiles, the fewest tiles (and bytes
     *    handed over) for its excess. Free tiles always stay. */
    for (int t = 0; t < tile_count; ++t) owner[t] = -1;
    for (int k = tile_count - 1; before && k >= 0; --k) {
        int t = order[k].tile, r = before[t];
        if (r >= 0 && r < ranks && load[r] + tile_cost[t] <= ideal) owner[t] = r, load[r] += tile_cost[t];
    }
    /* 2. The rest, dearest first, each to the rank with the least sum so far (Graham's LPT
     *    rule: the small tiles placed last even out the sums); ties go to the previous owner,
     *    then the lower rank. */
    for (int k = 0; k < tile_count; ++k) {
        int t = order[k].tile;
        if (owner[t] >= 0) continue;
        int least = before && before[t] >= 0 && before[t] < ranks ? before[t] : 0;
        for (int q = 0; q < ranks; ++q)
            if (load[q] < load[least]) least = q;
        owner[t] = least;
        load[least] += tile_cost[t];
    }
    free(order);
    free(load);
}

bool dist_reassign(ReconDist *d, const int *spp, Diag *e)
{
    if (!d || d->ranks <= 1 || !d->owner) return true;
    /* WEDGE_DIST_OWNERS=interleave (for measuring against it): the first build's ownership,
     * pass 1's interleave kept for every pass */
    static const char *const owners_names[] = {"balance", "interleave"};
    if (env_knob_choice("WEDGE_DIST_OWNERS", owners_names, 2, 0) == 1) {
        memcpy(d->owner_before, d->owner, (size_t)d->tile_count * sizeof(int)); /* nothing moves */
        return true;
    }
    double *cost = calloc((size_t)d->tile_count, sizeof(double));
    if (!cost) {
        diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the MPI tile costs");
        return false;
    }
    /* a tile's predicted cost: the samples planned in it times its measured time per sample
     * (dist_measure's units; paths differ in length and in the rays they spawn: sky, a
     * shadowed corner) */
    for (int y = 0; y < d->height; ++y)
        for (int x = 0; x < d->width; ++x)
            cost[(y / DIST_TILE_PX) * d->tiles_x + x / DIST_TILE_PX] += spp[(size_t)y * (size_t)d->width + (size_t)x];
    double seconds = 0.0, samples = 0.0;
    for (int t = 0; t < d->tile_count; ++t) seconds += d->tile_seconds[t], samples += d->tile_samples[t];
    double mean_rate = seconds > 0.0 && samples > 0.0 ? seconds / samples : 1.0;
    /* WEDGE_DIST_COST=samples (for measuring the model): every tile at the mean rate */
    static const char *const cost_names[] = {"measured", "samples"};
    bool counts_only = env_knob_choice("WEDGE_DIST_COST", cost_names, 2, 0) == 1;
    for (int t = 0; t < d->tile_count; ++t) {
        bool measured = !counts_only && d->tile_samples[t] > 0.0 && d->tile_seconds[t] > 0.0;
        cost[t] *= measured ? d->tile_seconds[t] / d->tile_samples[t] : mean_rate;
    }
    int *swap = d->owner_before;
    d->owner_before = d->owner;
    d->owner = swap;
    /* WEDGE_DIST_NO_KEEP=1 (for tests): plain largest-first, no tile kept with its owner, so
     * that about half the tiles move and the hand-over is exercised */
    const int *keep = getenv("WEDGE_DIST_NO_KEEP") ? NULL : d->owner_before;
    dist_balance(cost, keep, d->tile_count, d->ranks, d->owner);
    for (int t = 0; t < d->tile_count; ++t) d->tiles_moved += d->owner[t] != d->owner_before[t];
    free(cost);
    return true;
}

#ifdef WEDGE_MPI
static bool mpi_ok(int rc, const char *what, Diag *e);
static bool quiet_arrival(Diag *e);
#endif

bool dist_measure(ReconDist *d, float *pixel_seconds, const int *spp, int spp_uniform, Diag *e)
{
    if (!d || d->ranks <= 1 || !d->owner) return true;
    /* the seconds of every tile: this rank's tiles, 0 elsewhere; the sum over ranks is every
     * tile's (each tile has one owner, so the sum is exact and the same on every rank) */
    size_t n = (size_t)d->tile_count;
    double *mine = calloc(n, sizeof(double)), *all = calloc(n, sizeof(double));
    if (!mine || !all) {
        free(mine);
        free(all);
        diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the MPI tile costs");
        return false;
    }
    double my_seconds = 0.0, my_samples = 0.0;
    for (int y = 0; y < d->height; ++y)
        for (int x = 0; x < d->width; ++x) {
            int t = (y / DIST_TILE_PX) * d->tiles_x + x / DIST_TILE_PX;
            size_t i = (size_t)y * (size_t)d->width + (size_t)x;
            int samples = spp ? spp[i] : spp_uniform;
            if (d->owner[t] == d->rank) {
                mine[t] += pixel_seconds[i];
                my_seconds += pixel_seconds[i];
                my_samples += samples;
            }
            pixel_seconds[i] = 0.0f;
            d->tile_samples[t] += samples; /* known to every rank */
        }
    /* in units of this rank's mean time per sample this pass: a tile's cost relative to the
     * others the rank traced, so that a rank slower than another (other jobs on its cores, an
     * older node) does not make its tiles look dear */
    if (my_seconds > 0.0)
        for (size_t t = 0; t < n; ++t) mine[t] *= my_samples / my_seconds;
    bool ok = true;
#ifdef WEDGE_MPI
    ok = quiet_arrival(e) &&
         mpi_ok(mpi->allreduce(mine, all, (int)n, mpi->type_double, mpi->op_sum, mpi->comm_world), "all-reduce", e);
#else
    memcpy(all, mine, n * sizeof(double));
#endif
    for (size_t t = 0; ok && t < n; ++t) d->tile_seconds[t] += all[t];
    free(mine);
    free(all);
    return ok;
}

#ifdef WEDGE_MPI
static bool mpi_ok(int rc, const char *what, Diag *e)
{
    if (rc == MPI_SUCCESS) return true;
    char msg[MPI_MAX_ERROR_STRING] = "";
    int len = 0;
    mpi->error_string(rc, msg, &len);
    diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "MPI %s failed: %s (another rank may have died)", what, msg);
    return false;
}

/* Waits until every rank has reached this collective, napping rather than spinning. Open MPI
 * waits in a blocking call by polling, a core at 100%: a rank that has finished its part of
 * a pass (or rank 1 while rank 0 plans, reconstructs and writes the image) took a core from
 * rank 0, whose plan and OpenCL reconstruction use both (docs/benchmarks.md: AAF's
 * reconstruction at 720x720 took 0.217 s with 2 ranks against 0.145 s with one). A
 * nonblocking barrier tested between naps that double from 1 us to QUIET_NAP_MAX_NS frees
 * the core and costs at most a nap per round of the barrier; the collective that follows
 * then finds every rank there and spins only while its data moves.
 * WEDGE_DIST_WAIT=spin (for measuring against it): the plain blocking call. */
static bool quiet_arrival(Diag *e)
{
    static int spin = -1;
    static const char *const wait_names[] = {"nap", "spin"};
    if (spin < 0) spin = env_knob_choice("WEDGE_DIST_WAIT", wait_names, 2, 0) == 1;
    if (spin) return true;
    MPI_Request req;
    int rc = mpi->ibarrier(mpi->comm_world, &req);
    for (long nap_ns = 1000; rc == MPI_SUCCESS;) {
        int done = 0;
        rc = mpi->test(&req, &done, MPI_STATUS_IGNORE);
        if (rc != MPI_SUCCESS || done) break;
        struct timespec ts = {0, nap_ns};
        nanosleep(&ts, NULL);
        nap_ns = nap_ns * 2 < QUIET_NAP_MAX_NS ? nap_ns * 2 : QUIET_NAP_MAX_NS;
    }
    return e ? mpi_ok(rc, "barrier", e) : rc == MPI_SUCCESS;
}

/* Whether tile t travels for rank r: in a gather, the tiles r owns; in a hand-over, the tiles
 * r owns now and did not before. */
static bool travels(const ReconDist *d, int t, int r, bool handover)
{
    return d->owner[t] == r && (!handover || d->owner_before[t] != r);
}

/* The pixels [x0, x1) x [y0, y1) of tile t (clipped at the frame's edge). */
static void tile_rect(const ReconDist *d, int t, int *x0, int *y0, int *x1, int *y1)
{
    *x0 = (t % d->tiles_x) * DIST_TILE_PX, *y0 = (t / d->tiles_x) * DIST_TILE_PX;
    *x1 = *x0 + DIST_TILE_PX < d->width ? *x0 + DIST_TILE_PX : d->width;
    *y1 = *y0 + DIST_TILE_PX < d->height ? *y0 + DIST_TILE_PX : d->height;
}

/* Copies the bytes [lo, hi) of rank r's stream of travelling pixels (every array, array by
 * array, tile by tile in index order, row by row) out of (to_buf) or into (!to_buf) buf,
 * whose byte 0 is the stream's byte lo; buf NULL: only counts. Returns the stream's length. */
static size_t pack(const ReconDist *d, int r, bool handover, const DistArray *arrays, int count, unsigned char *buf,
                   bool to_buf, size_t lo, size_t hi)
{
    size_t pixels = 0; /* of the travelling tiles: each array's part of the stream is pixels * bpp */
    for (int t = 0; t < d->tile_count; ++t) {
        if (!travels(d, t, r, handover)) continue;
        int x0, y0, x1, y1;
        tile_rect(d, t, &x0, &y0, &x1, &y1);
        pixels += (size_t)(x1 - x0) * (size_t)(y1 - y0);
    }
    size_t at = 0;
    for (int k = 0; k < count; ++k) {
        size_t bpp = arrays[k].bytes_per_pixel;
        unsigned char *data = arrays[k].data;
        if (!buf || at + pixels * bpp <= lo || at >= hi) { /* the array lies outside the window */
            at += pixels * bpp;
            continue;
        }
        size_t start = at;
        for (int t = 0; t < d->tile_count && at < hi; ++t) {
            if (!travels(d, t, r, handover)) continue;
            int x0, y0, x1, y1;
            tile_rect(d, t, &x0, &y0, &x1, &y1);
            size_t bytes = (size_t)(x1 - x0) * bpp;
            if (at + bytes * (size_t)(y1 - y0) <= lo) { /* the tile lies before the window */
                at += bytes * (size_t)(y1 - y0);
                continue;
            }
            for (int y = y0; y < y1; ++y, at += bytes) {
                size_t from = at > lo ? at : lo, to = at + bytes < hi ? at + bytes : hi;
                if (from >= to) continue;
                unsigned char *row = data + ((size_t)y * (size_t)d->width + (size_t)x0) * bpp + (from - at);
                if (to_buf) memcpy(buf + (from - lo), row, to - from);
                else memcpy(row, buf + (from - lo), to - from);
            }
        }
        at = start + pixels * bpp; /* past the tiles after the window too */
    }
    return at;
}

/* Every rank's stream length in bytes (length[r]). */
static void layout(const ReconDist *d, bool handover, const DistArray *arrays, int count, size_t *length)
{
    for (int r = 0; r < d->ranks; ++r) length[r] = pack(d, r, handover, arrays, count, NULL, true, 0, 0);
}

/* d->xbuf with room for bytes (grow-only); NULL when out of memory. */
static unsigned char *exchange_buffer(ReconDist *d, size_t bytes)
{
    if (bytes > d->xbuf_bytes) {
        free(d->xbuf);
        d->xbuf = malloc(bytes);
        d->xbuf_bytes = d->xbuf ? bytes : 0;
    }
    return d->xbuf;
}

/* The gather (rank 0 receives every rank's tiles) or the hand-over (rank 0 sends each rank
 * its new tiles), every array in one stream per rank, sent in rounds of at most
 * DIST_CHUNK_BYTES per rank through one small buffer (rank 0: a chunk per rank). A buffer
 * for the whole stream (70 MB from rank 1 at 720x720 under AAF) cost a first-touch fault per
 * page on both sides in the first gather of each frame and a copy that left the caches; a
 * chunk is faulted once per process, stays in the caches between its packing, the sending and
 * the unpacking, and costs a collective (tens of microseconds) per round. Rank 0's own tiles
 * stay where they are (MPI_IN_PLACE). */
static bool exchange(ReconDist *d, bool handover, const DistArray *arrays, int count, int pass, Diag *e)
{
    size_t *length = calloc((size_t)d->ranks, sizeof(size_t));
    int *counts = calloc((size_t)d->ranks, sizeof(int)), *displs = calloc((size_t)d->ranks, sizeof(int));
    bool ok = length && counts && displs;
    if (!ok) diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the MPI exchange");
    if (ok) layout(d, handover, arrays, count, length);
    bool root = d->rank == 0;
    size_t longest = 0, total = 0;
    for (int r = 1; ok && r < d->ranks; ++r) {
        longest = length[r] > longest ? length[r] : longest;
        total += length[r];
    }
    /* WEDGE_DIST_CHUNK=bytes (for tests): smaller rounds, which cut rows and arrays anywhere */
    size_t most = getenv("WEDGE_DIST_CHUNK") ? (size_t)strtoull(getenv("WEDGE_DIST_CHUNK"), NULL, 10) : 0;
    /* rank 0 holds a chunk per rank: on many ranks the chunks shrink so that a round stays
     * within DIST_ROUND_BYTES (and its offsets within an int) */
    size_t fair = DIST_ROUND_BYTES / (size_t)d->ranks;
    size_t cap = DIST_CHUNK_BYTES < fair ? DIST_CHUNK_BYTES : fair > 4096 ? fair : 4096;
    most = most > 0 && most < cap ? most : cap;
    size_t chunk = longest < most ? longest : most;
    unsigned char *buf = NULL;
    if (ok) {
        /* rank 0: a chunk per rank at offset r * chunk (its own part never used); the others: one */
        buf = exchange_buffer(d, (root ? (size_t)d->ranks : 1) * (chunk ? chunk : 1));
        ok = buf != NULL;
        if (!ok) diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the MPI exchange");
    }
    ok = ok && quiet_arrival(e);
    /* every rank counts the same rounds: the longest stream's */
    for (size_t lo = 0; ok && lo < longest; lo += chunk) {
        size_t hi = lo + chunk;
        for (int r = 0; r < d->ranks; ++r) {
            size_t end = r > 0 && length[r] > lo ? (length[r] < hi ? length[r] : hi) : lo;
            counts[r] = (int)(end - lo);
            displs[r] = (int)((size_t)r * chunk);
        }
        unsigned char *mine = root ? NULL : buf;
        if (!handover) {
            if (!root) pack(d, d->rank, false, arrays, count, mine, true, lo, hi);
            MPI_Datatype byte = mpi->type_byte;
            ok = mpi_ok(root ? mpi->gatherv(MPI_IN_PLACE, 0, byte, buf, counts, displs, byte, 0, mpi->comm_world)
                             : mpi->gatherv(mine, counts[d->rank], byte, NULL, NULL, NULL, byte, 0, mpi->comm_world),
                        "gather", e);
            if (ok && root)
                for (int r = 1; r < d->ranks; ++r) pack(d, r, false, arrays, count, buf + displs[r], false, lo, hi);
        } else {
            if (root)
                for (int r = 1; r < d->ranks; ++r) pack(d, r, true, arrays, count, buf + displs[r], true, lo, hi);
            MPI_Datatype byte = mpi->type_byte;
            ok = mpi_ok(root ? mpi->scatterv(buf, counts, displs, byte, MPI_IN_PLACE, 0, byte, 0, mpi->comm_world)
                             : mpi->scatterv(NULL, NULL, NULL, byte, mine, counts[d->rank], byte, 0, mpi->comm_world),
                        "hand-over", e);
            if (ok && !root) pack(d, d->rank, true, arrays, count, mine, false, lo, hi);
        }
    }
    if (ok && root) { /* what crossed between ranks: everything but rank 0's own part */
        d->bytes_sent[pass < 3 ? pass : 3] += (long long)total;
        d->bytes_total += (long long)total;
    }
    free(length);
    free(counts);
    free(displs);
    return ok;
}
#endif

bool dist_gather(ReconDist *d, const DistArray *arrays, int count, int pass, Diag *e)
{
    if (!d || d->ranks <= 1) return true;
#ifdef WEDGE_MPI
    return exchange(d, false, arrays, count, pass, e);
#else
    (void)arrays, (void)count, (void)pass, (void)e;
    return true;
#endif
}

bool dist_handover(ReconDist *d, const DistArray *arrays, int count, int pass, Diag *e)
{
    if (!d || d->ranks <= 1) return true;
#ifdef WEDGE_MPI
    return exchange(d, true, arrays, count, pass, e);
#else
    (void)arrays, (void)count, (void)pass, (void)e;
    return true;
#endif
}

bool dist_broadcast_ints(ReconDist *d, int *data, size_t n, Diag *e)
{
    if (!d || d->ranks <= 1) return true;
#ifdef WEDGE_MPI
    if (!quiet_arrival(e)) return false;
    for (size_t at = 0; at < n;) { /* in chunks an int count can say */
        size_t chunk = n - at < (size_t)INT_MAX / 4 ? n - at : (size_t)INT_MAX / 4;
        if (!mpi_ok(mpi->bcast(data + at, (int)chunk, mpi->type_int, 0, mpi->comm_world), "broadcast", e)) return false;
        if (d->rank == 0) {
            d->bytes_sent[1] += (long long)(chunk * sizeof(int)) * (d->ranks - 1);
            d->bytes_total += (long long)(chunk * sizeof(int)) * (d->ranks - 1);
        }
        at += chunk;
    }
    return true;
#else
    (void)data, (void)n, (void)e;
    return true;
#endif
}

long long dist_sum_ll(const ReconDist *d, long long v)
{
#ifdef WEDGE_MPI
    if (d && d->ranks > 1) {
        long long sum = 0;
        if (quiet_arrival(NULL) &&
            mpi->allreduce(&v, &sum, 1, mpi->type_long_long, mpi->op_sum, mpi->comm_world) == MPI_SUCCESS)
            return sum;
    }
#else
    (void)d;
#endif
    return v;
}

int dist_max_int(const ReconDist *d, int v)
{
#ifdef WEDGE_MPI
    if (d && d->ranks > 1) {
        int max = v;
        if (quiet_arrival(NULL) &&
            mpi->allreduce(&v, &max, 1, mpi->type_int, mpi->op_max, mpi->comm_world) == MPI_SUCCESS)
            return max;
        return v != 0 ? v : WEDGE_EXIT_RUNTIME;
    }
#else
    (void)d;
#endif
    return v;
}

bool dist_all_ok(const ReconDist *d, bool ok)
{
#ifdef WEDGE_MPI
    if (d && d->ranks > 1) {
        int mine = ok ? 1 : 0, all = 0;
        if (!quiet_arrival(NULL) ||
            mpi->allreduce(&mine, &all, 1, mpi->type_int, mpi->op_min, mpi->comm_world) != MPI_SUCCESS)
            return false;
        return all == 1;
    }
#else
    (void)d;
#endif
    return ok;
}
