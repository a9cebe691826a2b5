/* One frame rendered by several processes (MPI ranks, DESIGN.md section 8), each pixel's
 * samples in a pass taken by exactly one rank, its owner in that pass.
 *
 * Ownership, per pass, in 8x8 tiles. Pass 1 (the same count everywhere): the interleave,
 * tile t (row-major) to rank t mod ranks; neighbouring tiles cost alike, so it balances to
 * within a few tiles' cost (8x8 rather than 16x16 tiles: defocus bench scene, 2 ranks, 1.45x
 * -> 1.71x, where the costly out-of-focus pixels come in patches). Every later pass (the
 * adaptive pass 2, progressive steps) is balanced by its predicted cost: once the plan is
 * broadcast every rank knows each pixel's count; a tile's cost is its planned samples times
 * the time per sample measured in that tile so far, relative to its tracer's mean (each rank
 * times the samples it traces; the tiles' totals are all-reduced after each pass, 8 bytes
 * per tile), and
 * dist_balance assigns the tiles so that each rank's sum is within one tile of the ideal,
 * keeping tiles with their previous owner where that does not unbalance and moving the
 * dearest ones where it must (fewest tiles to hand over; deterministic: every rank computes
 * the same owners from the same numbers). A rank traces only the pixels it owns
 * (the others get 0 samples) and feeds their samples to its own sinks; after each pass every
 * per-pixel quantity (the frame's sums, the shared guides, each method's statistics, the
 * per-sample store) is gathered to rank 0, which plans the next pass, broadcasts the plan,
 * and reconstructs. Before a pass traces, rank 0 (which holds every pixel's state after the
 * gather) hands the state of each tile that changed owner to its new owner, so that a pixel's
 * sums continue from exactly the single-process values: made in the same order (same seeds,
 * same rounds), the image is the single-process image value for value.
 *
 * Why gather to rank 0 rather than exchange halos: the plan and every filter read the whole
 * image (the light estimate of AAF-shadow, the scene size, filter footprints up to 32 px), the
 * state is a few dozen bytes per pixel (about 150 B per pixel per pass for AAF), and one
 * gather per pass is one stream per rank; docs/benchmarks.md has the measured bytes and
 * times and a model of where it stops scaling. Why a hand-over of the moved tiles rather than
 * gathering to every rank: only the tiles that move cross (a few in ten when the owner is
 * kept where it can be), not the whole frame to every rank.
 *
 * Each exchange streams a rank's tiles in rounds of at most 4 MiB through one small buffer
 * (no frame-sized buffer to fault in on either side), and a rank that reaches a collective
 * before the others naps until they arrive instead of spinning in MPI's poll, so that rank 0's
 * plan and reconstruction, which use both cores of a node, get them (docs/benchmarks.md,
 * "Two ranks without spinning").
 *
 * Without MPI (or a single rank) every call is a no-op on a "world" of one. */
#ifndef WEDGE_RECON_DIST_H
#define WEDGE_RECON_DIST_H

#include <stdbool.h>
#include <stddef.h>

#include "core/diag.h"

/* Room for a core mask: 1024 cores, the C library's cpu_set_t. */
enum { DIST_CPU_BYTES = 128 };

typedef struct {
    int rank, ranks;
    long long bytes_sent[4];    /* rank 0: bytes that crossed between ranks per pass (gathered
                                 * from the others, the plan broadcast to them); index 3 holds
                                 * any later pass */
    long long bytes_total;
    /* ownership of the pass being traced (dist_tiles_reset, dist_reassign) */
    int width, height, tiles_x, tile_count;
    int *owner;                 /* owner[t] of tile t; NULL: the interleave */
    int *owner_before;          /* the previous pass's owners */
    double *tile_seconds;       /* tracing time measured in each tile so far (every rank), in
                                 * its tracer's mean seconds per sample (dist_measure) */
    double *tile_samples;       /* ... and the samples they took */
    long long tiles_moved;      /* tiles that changed owner between passes, over the frame */
    unsigned char *xbuf;        /* the exchanges' message buffer (a round's chunk per rank on
                                 * rank 0, one elsewhere), kept between exchanges */
    size_t xbuf_bytes;
    /* the cores this rank may run on as launched (mpirun binds each rank to a core by default)
     * and those of every rank on its node, as the bytes of a cpu_set_t; set by
     * dist_init on Linux, cpus_known false otherwise */
    unsigned char own_cpus[DIST_CPU_BYTES], node_cpus[DIST_CPU_BYTES];
    bool cpus_known;
} ReconDist;

/* A per-pixel array to gather: element p of pixel i is at data + i * bytes_per_pixel. */
typedef struct {
    void *data;
    size_t bytes_per_pixel;
} DistArray;

/* Starts MPI when the process was launched by mpirun (and wedge was built with it), loading
 * the MPI library first (only then: recon/mpi_library.h); fills d with this rank and the world
 * size (a world of one otherwise). False with e set (exit 3) when mpirun started the process
 * but the library cannot be loaded (d is then a world of one, and dist_finish may be called).
 * Call once, first thing. */
bool dist_init(int *argc, char ***argv, ReconDist *d, Diag *e);
/* Ends MPI (after the last collective call). exit_code: this rank's result. */
void dist_finish(ReconDist *d);
/* Whether MPI support was built in. */
bool dist_available(void);

/* The node's cores (docs/rendering.md, "Several machines"). mpirun binds each rank to its own
 * core(s) (Open MPI: to a core for up to two ranks, to a socket beyond), and a thread a rank
 * starts inherits its starter's binding: rank 0's OpenCL driver threads and its plan's and
 * reconstruction's helper threads would all run on rank 0's core while the other ranks on
 * the node wait for it, their cores idle. on: the calling thread may run on every core bound
 * to a rank of its node (the union of their masks, gathered by dist_init); off: back to its
 * own rank's cores. Rank 0 turns it on outside its tracing (and for the threads the driver
 * starts) and off for tracing, so that its render threads keep to its core while the others
 * trace. No-op when the masks are not known (no MPI, not Linux) or equal (not bound). */
void dist_node_cpus(const ReconDist *d, bool on);
/* The cores this rank was bound to at start (0: not known, e.g. without MPI): the default
 * count of render threads under mpirun, rather than every core of the node, which ranks
 * bound to a core each would crowd onto that core. */
int dist_own_cores(const ReconDist *d);
/* The calling process's thread ids (up to max, from /proc/self/task); their count, 0 when
 * unknown. For dist_log_new_threads. */
int dist_thread_ids(int *tid, int max);
/* WEDGE_DIST_LOG (tests/app/mpi_render.sh): prints "dist-cpus rank R: own LIST node LIST
 * WHAT LIST LIST ...", the cores this rank was bound to, its node's, and those each thread
 * that is not among before[0..before_count) may use (the threads started since the
 * snapshot, e.g. the OpenCL driver's). */
void dist_log_new_threads(const ReconDist *d, const int *before, int before_count, const char *what);

/* The side of an ownership tile, in pixels. */
enum { DIST_TILE_PX = 8 };

/* Starts a width x height frame's ownership at the interleave of pass 1: tile t (row-major)
 * to rank t mod ranks. False when out of memory (e set). */
bool dist_tiles_reset(ReconDist *d, int width, int height, Diag *e);
/* The rank that owns pixel (px, py) in the pass being traced. */
int dist_owner(const ReconDist *d, int px, int py);

/* Assigns tile_count tiles of cost tile_cost[t] to ranks (owner[t]), each rank's sum of
 * costs within the largest tile cost of total/ranks. First every rank keeps the tiles it had
 * (before[t]; NULL: none), cheapest first, while its sum stays within total/ranks; then the
 * others, dearest first, go each to the rank with the least sum so far (ties: the previous
 * owner, then the lower rank). The bound holds because a rank passes total/ranks only by a
 * tile taken while it had the least sum, then at most total/ranks. Deterministic; no
 * communication. */
void dist_balance(const double *tile_cost, const int *before, int tile_count, int ranks, int *owner);

/* After a pass: adds the tracing seconds each rank measured in the pixels it owned
 * (pixel_seconds, which it zeroes; the others' pixels are ignored), in units of that rank's
 * mean seconds per sample in the pass (so that a slower rank's tiles do not look dear), to
 * every tile's total on every rank, and the pass's samples (spp per pixel, NULL:
 * spp_uniform everywhere) to the tiles' sample counts. A collective (one all-reduce of a
 * double per tile). False with e set on a communication failure. */
bool dist_measure(ReconDist *d, float *pixel_seconds, const int *spp, int spp_uniform, Diag *e);

/* The next pass's ownership, balanced by its predicted cost (spp[i] samples at pixel i, the
 * same on every rank, each at its tile's measured seconds per sample; the frame's mean rate
 * for a tile not measured yet): the previous owners become owner_before. False when out of
 * memory (e set). */
bool dist_reassign(ReconDist *d, const int *spp, Diag *e);

/* Before a pass traces: rank 0 sends each rank the arrays' values of the pixels of tiles it
 * owns now and did not own in the previous pass (rank 0 holds every pixel after a gather).
 * pass selects the byte counter. False with e set on a communication failure (exit 3). */
bool dist_handover(ReconDist *d, const DistArray *arrays, int count, int pass, Diag *e);

/* Gathers the owners' values of every array to rank 0 (each rank sends the pixels it owns in
 * this pass, all arrays in one stream sent in rounds of at most 4 MiB; rank 0 writes them
 * into its arrays). pass selects the byte counter. False with e set on a communication failure (exit 3). */
bool dist_gather(ReconDist *d, const DistArray *arrays, int count, int pass, Diag *e);

/* Rank 0's n ints to every rank. */
bool dist_broadcast_ints(ReconDist *d, int *data, size_t n, Diag *e);

/* The sum over ranks of v (every rank gets it). */
long long dist_sum_ll(const ReconDist *d, long long v);
/* The largest v over ranks (every rank gets it): e.g. an exit code, so that a step only rank 0
 * does (the OpenCL device check) fails every rank with its code. */
int dist_max_int(const ReconDist *d, int v);
/* Whether every rank says ok (a collective: a failing rank's error stops all, none hangs in
 * a later collective). */
bool dist_all_ok(const ReconDist *d, bool ok);

#endif
