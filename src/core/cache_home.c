/* The cache folder of the XDG base-directory spec (see cache_home.h). */
#include "core/cache_home.h"

#include <stdio.h>
#include <stdlib.h>

bool cache_home(const char *name, char *out, size_t out_size)
{
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    int n;
    if (xdg && xdg[0] == '/') n = snprintf(out, out_size, "%s/%s", xdg, name);
    else if (home && home[0]) n = snprintf(out, out_size, "%s/.cache/%s", home, name);
    else return false;
    return n >= 0 && (size_t)n < out_size;
}
