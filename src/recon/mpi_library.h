/* The MPI library opened at run time, for dist.c: the functions one frame on several ranks
 * calls and the predefined handles it passes, through one table.
 *
 * wedge is built against MPI's header (CMake finds it) but does not link the library: linked,
 * Open MPI and what it brings (open-rte, open-pal, hwloc, libevent, ...) were mapped and
 * initialised by every wedge process, launched by mpirun or not. dist_init loads it only when
 * mpirun started the process, with RTLD_GLOBAL: Open MPI's own components (mca_*.so), which it
 * dlopens in MPI_Init, may bind to libmpi's and open-pal's symbols through the global scope.
 *
 * Constants that are plain numbers in the header (MPI_SUCCESS, MPI_IN_PLACE,
 * MPI_STATUS_IGNORE, MPI_COMM_TYPE_SHARED, MPI_MAX_ERROR_STRING) are used as they are. Handles
 * that Open MPI defines as addresses of objects in libmpi (MPI_COMM_WORLD, MPI_BYTE, MPI_SUM,
 * ...) come from the table: written directly in dist.c they would reference libmpi at link
 * time, and the link of wedge fails (which keeps them out). */
#ifndef WEDGE_RECON_MPI_LIBRARY_H
#define WEDGE_RECON_MPI_LIBRARY_H

#ifdef WEDGE_MPI
#include <mpi.h>

#include "core/diag.h"

/* The MPI functions dist.c calls: (field, MPI name). */
#define DIST_MPI_FUNCTIONS(X) \
    X(init, MPI_Init) \
    X(initialized, MPI_Initialized) \
    X(finalize, MPI_Finalize) \
    X(finalized, MPI_Finalized) \
    X(error_string, MPI_Error_string) \
    X(comm_set_errhandler, MPI_Comm_set_errhandler) \
    X(comm_rank, MPI_Comm_rank) \
    X(comm_size, MPI_Comm_size) \
    X(comm_split_type, MPI_Comm_split_type) \
    X(comm_free, MPI_Comm_free) \
    X(allgather, MPI_Allgather) \
    X(allreduce, MPI_Allreduce) \
    X(ibarrier, MPI_Ibarrier) \
    X(test, MPI_Test) \
    X(gatherv, MPI_Gatherv) \
    X(scatterv, MPI_Scatterv) \
    X(bcast, MPI_Bcast)

/* Each function a pointer of its own type (from the header's prototype), so that a call
 * through the table is checked as a direct call would be. */
#define DIST_MPI_FIELD(field, name) __typeof__(name) *field;
typedef struct {
    DIST_MPI_FUNCTIONS(DIST_MPI_FIELD)
    /* the predefined handles dist.c passes */
    MPI_Comm comm_world;
    MPI_Datatype type_byte, type_int, type_double, type_long_long;
    MPI_Op op_sum, op_min, op_max;
    MPI_Info info_null;
    MPI_Errhandler errors_return;
} MpiLibrary;
#undef DIST_MPI_FIELD

/* Opens the MPI library once per process (later calls return the first call's outcome): the
 * soname the build found, then the same name in the directory the build found it in (Open
 * MPI's private lib folder on some systems). NULL with e set (exit 3) when it cannot be
 * opened or lacks a function or handle, the message saying what to install.
 * $WEDGE_MPI_LIBRARY names the one file to open instead (tests). */
const MpiLibrary *mpi_library_load(Diag *e);

#endif
#endif
