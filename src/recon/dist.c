/* Several ranks, one frame (see dist.h). */
#include "recon/dist.h"

#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifdef WEDGE_MPI
#include <mpi.h>
#endif

enum { DIST_TILE_PX = 8 };

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

void dist_init(int *argc, char ***argv, ReconDist *d)
{
    memset(d, 0, sizeof *d);
    d->rank = 0;
    d->ranks = 1;
#ifdef WEDGE_MPI
    if (!launched_by_mpirun()) return;
    int inited = 0;
    MPI_Initialized(&inited);
    if (!inited && MPI_Init(argc, argv) != MPI_SUCCESS) return;
    /* errors come back as codes (reported with a message, exit 3), not an abort */
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &d->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &d->ranks);
#else
    (void)argc, (void)argv;
#endif
}

void dist_finish(ReconDist *d)
{
#ifdef WEDGE_MPI
    int inited = 0, done = 0;
    MPI_Initialized(&inited);
    MPI_Finalized(&done);
    if (inited && !done) MPI_Finalize();
#endif
    (void)d;
}

int dist_owner(const ReconDist *d, int width, int px, int py)
{
    if (!d || d->ranks <= 1) return 0;
    int tiles_x = (width + DIST_TILE_PX - 1) / DIST_TILE_PX;
    long tile = (long)(py / DIST_TILE_PX) * tiles_x + px / DIST_TILE_PX;
    return (int)(tile % d->ranks);
}

#ifdef WEDGE_MPI
static bool mpi_ok(int rc, const char *what, Diag *e)
{
    if (rc == MPI_SUCCESS) return true;
    char msg[MPI_MAX_ERROR_STRING] = "";
    int len = 0;
    MPI_Error_string(rc, msg, &len);
    diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "MPI %s failed: %s (another rank may have died)", what, msg);
    return false;
}

/* Copies the bytes of the pixels rank r owns, in row-major order, out of (to_buf) or into
 * (!to_buf) one array. */
static size_t pack_owned(const ReconDist *d, int width, int height, int r, const DistArray *a, unsigned char *buf,
                         bool to_buf)
{
    size_t at = 0, bpp = a->bytes_per_pixel;
    unsigned char *data = a->data;
    for (int y = 0; y < height; ++y)
        for (int x0 = 0; x0 < width; x0 += DIST_TILE_PX) {
            if (dist_owner(d, width, x0, y) != r) continue;
            int x1 = x0 + DIST_TILE_PX < width ? x0 + DIST_TILE_PX : width;
            size_t bytes = (size_t)(x1 - x0) * bpp, off = ((size_t)y * (size_t)width + (size_t)x0) * bpp;
            if (buf) {
                if (to_buf) memcpy(buf + at, data + off, bytes);
                else memcpy(data + off, buf + at, bytes);
            }
            at += bytes;
        }
    return at;
}
#endif

bool dist_gather(ReconDist *d, int width, int height, const DistArray *arrays, int count, int pass, Diag *e)
{
    if (!d || d->ranks <= 1) return true;
#ifdef WEDGE_MPI
    int *counts = calloc((size_t)d->ranks, sizeof(int)), *displs = calloc((size_t)d->ranks, sizeof(int));
    unsigned char *send = NULL, *recv = NULL;
    bool ok = counts && displs;
    for (int k = 0; ok && k < count; ++k) {
        const DistArray *a = &arrays[k];
        size_t total = 0;
        for (int r = 0; r < d->ranks; ++r) {
            size_t bytes = pack_owned(d, width, height, r, a, NULL, true);
            if (bytes > INT_MAX || total > INT_MAX - bytes) {
                diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                         "a %dx%d frame is too large to gather in one MPI message per array (over 2 GiB)", width, height);
                ok = false;
                break;
            }
            counts[r] = (int)bytes;
            displs[r] = (int)total;
            total += bytes;
        }
        if (!ok) break;
        size_t mine = (size_t)counts[d->rank];
        free(send);
        send = malloc(mine ? mine : 1);
        if (d->rank == 0) {
            free(recv);
            recv = malloc(total ? total : 1);
        }
        if (!send || (d->rank == 0 && !recv)) {
            diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the MPI gather");
            ok = false;
            break;
        }
        pack_owned(d, width, height, d->rank, a, send, true);
        ok = mpi_ok(MPI_Gatherv(send, counts[d->rank], MPI_BYTE, recv, counts, displs, MPI_BYTE, 0, MPI_COMM_WORLD),
                    "gather", e);
        if (ok && d->rank == 0)
            for (int r = 1; r < d->ranks; ++r) pack_owned(d, width, height, r, a, recv + displs[r], false);
        if (d->rank == 0) { /* what crossed between ranks: everything but rank 0's own part */
            d->bytes_sent[pass < 3 ? pass : 3] += (long long)(total - mine);
            d->bytes_total += (long long)(total - mine);
        }
    }
    free(send);
    free(recv);
    free(counts);
    free(displs);
    return ok;
#else
    (void)width, (void)height, (void)arrays, (void)count, (void)pass, (void)e;
    return true;
#endif
}

bool dist_broadcast_ints(ReconDist *d, int *data, size_t n, Diag *e)
{
    if (!d || d->ranks <= 1) return true;
#ifdef WEDGE_MPI
    for (size_t at = 0; at < n;) { /* in chunks an int count can say */
        size_t chunk = n - at < (size_t)INT_MAX / 4 ? n - at : (size_t)INT_MAX / 4;
        if (!mpi_ok(MPI_Bcast(data + at, (int)chunk, MPI_INT, 0, MPI_COMM_WORLD), "broadcast", e)) return false;
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
        if (MPI_Allreduce(&v, &sum, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD) == MPI_SUCCESS) return sum;
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
        if (MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD) != MPI_SUCCESS) return false;
        return all == 1;
    }
#else
    (void)d;
#endif
    return ok;
}
