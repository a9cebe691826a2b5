/* Where a program keeps files between runs, after the XDG base-directory spec:
 * $XDG_CACHE_HOME/NAME when that is an absolute path (relative values are ignored), else
 * $HOME/.cache/NAME. */
#ifndef WEDGE_CORE_CACHE_HOME_H
#define WEDGE_CORE_CACHE_HOME_H

#include <stdbool.h>
#include <stddef.h>

/* false when neither variable gives a place, or the path does not fit in out. */
bool cache_home(const char *name, char *out, size_t out_size);

/* Creates a folder and its parents (like mkdir -p); true when it exists afterwards. */
bool make_dirs(const char *path);

#endif
