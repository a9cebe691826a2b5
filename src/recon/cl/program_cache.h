/* Compiled OpenCL programs kept between runs. Building the kernels from source costs PoCL
 * about 65 ms per process even when its own cache holds the machine code (it preprocesses
 * the sources with clang to find it); a program created from the binary the driver handed
 * out last time builds in 3-7 ms. The binary is kept in the wedge cache folder
 * (core/cache_home.h) as cl-KEY.bin, KEY a hash of the sources, the build options and the
 * device's and driver's names and versions, written atomically (temporary file, then
 * rename). A file that is missing, damaged or refused by the driver is simply not used: the
 * caller builds from source and stores the result. $WEDGE_CL_PROGRAM_CACHE=0 turns it off. */
#ifndef WEDGE_RECON_CL_PROGRAM_CACHE_H
#define WEDGE_RECON_CL_PROGRAM_CACHE_H

#include "recon/cl/cl_runtime_internal.h"

/* The program built from the cached binary for these sources and options on rt's device,
 * or NULL (nothing cached, unusable, or the cache is off). */
cl_program program_cache_load(const ClRuntime *rt, const char *const *sources, int count, const char *options);

/* Keeps a built program's binary for the next run; failures are silent (a cache). */
void program_cache_store(const ClRuntime *rt, cl_program program, const char *const *sources, int count,
                         const char *options);

#endif
