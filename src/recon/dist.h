/* One frame rendered by several processes (MPI ranks, DESIGN.md section 8), each pixel's
 * samples in a pass taken by exactly one rank, its owner in that pass.
 *
 * Ownership, per pass, in 8x8 tiles. Pass 1 (the same count everywhere): the interleave,
 * tile t (row-major) to rank t mod ranks (neighbouring tiles cost alike, so it balances the
 * work to within a few tiles' cost, though not the ranks' speeds; 8x8 rather than 16x16
 * tiles: defocus bench scene, 2 ranks, 1.45x -> 1.71x, where the costly out-of-focus pixels
 * come in patches); with WEDGE_DIST_PASS1=claims, bands of tile rows claimed on demand
 * (dist_claims_begin), so that a rank slowed by anything (rank 0's OpenCL device opening,
 * another job on its core) takes fewer: not the default, since on a quiet node it cost
 * defocus and combined more than it gave soft_shadows (docs/benchmarks.md, "Pass 1 claimed
 * on demand"). Every later pass (the
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
    int *band_start;            /* pass 1 claimed on demand: the bands' first positions in */
    int *row_order;             /* ... the order the tile rows are claimed in */
    int band_count;
    bool claiming;              /* between dist_claims_begin and dist_claims_end */
    void *claim_window;         /* the bands' counter's MPI window (an MPI_Win *), made by dist_init */
    long long claims_base;      /* the counter's value where this frame's bands begin */
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

/* Starts MPI when the process was launched by mpirun (and wedge was built with it); fills d
 * with this rank and the world size (a world of one otherwise). Call once, first thing. */
void dist_init(int *argc, char ***argv, ReconDist *d);
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

/* Pass 1 claimed on demand (docs/benchmarks.md, "Pass 1 claimed on demand"). The frame's
 * rows of tiles are cut into bands, large first and shrinking to one row of tiles (the same
 * cut on every rank: dist_claim_bands), and each rank, while it traces, takes the next band
 * from a counter on rank 0 (an MPI atomic fetch-and-add on a one-int window), so that a rank
 * slowed by anything (rank 0's OpenCL device opening, another job on its core, dearer
 * pixels) traces fewer bands and every rank ends pass 1 within about one band of the
 * others. Who traced a pixel changes nothing in it (each pixel's samples come from (seed,
 * pixel, pass) and are summed by one rank in one order), so images stay value for value.
 * dist_claims_begin (a collective) starts the count with every tile unowned; dist_claim
 * gives the next band's positions [row0, row1) in the claim order (dist_claim_row: rows spread
 * over the frame) and makes their tiles this rank's; dist_claims_end (a collective) tells every
 * rank every tile's owner (owner and owner_before), as after dist_tiles_reset's interleave.
 * Without MPI or with one rank every tile row is one band of rank 0.
 * Only under WEDGE_DIST_PASS1=claims (otherwise dist_claims_begin returns 0 and pass 1 keeps
 * the interleave). Failures set e (exit 3). */
/* Whether pass 1 is claimed: WEDGE_DIST_PASS1=claims, several ranks, and at least
 * DIST_CLAIM_ROWS_PER_RANK rows of tiles per rank in the frame (dist_tiles_reset). */
enum { DIST_CLAIM_ROWS_PER_RANK = 8 };
bool dist_claims_wanted(const ReconDist *d);
int dist_claims_begin(ReconDist *d, Diag *e); /* 1: claiming; 0: the interleave; -1: failed */
int dist_claim(ReconDist *d, int *row0, int *row1, Diag *e); /* 1: a band; 0: none left; -1: failed */
/* The tile row at position k of the claim order: a band [row0, row1) holds the rows
 * dist_claim_row(d, row0) .. dist_claim_row(d, row1 - 1), spread over the frame. */
int dist_claim_row(const ReconDist *d, int k);
/* The claim order of rows tile rows (order[k]: the row at position k): bit-reversed, so that
 * the first m positions leave no gap wider than 2 rows / m. */
void dist_claim_order(int rows, int *order);
bool dist_claims_end(ReconDist *d, Diag *e);
/* The cut of rows tile rows into bands for ranks claimers: the first row of band k in
 * start[k] (start[count] = rows); each band holds about 1 / (DIST_CLAIM_SHARE * ranks) of the rows not yet cut, at
 * least one. Returns the count (at most rows). */
enum { DIST_CLAIM_SHARE = 3 };
int dist_claim_bands(int rows, int ranks, int *start);

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
