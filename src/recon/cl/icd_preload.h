/* The OpenCL drivers loaded ahead of the ICD loader, each bound to its own libraries first.
 *
 * The ICD loader (libOpenCL) dlopens each driver named in /etc/OpenCL/vendors (one .icd file each) at the
 * first clGetPlatformIDs. PoCL's driver pulls in LLVM and clang, whose ~35k symbol
 * relocations glibc resolves by searching the global scope first: wedge and the ~70
 * libraries it links (MPI, OpenColorIO, Embree, SDL2, ...), a failed hash lookup each,
 * before reaching LLVM's own tables. Opened first with RTLD_DEEPBIND, a driver and the
 * libraries it brings search their own scope first; the ICD loader's later dlopen of the
 * same file finds it loaded. Which definitions bind changes only where the driver's
 * libraries and wedge's define the same symbol, and then the driver's own is the one it
 * was built against. */
#ifndef WEDGE_RECON_CL_ICD_PRELOAD_H
#define WEDGE_RECON_CL_ICD_PRELOAD_H

#include <stdbool.h>

/* ocl-icd's and the Khronos loader's default vendor directory on Linux */
#define CL_ICD_VENDOR_DIR "/etc/OpenCL/vendors"

/* Opens the drivers of the system's vendor directory once per process (later calls return
 * at once). Does nothing where the ICD loader is pointed elsewhere (OCL_ICD_VENDORS,
 * OCL_ICD_FILENAMES, OPENCL_VENDOR_PATH), where LD_PRELOAD interposes a library (the
 * driver would bind past it to its own copies), in builds with AddressSanitizer or
 * ThreadSanitizer (their interceptors refuse RTLD_DEEPBIND), or with WEDGE_CL_PRELOAD=0.
 * A driver that fails to open is left to the ICD loader, which reports as before. */
void cl_icd_preload(void);

/* How many drivers the first call opened (0 before it or where it did nothing). With
 * $WEDGE_CL_LOG=1 each one opened is also named on stderr. */
int cl_icd_preloaded(void);

/* An .icd file's first line as the library name the ICD loader opens: trimmed of white space
 * (the newline) in place; false when nothing is left. */
bool cl_icd_library_name(char *line);

/* False in the builds whose sanitizers refuse RTLD_DEEPBIND (then cl_icd_preload is a no-op). */
bool cl_icd_preload_built_in(void);

#endif
