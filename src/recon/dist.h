/* One frame rendered by several processes (MPI ranks, DESIGN.md section 8), each pixel's
 * samples taken by exactly one rank.
 *
 * Ownership: interleaved 8x8 tiles, tile t (row-major) belongs to rank t mod ranks, for
 * every pass; neighbouring tiles cost alike, so the interleave balances the ranks to within
 * a tile's cost (8x8 rather than 16x16 tiles: defocus bench scene, 2 ranks, 1.45x -> 1.71x,
 * where the costly out-of-focus pixels come in patches). A rank traces only the pixels it owns (the others get 0 samples) and feeds
 * their samples to its own sinks; after each pass every per-pixel quantity (the frame's sums,
 * the shared guides, each method's statistics, the per-sample store) is gathered to rank 0,
 * which plans the next pass, broadcasts the plan, and reconstructs. Because a pixel's sums are
 * made by one rank in the same order as by a single process (same seeds, same rounds), the
 * image is the single-process image value for value.
 *
 * Why gather to rank 0 rather than exchange halos: the plan and every filter read the whole
 * image (the light estimate of AAF-shadow, the scene size, filter footprints up to 32 px), the
 * state is a few dozen bytes per pixel (about 150 B per pixel per pass for AAF), and one
 * gather per pass is one message per rank; docs/benchmarks.md has the measured bytes and
 * times and a model of where it stops scaling.
 *
 * Without MPI (or a single rank) every call is a no-op on a "world" of one. */
#ifndef WEDGE_RECON_DIST_H
#define WEDGE_RECON_DIST_H

#include <stdbool.h>
#include <stddef.h>

#include "core/diag.h"

typedef struct {
    int rank, ranks;
    long long bytes_sent[4];    /* rank 0: bytes that crossed between ranks per pass (gathered
                                 * from the others, the plan broadcast to them); index 3 holds
                                 * any later pass */
    long long bytes_total;
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

/* The rank that owns pixel (px, py) of a width-wide image. */
int dist_owner(const ReconDist *d, int width, int px, int py);

/* Gathers the owners' values of every array to rank 0 (each rank sends the pixels it owns,
 * rank 0 writes them into its arrays). pass selects the byte counter. False with e set on a
 * communication failure (exit 3). */
bool dist_gather(ReconDist *d, int width, int height, const DistArray *arrays, int count, int pass, Diag *e);

/* Rank 0's n ints to every rank. */
bool dist_broadcast_ints(ReconDist *d, int *data, size_t n, Diag *e);

/* The sum over ranks of v (every rank gets it). */
long long dist_sum_ll(const ReconDist *d, long long v);
/* Whether every rank says ok (a collective: a failing rank's error stops all, none hangs in
 * a later collective). */
bool dist_all_ok(const ReconDist *d, bool ok);

#endif
