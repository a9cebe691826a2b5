/* PoCL, the CPU OpenCL driver, keeps compiled kernels in $POCL_CACHE_DIR, else
 * $XDG_CACHE_HOME/pocl or $HOME/.cache/pocl, and reports no device at all when it cannot
 * create that directory (an unwritable or missing $HOME): the error then said "install an
 * OpenCL driver", which was wrong. Before the first OpenCL call, kernel_cache_prepare checks
 * the place and, when it is not writable and $POCL_CACHE_DIR is not set, points
 * $POCL_CACHE_DIR at a temporary directory (removed at exit), saying so on stderr. Other
 * drivers ignore the variable. */
#ifndef WEDGE_RECON_CL_KERNEL_CACHE_H
#define WEDGE_RECON_CL_KERNEL_CACHE_H

/* Idempotent and thread-safe. */
void kernel_cache_prepare(void);

#endif
