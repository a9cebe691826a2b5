/* The MPI library opened at run time (see mpi_library.h); empty in a build without MPI. */
#ifdef WEDGE_MPI
#include "recon/mpi_library.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

#ifndef WEDGE_MPI_SONAME
#define WEDGE_MPI_SONAME "libmpi.so.40" /* Open MPI 3.0 to 5 */
#endif

/* The library the one load opened (NULL before it), and why a load failed. */
static void *mpi_handle;
static const char *mpi_missing; /* the first function or object not found */

/* An object of the library (a predefined handle's target); NULL, and noted, when absent. */
static void *library_object(const char *name)
{
    void *p = dlsym(mpi_handle, name);
    if (!p && !mpi_missing) mpi_missing = name;
    return p;
}

#ifdef OMPI_PREDEFINED_GLOBAL
/* Open MPI's header spells each predefined handle (MPI_COMM_WORLD, MPI_BYTE, MPI_SUM, ...) as
 * OMPI_PREDEFINED_GLOBAL(type, object): the address of an object in libmpi. Redefined here,
 * the same spelling looks that object up in the library opened at run time, so the objects'
 * names are the header's own, not a list typed here. (An MPI whose handles are plain numbers,
 * MPICH's, needs nothing: its macros are used as they are.) */
#undef OMPI_PREDEFINED_GLOBAL
#define OMPI_PREDEFINED_GLOBAL(type, object) ((type)library_object(#object))
#endif

static MpiLibrary mpi;
static bool mpi_loaded;
static char mpi_load_error[512];

static void mpi_load_once(void)
{
    /* RTLD_GLOBAL: the components Open MPI dlopens in MPI_Init may bind to its libraries'
     * symbols through the global scope (Open MPI's advice for a dlopened libmpi; Debian's
     * components are linked against libmpi and also ran with RTLD_LOCAL here, which is not
     * true of every build) */
    const int flags = RTLD_NOW | RTLD_GLOBAL;
    const char *name = getenv("WEDGE_MPI_LIBRARY");
    if (name && *name) mpi_handle = dlopen(name, flags);
    else {
        name = WEDGE_MPI_SONAME;
        mpi_handle = dlopen(name, flags);
#ifdef WEDGE_MPI_LIBDIR
        if (!mpi_handle) {
            const char *first = dlerror();
            snprintf(mpi_load_error, sizeof mpi_load_error, "%s", first ? first : name);
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", WEDGE_MPI_LIBDIR, WEDGE_MPI_SONAME);
            mpi_handle = dlopen(path, flags);
            if (!mpi_handle) return; /* the soname's error is the one to show */
        }
#endif
    }
    if (!mpi_handle) {
        const char *why = dlerror();
        snprintf(mpi_load_error, sizeof mpi_load_error, "%s", why ? why : name);
        return;
    }
#define DIST_MPI_LOAD(field, fn) mpi.field = (__typeof__(fn) *)library_object(#fn);
    DIST_MPI_FUNCTIONS(DIST_MPI_LOAD)
#undef DIST_MPI_LOAD
    mpi.comm_world = MPI_COMM_WORLD;
    mpi.type_byte = MPI_BYTE;
    mpi.type_int = MPI_INT;
    mpi.type_double = MPI_DOUBLE;
    mpi.type_long_long = MPI_LONG_LONG;
    mpi.op_sum = MPI_SUM;
    mpi.op_min = MPI_MIN;
    mpi.op_max = MPI_MAX;
    mpi.info_null = MPI_INFO_NULL;
    mpi.errors_return = MPI_ERRORS_RETURN;
    if (mpi_missing) {
        snprintf(mpi_load_error, sizeof mpi_load_error, "%s has no %s (not the MPI wedge was built with?)", name,
                 mpi_missing);
        return;
    }
    mpi_loaded = true;
}

const MpiLibrary *mpi_library_load(Diag *e)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, mpi_load_once);
    if (mpi_loaded) return &mpi;
    diag_set(e, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
             "started by mpirun, but the MPI library cannot be loaded (%s): install the one wedge was built with "
             "(Open MPI, Debian and Ubuntu: apt-get install libopenmpi3; tools/setup installs openmpi-bin), or run "
             "wedge without mpirun",
             mpi_load_error);
    return NULL;
}
#else
typedef int wedge_mpi_library_needs_mpi;
#endif
